# SPDX-License-Identifier: GPL-3.0-or-later
"""Properties editor panels: Phong settings of a light (Light tab) and of the World."""

import bpy

from ...node_groups import models
from ..lighting import properties, rig, shadows
from ..lighting.lights import SUPPORTED
from ..lighting.recipe import OPACITY, blends, is_phong_material
from .operators import (PHONG_OT_add_term_passes, PHONG_OT_apply_material,
                        PHONG_OT_relink_lights, PHONG_OT_restore_materials)


class DATA_PT_phong_light(bpy.types.Panel):
    """Phong settings of the light"""

    bl_idname = "DATA_PT_phong_light"
    bl_label = "Phong"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        light = getattr(context, "light", None)
        return light is not None and light.type in SUPPORTED

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        light = context.light
        settings = light.phong
        scene = context.scene
        layout.prop(scene.phong, "model")
        model = scene.phong.model
        col = layout.column(align=True)
        power = properties.from_power(light)
        for attr, _target in properties.model_settings(model, light):  # one list of them
            if attr == "intensity":
                col.prop(settings, "from_power")
                if power:
                    col.label(text=f"i0 {properties.power_intensity(light):.4g} from the "
                                   "light's Power", icon="LIGHT")
                    continue
            col.prop(settings, attr)
        if light.type == "AREA":
            layout.label(text="Area light: a Lambertian emitter's far field (a 180° spot)",
                         icon="INFO")
        note = models.get(model).spot_note  # docs/threejs.md, docs/x3d.md
        if note and light.type == "SPOT":
            layout.label(text=note, icon="INFO")
        layout.label(text="Colour, position, direction and spot size come from the light",
                     icon="INFO")
        layout.prop(light, "use_shadow", text="Cast Shadow")  # Blender's own switch
        rays = rig.wants_shadows(scene)
        for line in shadows.notes(model, rays, rig.wants_loop(scene)):
            layout.label(text=line, icon="INFO")
        obj = getattr(context, "object", None)
        blockers = shadows.blocker_note(obj) if rays and obj is not None else None
        if blockers:
            layout.label(text=blockers, icon="ERROR")
        layout.operator(PHONG_OT_relink_lights.bl_idname, icon="FILE_REFRESH")


class WORLD_PT_phong(bpy.types.Panel):
    """Phong ambient light of the world"""

    bl_idname = "WORLD_PT_phong"
    bl_label = "Phong Ambient"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "world"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return getattr(context, "world", None) is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.world.phong
        if context.scene is not None:
            layout.prop(context.scene.phong, "model")
        layout.prop(settings, "ambient_intensity")
        layout.prop(settings, "ambient_color")
        layout.operator(PHONG_OT_relink_lights.bl_idname, icon="FILE_REFRESH")


class MATERIAL_PT_phong(bpy.types.Panel):
    """Phong settings of the material (docs/shading_modes.md)"""

    bl_idname = "MATERIAL_PT_phong"
    bl_label = "Phong"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return is_phong_material(getattr(context, "material", None))

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(context.material.phong, "shading")
        if context.material.node_tree.nodes.get(OPACITY) is not None:
            layout.prop(context.material.phong, "opacity", slider=True)
        if context.material.phong.shading != "PIXEL":
            layout.label(text="Evaluated in the shader, on the mesh data of the modifier "
                              "\"Phong Shading\"", icon="INFO")
        scene = context.scene
        for line in shadows.material_notes(context.material.phong.shading,
                                           blends(context.material), rig.wants_shadows(scene),
                                           rig.wants_loop(scene)):
            layout.label(text=line, icon="INFO")


def _draw_material_menu(self, context):
    self.layout.separator()
    self.layout.operator(PHONG_OT_apply_material.bl_idname, icon="MATERIAL")
    self.layout.operator(PHONG_OT_relink_lights.bl_idname, icon="FILE_REFRESH")
    self.layout.operator(PHONG_OT_restore_materials.bl_idname, icon="LOOP_BACK")


def _draw_aov_panel(self, context):
    self.layout.operator(PHONG_OT_add_term_passes.bl_idname, icon="RENDERLAYERS")


#: The View Layer ▸ Shader AOV panel (its name in 4.2-5.0).
_AOV_PANEL = "VIEWLAYER_PT_layer_passes_aov"


classes = (DATA_PT_phong_light, WORLD_PT_phong, MATERIAL_PT_phong)


_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    _register_classes()
    bpy.types.VIEW3D_MT_object.append(_draw_material_menu)
    panel = getattr(bpy.types, _AOV_PANEL, None)
    if panel is not None:
        panel.append(_draw_aov_panel)


def unregister():
    panel = getattr(bpy.types, _AOV_PANEL, None)
    if panel is not None:
        panel.remove(_draw_aov_panel)
    bpy.types.VIEW3D_MT_object.remove(_draw_material_menu)
    _unregister_classes()
