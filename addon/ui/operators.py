# SPDX-License-Identifier: GPL-3.0-or-later
"""Every operator of the extension: the node-group library, Phong materials, demo scenes,
the comparison bake and the MTL export.  The work itself is done by the feature packages; an operator
checks its input, calls them and reports."""

from __future__ import annotations

import os
import tempfile

import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ...core import compare, outputs, scenes
from ...core.wording import name_list
from ...node_groups.library import GROUPS
from .. import loader
from ..comparison import engine
from ..demos import builder
from ..scene import describe, framing
from ..lighting import convert, engine_outputs, loop, recipe, rig, shadows
from ..lighting import sync as sync_mod
from . import file_io


class PHONG_OT_load_node_groups(bpy.types.Operator):
    """Put every Phong node group into this file (creates, or upgrades in place)"""

    bl_idname = "phong.load_node_groups"
    bl_label = "Load Phong Node Groups"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        summary = loader.load_all()
        parts = [f"{len(names)} {status}" for status, names in summary.items()]
        self.report({"INFO"}, f"Phong node groups: {', '.join(parts)}")
        return {"FINISHED"}


class PHONG_OT_add_node_group(bpy.types.Operator):
    """Add a Phong node group to the active shader node tree"""

    bl_idname = "phong.add_node_group"
    bl_label = "Add Phong Node Group"
    bl_options = {"REGISTER", "UNDO"}

    group_name: StringProperty(name="Group", description="Name of the Phong node group to add")

    @classmethod
    def poll(cls, context):
        space = context.space_data
        if (space is not None and space.type == "NODE_EDITOR"
                and space.tree_type == "ShaderNodeTree" and space.edit_tree is not None):
            return True
        cls.poll_message_set("Add Phong Node Group: open a material's node tree in the "
                             "Shader Editor first")
        return False

    @classmethod
    def description(cls, context, properties):
        group = GROUPS.get(properties.group_name)
        return group.description if group else cls.__doc__

    def execute(self, context):
        space = context.space_data
        try:
            add_group_node(space.edit_tree, self.group_name, space.cursor_location)
        except ValueError as error:
            self.report({"ERROR"}, f"Add Phong Node Group: {error}")
            return {"CANCELLED"}
        return {"FINISHED"}

    def invoke(self, context, event):
        result = self.execute(context)
        if result == {"FINISHED"}:  # follow the mouse, like Blender's own Add menu
            bpy.ops.node.translate_attach_remove_on_cancel("INVOKE_DEFAULT")
        return result


def add_group_node(tree, group_name: str, location):
    """Add a node of the Phong group *group_name* (loaded or upgraded as needed) to *tree*."""
    if group_name not in GROUPS:
        raise ValueError(f"Unknown Phong group {group_name!r}; expected one of: {', '.join(GROUPS)}")
    group, _status = loader.ensure_group(group_name)
    for node in tree.nodes:
        node.select = False
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.location = location
    node.width = 200
    node.select = True
    tree.nodes.active = node
    return node



# -- Phong materials -----------------------------------------------------------------

def _warn(op, message):
    if message:
        op.report({"WARNING"}, message)


_lights_report = file_io.lights_report


def _selected_meshes(op, context, action):
    """The editable selected meshes, or None after an error report (baking works on
    meshes)."""
    selected = list(context.selected_objects or [])
    meshes, others = [], []  # one pass: `o not in meshes` made Apply quadratic (1.3 s at 10,000)
    for obj in selected:
        editable = obj.type == "MESH" and obj.library is None and obj.data.library is None
        (meshes if editable else others).append(obj)
    if not meshes:
        what = (f"no mesh among the selected objects ({', '.join(o.name for o in others)})"
                if others else "nothing is selected")
        op.report({"ERROR"}, f"{action}: {what}; select mesh objects")
        return None
    if others:
        op.report({"WARNING"}, f"{action}: skipped (not editable meshes): "
                  + ", ".join(o.name for o in others))
    return meshes


def _selected_objects(op, context, action, override=False):
    """The selected objects that take Phong materials (with the objects of the collections
    their Empties instance), or None after an error report; those that cannot are named in
    a warning.  *override*: what is linked from a library first made convertible through
    library overrides (``convert.override_linked``: Apply)."""
    selected = list(context.selected_objects or [])
    if override:
        selected = convert.override_linked(context.scene, selected, context.view_layer)
    objects, skipped = convert.expand(selected)
    if not objects:
        what = (f"no object with materials among the selected objects "
                f"({', '.join(o.name for o in selected)})" if selected else "nothing is selected")
        op.report({"ERROR"}, f"{action}: {what}; select meshes, curves, text or surfaces")
        return None
    if skipped:
        op.report({"WARNING"}, f"{action}: not converted: "
                  + "; ".join(f"{name} ({why})" for name, why in skipped))
    return objects


class PHONG_OT_apply_material(bpy.types.Operator):
    """Convert the materials of the selected objects (meshes, curves, text, surfaces, and the \
objects of instanced collections) to Phong materials driven by the scene's lights (objects \
that shared a material share its Phong version; the originals are kept)"""

    bl_idname = "phong.apply_material"
    bl_label = "Apply Phong Material"
    bl_options = {"REGISTER", "UNDO"}

    model: EnumProperty(
        name="Model", default="SCENE",
        items=(("SCENE", "Scene's Model", "Keep the scene's lighting model (Seeds unless "
                "changed)"),
               ("SEEDS", "Seeds", "The textbook Phong model of the lecture notes"),
               ("THREEJS", "three.js", "three.js r181's MeshPhongMaterial / "
                "MeshLambertMaterial (docs/threejs.md)"),
               ("X3D", "X3D / VRML97", "The ISO lighting equation of X3D and VRML97 "
                "(docs/x3d.md)")),
        description="Lighting model of the scene's Phong materials (one per scene: the "
                    "lights are shared)")

    def execute(self, context):
        objects = _selected_objects(self, context, "Apply Phong Material", override=True)
        if objects is None:
            return {"CANCELLED"}
        if self.model != "SCENE":
            context.scene[rig.MODEL_KEY] = self.model.lower()
        report = convert.apply(context.scene, objects, context.view_layer)
        _lights_report(self, report.sync)
        for note in report.notes:
            self.report({"WARNING"}, f"Phong: {note}")
        names = report.materials
        shown = name_list(names, limit=8, quote=False)
        lights = len(report.lights)
        self.report({"INFO"}, f"Phong materials: {shown} ({lights} light"
                              f"{'s' if lights != 1 else ''})")
        return {"FINISHED"}


class PHONG_OT_relink_lights(bpy.types.Operator):
    """Bring the Phong materials of the current scene up to date with its lights (also \
upgrades Phong materials of older versions)"""

    bl_idname = "phong.relink_lights"
    bl_label = "Relink Phong Lights"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        sync = sync_mod.relink_scene(context.scene, context.view_layer)
        _lights_report(self, sync)
        groups = len(sync.groups)
        self.report({"INFO"}, f"Phong: {len(sync.lights)} light(s) in {groups} lights "
                              f"group(s); {len(sync.changed)} material(s) updated")
        return {"FINISHED"}


class PHONG_OT_restore_materials(bpy.types.Operator):
    """Put the original materials back on the selected objects (their Phong versions stay \
in the file until unused)"""

    bl_idname = "phong.restore_materials"
    bl_label = "Restore Original Materials"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        objects = _selected_objects(self, context, "Restore Original Materials")
        if objects is None:
            return {"CANCELLED"}
        names = {m.name: m for m in bpy.data.materials}  # one look-up table for all slots
        slots = sum(convert.restore(obj, names) for obj in objects)
        scene = context.scene
        slots += convert.drop_overrides(scene, list(context.selected_objects or []))
        if not any(recipe.is_phong_material(slot.material) for obj in scene.objects
                   for slot in getattr(obj, "material_slots", ())):
            shadows.give_back_raycast(scene)  # no Phong shadows left: Ray Cast as it was
        if not slots:
            self.report({"WARNING"}, "Restore Original Materials: no selected object has a "
                                     "Phong material made from another material")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Restored the original material in {slots} slot(s)")
        return {"FINISHED"}


class PHONG_OT_add_term_passes(bpy.types.Operator):
    """Add the Phong AOV passes (Color and each term) to the active view layer, for the \
compositor"""

    bl_idname = "phong.add_term_passes"
    bl_label = "Add Phong Passes"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        layer = context.view_layer
        added = engine_outputs.add_view_layer_aovs(layer, recipe.AOVS)
        if added and any(loop.has_loop(t) or shadows.has_shadows(t)
                         for t in rig.groups_of(context.scene)):
            sync_mod.relink_scene(context.scene, layer)  # 5.3+: the materials write them again
        self.report({"INFO"}, f"Phong passes on view layer {layer.name!r}: "
                              + (", ".join(added) if added else "all there already"))
        return {"FINISHED"}


# -- demo scenes and the comparison -------------------------------------------------

def _scene_items(_self, _context):
    items = []
    for name in scenes.available():
        try:
            title = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))["title"]
        except scenes.SceneError as error:
            title = f"(invalid: {error})"
        items.append((name, name.replace("_", " ").title(), title))
    return items or [("NONE", "No scene", "")]


class PHONG_OT_build_demo_scene(bpy.types.Operator):
    """Build a demo scene of the seeds into a new scene (your scenes are not touched)"""

    bl_idname = "phong.build_demo_scene"
    bl_label = "Build Phong Demo Scene"
    bl_options = {"REGISTER", "UNDO"}

    name: EnumProperty(name="Scene", description="Demo scene (scenes/<name>.toml)",
                       items=_scene_items)
    resolution: IntProperty(name="Resolution", description="Picture height in pixels",
                            default=256, min=8, max=4096)
    filepath: StringProperty(name="Scene File", subtype="FILE_PATH", default="",
                             description="A scene .toml file of your own (instead of Scene)",
                             options={"SKIP_SAVE"})

    def execute(self, context):
        path = (bpy.path.abspath(self.filepath) if self.filepath
                else os.path.join(scenes.SCENES_DIR, f"{self.name}.toml"))
        try:
            data = scenes.load(path)
        except scenes.SceneError as error:
            self.report({"ERROR"}, f"Build Phong Demo Scene: {error}")
            return {"CANCELLED"}
        scene = builder.build(data, self.resolution)
        if context.window is not None:
            context.window.scene = scene
        self.report({"INFO"}, f"Built '{scene.name}': {data['title']}")
        return {"FINISHED"}


class _CompareScene:
    """Compare Phong Scene, under its name and its old one (a mixin: Blender registers each
    operator class on its own)."""

    bl_label = "Compare Phong Scene"

    directory: StringProperty(name="Folder", subtype="DIR_PATH", default="//phong_compare",
                              description="Output folder (one sub-folder per scene)")
    engines: EnumProperty(name="Engines", options={"ENUM_FLAG"}, default={"EEVEE", "CYCLES"},
                          items=(("EEVEE", "Eevee", ""), ("CYCLES", "Cycles", "")))
    peers: EnumProperty(name="Peers", options={"ENUM_FLAG"}, default=set(),
                        items=(("THREEJS", "three.js", "Export the scene as a three.js page "
                                "and render it in headless Chromium (needs chromium and "
                                "three.js: bash tools/phong.sh setup)"),
                               ("X_ITE", "X_ITE", "Export the scene as X3D and render it with "
                                "the X3D browser X_ITE in headless Chromium (needs chromium "
                                "and X_ITE: bash tools/phong.sh setup)")))

    @classmethod
    def poll(cls, context):
        if context.scene is None:
            cls.poll_message_set("No active scene")
            return False
        return True

    @staticmethod
    def _layer(context):
        """The active view layer's name when it is one of the active scene's, else None."""
        layer = context.view_layer
        scene = context.scene
        if layer is not None and scene.view_layers.get(layer.name) == layer:
            return layer.name
        return None

    def execute(self, context):
        scene = context.scene
        if scene is not None and scene.camera is None:
            return self._with_camera(context)
        return self._compare(context)

    def _with_camera(self, context):
        """The comparison of a scene without a scene camera: from its first camera object,
        else from a camera that frames its Phong objects, added for the comparison and
        removed after it (the scene is left as it was)."""
        scene = context.scene
        cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
        added = None
        try:
            if cameras:
                scene.camera = cameras[0]
                self.report({"INFO"}, f"{self.bl_label}: the scene sets no camera: compared "
                                      f"from its camera object '{cameras[0].name}'")
            else:
                try:
                    _layer, objects = engine.check(scene, self._layer(context), camera=False)
                except engine.ComparisonError as error:
                    self.report({"ERROR"}, f"{self.bl_label}: {error}")
                    return {"CANCELLED"}
                added = framing.add_camera(scene, objects)
                self.report({"INFO"}, f"{self.bl_label}: the scene has no camera: compared "
                                      "from one that frames its Phong objects")
            return self._compare(context)
        finally:
            scene.camera = None
            if added is not None:
                data = added.data
                bpy.data.objects.remove(added)
                bpy.data.cameras.remove(data)

    def _compare(self, context):
        scene = context.scene
        peers = [p.lower() for p in self.peers]
        try:
            engine.check(scene, self._layer(context))
            engine.check_peers(peers)
        except engine.ComparisonError as error:
            self.report({"ERROR"}, f"{self.bl_label}: {error}")
            return {"CANCELLED"}
        folder = bpy.path.abspath(self.directory) if self.directory.startswith("//") \
            else self.directory
        if self.directory.startswith("//") and not bpy.data.filepath:
            folder = os.path.join(tempfile.gettempdir(), "phong_compare")
        problem = outputs.output_problem(folder)
        if problem is not None:
            self.report({"ERROR"}, f"{self.bl_label}: {problem}")
            return {"CANCELLED"}
        name = describe.folder_name(scene)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            metrics = engine.run(scene, os.path.join(folder, name),
                                engines=[e.lower() for e in self.engines],
                                progress=lambda f, _t: wm.progress_update(int(100 * f)),
                                view_layer=self._layer(context), peers=peers)
        except (RuntimeError, OSError, engine.ComparisonError) as error:
            self.report({"ERROR"}, f"{self.bl_label}: the comparison failed: {error}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        sheet = os.path.join(folder, name, "sheet.png")
        _show_image(context, sheet)
        seen = metrics["coverage"]
        if not seen["ok"]:   # a comparison of (almost) nothing: no verdict at all
            self.report({"ERROR"}, f"{self.bl_label}: '{scene.name}': {seen['message']} "
                                   f"({sheet})")
            return {"FINISHED"}
        for note in metrics.get("notes", []):   # what the verdicts rest on (the report's too)
            self.report({"INFO"}, f"{self.bl_label}: '{scene.name}': {note}")
        verdicts = compare.verdict_text(metrics["verdict"])
        self.report({"INFO"} if metrics["ok"] else {"WARNING"},
                    f"Phong comparison of '{scene.name}': {verdicts} ({sheet})")
        return {"FINISHED"}

    def invoke(self, context, event):
        return self.execute(context)


class PHONG_OT_compare_scene(_CompareScene, bpy.types.Operator):
    """Render the active scene's Phong materials with Eevee and Cycles, compare both with \
the numpy reference of the formulas for the scene's lights, and write images, term passes, \
heatmaps, a sheet and metrics.json"""

    bl_idname = "phong.compare_scene"
    bl_options = {"REGISTER"}


class PHONG_OT_bake_comparison(_CompareScene, bpy.types.Operator):
    """The old name of Compare Phong Scene (0.3 and earlier), kept for scripts: "bake" now \
means Bake Phong Lighting only"""

    bl_idname = "phong.bake_comparison"
    bl_options = {"REGISTER", "INTERNAL"}


# -- interchange (the formats' table: interchange/formats.py) --------------------------------

class PHONG_OT_export_mtl(bpy.types.Operator, ExportHelper):
    """Write the Phong materials as a Wavefront MTL library (Kd = Object Color, Ka = Ambient \
Object Color, Ks, Ns, Ke, illum 2)"""

    bl_idname = "phong.export_mtl"
    bl_label = "Export Phong Materials (.mtl)"
    bl_options = {"REGISTER"}

    filename_ext = ".mtl"
    filter_glob: StringProperty(default=file_io.glob("mtl"), options={"HIDDEN"})
    selection_only: BoolProperty(name="Selected Objects Only", default=False,
                                 description="Only the Phong materials of the selected objects")

    def execute(self, context):
        return file_io.run_export(self, context, "mtl", self.selection_only)


class PHONG_OT_export_obj(bpy.types.Operator, ExportHelper):
    """Export Wavefront OBJ with Blender's exporter, its MTL holding the exact values of \
every Phong material (the other materials as Blender writes them)"""

    bl_idname = "phong.export_obj"
    bl_label = "Export Wavefront (.obj) with Phong Materials"
    bl_options = {"REGISTER"}

    filename_ext = ".obj"
    filter_glob: StringProperty(default=file_io.glob("obj"), options={"HIDDEN"})
    selection_only: BoolProperty(name="Selected Objects Only", default=False,
                                 description="Only the selected objects")

    def execute(self, context):
        return file_io.run_export(self, context, "obj", self.selection_only)


class PHONG_OT_import_obj(bpy.types.Operator, ImportHelper):
    """Import a Wavefront OBJ with its MTL materials as exact Phong materials driven by the \
scene's lights (Ka, Kd, Ks, Ns, Ke, illum 0-2, maps); the importer's materials are kept"""

    bl_idname = "phong.import_obj"
    bl_label = "Import Wavefront (.obj) as Phong"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".obj"
    filter_glob: StringProperty(default=file_io.glob("obj"), options={"HIDDEN"})

    def execute(self, context):
        return file_io.run_import(self, context, "obj")


def _show_image(context, path):
    """Open *path* in an Image Editor (an existing one, else a new window); no-op headless."""
    image = bpy.data.images.load(path, check_existing=True)
    image.reload()
    if context.window is None or context.screen is None:
        return
    area = next((a for a in context.screen.areas if a.type == "IMAGE_EDITOR"), None)
    if area is None:
        try:
            bpy.ops.wm.window_new()
            area = bpy.context.window_manager.windows[-1].screen.areas[0]
            area.type = "IMAGE_EDITOR"
        except RuntimeError:
            return
    area.spaces.active.image = image


class PHONG_OT_export_threejs(bpy.types.Operator, ExportHelper):
    """Write the scene as a three.js page: the HTML page (the scene's triangles, corner normals, camera, lights and Phong materials inside) with three.js r181 copied beside it; it opens in any browser"""

    bl_idname = "phong.export_threejs"
    bl_label = "Export three.js Page"
    bl_options = {"REGISTER"}

    filename_ext = ".html"
    filter_glob: StringProperty(default=file_io.glob("threejs"), options={"HIDDEN"})

    def execute(self, context):
        return file_io.run_export(self, context, "threejs")


classes = (PHONG_OT_load_node_groups, PHONG_OT_add_node_group, PHONG_OT_apply_material,
           PHONG_OT_relink_lights, PHONG_OT_restore_materials, PHONG_OT_add_term_passes,
           PHONG_OT_build_demo_scene, PHONG_OT_compare_scene, PHONG_OT_bake_comparison, PHONG_OT_export_mtl,
           PHONG_OT_import_obj, PHONG_OT_export_obj, PHONG_OT_export_threejs)


register, unregister = bpy.utils.register_classes_factory(classes)
