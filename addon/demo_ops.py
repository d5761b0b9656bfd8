# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators of the demo scenes: build one, bake its Eevee / Cycles / reference comparison."""

from __future__ import annotations

import os

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty

from . import bake, builder, outputs, scenes


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


class PHONG_OT_bake_comparison(bpy.types.Operator):
    """Render the active demo scene with Eevee and Cycles, compare both with the numpy \
reference of the formulas and write images, heatmaps, a sheet and metrics.json"""

    bl_idname = "phong.bake_comparison"
    bl_label = "Bake Phong Comparison"
    bl_options = {"REGISTER"}

    directory: StringProperty(name="Folder", subtype="DIR_PATH", default="//phong_bake",
                              description="Output folder (one sub-folder per scene)")
    engines: EnumProperty(name="Engines", options={"ENUM_FLAG"}, default={"EEVEE", "CYCLES"},
                          items=(("EEVEE", "Eevee", ""), ("CYCLES", "Cycles", "")))

    @classmethod
    def poll(cls, context):
        if context.scene is None or builder.SCENE_KEY not in context.scene:
            cls.poll_message_set("The active scene is not a Phong demo scene "
                                 "(Build Phong Demo Scene first)")
            return False
        return True

    def execute(self, context):
        scene = context.scene
        folder = bpy.path.abspath(self.directory) if self.directory.startswith("//") \
            else self.directory
        if self.directory.startswith("//") and not bpy.data.filepath:
            import tempfile
            folder = os.path.join(tempfile.gettempdir(), "phong_bake")
        problem = outputs.output_problem(folder)
        if problem is not None:
            self.report({"ERROR"}, f"Bake Phong Comparison: {problem}")
            return {"CANCELLED"}
        data = builder.scene_dict(scene)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            metrics = bake.bake(scene, os.path.join(folder, data["name"]),
                                engines=[e.lower() for e in self.engines],
                                progress=lambda f, _t: wm.progress_update(int(100 * f)))
        except (RuntimeError, OSError) as error:
            self.report({"ERROR"}, f"Bake Phong Comparison: bake failed: {error}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        sheet = os.path.join(folder, data["name"], "sheet.png")
        _show_image(context, sheet)
        verdicts = ", ".join(f"{e} {v['value']} {'OK' if v['ok'] else 'FAIL'}"
                             for e, v in metrics["verdict"].items())
        self.report({"INFO"} if metrics["ok"] else {"WARNING"},
                    f"Phong comparison of '{data['name']}': {verdicts} ({sheet})")
        return {"FINISHED"}

    def invoke(self, context, event):
        return self.execute(context)


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


classes = (PHONG_OT_build_demo_scene, PHONG_OT_bake_comparison)


register, unregister = bpy.utils.register_classes_factory(classes)
