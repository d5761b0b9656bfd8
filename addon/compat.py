# SPDX-License-Identifier: GPL-3.0-or-later
"""Differences between the supported Blender versions (4.2 LTS to 5.3), in one place.

Sockets of Blender's own nodes are reached through :func:`input_socket` and
:func:`output_socket`, by identifier, never by position: releases insert sockets before existing
ones (5.3 put a hidden ``LightIndex`` before Vector Transform's ``Vector`` and two dispersion
inputs in the middle of Principled BSDF), and Blender's own ``node.inputs["key"]`` skips
sockets that are unavailable for the node's current mode.  ``tests/test_layout.py`` fails if
positional socket access comes back in ``addon/`` or ``node_groups/``."""

import os
import sys

import bpy

from ..node_groups.library import SWITCH_FEATURE

VERSION = bpy.app.version
#: Attribute nodes of type View Layer a lights group may hold (lights' transforms read from
#: World custom properties, ``lighting/rig.py``): each is a search loop in Eevee's shader and
#: its compile time grows steeply with their number, more so with the five term AOVs on the
#: view layer (each AOV output evaluates the group again).  Measured with
#: tests/test_materials.py's Eevee test (5 AOVs) on 5.2.3: 4 lookups 2.9 s (6 lights: 3.4 s
#: against 4.7 s with none), 5: 9.9 s, 6: 15 s, 8: 154 s; so 4.  Before 5.2 none: 4.2.23, 4.5.15
#: and 5.0.1 read them right in Cycles and Eevee, but that test ran past 4 minutes with 4
#: lookups on each; there the lights keep drivers in the lights group (the rig of 0.2).
VIEW_LAYER_LOOKUPS = 4 if VERSION >= (5, 2, 0) else 0
#: Eevee's light loop (Blender 5.3): Light Evaluation, Light Info, Attribute nodes of type
#: Light and Vector Transform's Light space upstream of a Light Accumulation node are run once
#: per light (``lighting/loop.py``).  Eevee only: Cycles renders that part as 0, and before 5.3
#: the nodes do not exist (a file of 5.3 shows them as undefined nodes).
HAS_LIGHT_LOOP = VERSION >= (5, 3, 0) and hasattr(bpy.types, "ShaderNodeLightAccumulation")
#: The group variants this Blender can write (``node_groups.library.VARIANTS``): 5.3's shader
#: trees have the Switch node (5.2's and earlier cannot add one).
NODE_FEATURES = (SWITCH_FEATURE,) if VERSION >= (5, 3, 0) else ()
#: Cycles' Raycast shader node (Blender 5.1+; 4.2-5.0 have none): a lights group casts each
#: light's shadow ray with it (``lighting/shadows.py``).  Eevee's is screen space only: it
#: never evaluates one (the group's Shader, which Eevee shows, has no shadow).
HAS_RAYCAST = VERSION >= (5, 1, 0) and hasattr(bpy.types, "ShaderNodeRaycast")
#: What Blender's Raycast node skips (5.3: an object whose Ray Visibility ▸ Ray Cast is off,
#: ``visible_raycast``; 5.2: only one with every ray visibility off).  Neither release's node
#: reads Ray Visibility ▸ Shadow (``visible_shadow``) nor Light Linking's blockers.
RAYCAST_VISIBILITY = "visible_raycast" if VERSION >= (5, 3, 0) else None
_RAY_VISIBILITY = ("visible_camera", "visible_diffuse", "visible_glossy", "visible_transmission",
                   "visible_volume_scatter", "visible_shadow")


def set_casts_shadow(obj, casts: bool) -> None:
    """Let *obj* cast shadows or not: Ray Visibility ▸ Shadow (Eevee, Blender's own shaders)
    and, where the Raycast node reads it (5.3+), Ray Visibility ▸ Ray Cast."""
    obj.visible_shadow = casts
    if RAYCAST_VISIBILITY is not None and hasattr(obj, RAYCAST_VISIBILITY):
        setattr(obj, RAYCAST_VISIBILITY, casts)


def blocks_raycast(obj) -> bool:
    """Whether Cycles' Raycast node can meet *obj* (a renderable object): on 5.3 unless its
    Ray Visibility ▸ Ray Cast is off; before, unless every ray visibility is off."""
    if RAYCAST_VISIBILITY is not None:
        return bool(getattr(obj, RAYCAST_VISIBILITY, True))
    return any(getattr(obj, name, True) for name in _RAY_VISIBILITY)
#: View Layer lookups of a lights group whose Eevee side is the light loop: Eevee compiles no
#: part of that group (the lookups' cost above is Eevee's), Cycles resolves each lookup once
#: per render, so every light's transform comes from the World (a light drag then re-evaluates
#: no material, whatever the number of lights).
LOOP_VIEW_LAYER_LOOKUPS = 1 << 20
#: Eevee leaves out a point or spot light beyond its influence distance (by default from its
#: watts, about √watts metres; a Phong light's reach does not depend on its watts): on 5.3
#: the lights that drive Phong materials get this custom distance (``lighting/loop.py``), so
#: a Phong surface up to 3 km from a point or spot light is lit by it in Eevee.  Not more:
#: with a custom distance of 5,000 m or more Eevee drops the light's shadows for every
#: material of the scene (Principled ones too); up to 3,000 m they stay (measured, 5.3.0; the
#: releases before 5.3 set no distance).  Lights set to 10⁴ m by earlier versions of the
#: extension come down to this.
LOOP_LIGHT_DISTANCE = 3.0e3


def file_from_newer_release() -> bool:
    """Whether the open file was written by a newer Blender than this one (Blender reads it
    and says "expect loss of data"): bpy 5.2.3 reads the group nodes of a material saved by
    5.3.0 so that their inputs evaluate wrongly (a Phong material's highlight as if its
    exponent were 0; measured), until the node is made again (``sync.upgrade_on_load``)."""
    return tuple(bpy.data.version[:2]) > tuple(VERSION[:2])


def view_layer_lookups(loop: bool) -> int:
    """The View Layer lookups a lights group may hold: unlimited (LOOP_VIEW_LAYER_LOOKUPS)
    when Eevee renders its materials with the light loop, else VIEW_LAYER_LOOKUPS (none
    where that is 0: the drivers of the rig of 0.2, as ``benchmarks/light_move.py`` sets it
    to measure that rig)."""
    if loop and HAS_LIGHT_LOOP and VIEW_LAYER_LOOKUPS:
        return LOOP_VIEW_LAYER_LOOKUPS
    return VIEW_LAYER_LOOKUPS


def _socket(sockets, key: str, node, side: str):
    """The socket of *sockets* whose identifier is *key*, else the first whose name is *key*
    (available sockets first): identifiers are stable across releases for Blender's nodes
    (``Value``, ``Value_001``, ``Vector``, ``Scale`` ...); a group node's sockets are found by
    the names of its interface."""
    if not isinstance(key, str):
        raise TypeError(f"{side} sockets are looked up by identifier or name, not by {key!r}")
    named = None
    for socket in sockets:
        if socket.identifier == key:
            return socket
        if named is None and socket.name == key and getattr(socket, "enabled", True):
            named = socket
    if named is None:
        named = next((socket for socket in sockets if socket.name == key), None)
    if named is None:
        have = ", ".join(socket.identifier for socket in sockets)
        raise KeyError(f"{node.bl_idname} '{node.name}' has no {side} socket {key!r} "
                       f"(Blender {bpy.app.version_string}: {have})")
    return named


def input_socket(node, key: str):
    """The input of *node* whose identifier (else name) is *key*: never by position."""
    return _socket(node.inputs, key, node, "input")


def output_socket(node, key: str):
    """The output of *node* whose identifier (else name) is *key*: never by position."""
    return _socket(node.outputs, key, node, "output")


#: The one output of Blender's value nodes, by node type (a control of a Phong material is a
#: Value or an RGB node).
VALUE_OUTPUTS = {"ShaderNodeValue": "Value", "ShaderNodeRGB": "Color"}


def value_output(node):
    """The output of a Value or RGB node (the controls of a Phong material)."""
    try:
        return output_socket(node, VALUE_OUTPUTS[node.bl_idname])
    except KeyError:
        raise TypeError(f"{node.bl_idname} '{node.name}' is not a Value or RGB node") from None


def exit_crashes() -> bool:
    """Whether bpy's own clean-up at interpreter exit crashes this process (signal 11): on
    Blender 4.2 once its glTF exporter has exported, also in a plain script without this
    extension (measured)."""
    return VERSION < (4, 3, 0) and "io_scene_gltf2.blender.exp" in sys.modules


def leave_if_exit_crashes(code: int) -> None:
    """Where bpy's clean-up at exit would crash (``exit_crashes``), end the process now with
    *code*, its output flushed (callers' files are written and closed by then); otherwise
    return, and Python ends as usual."""
    if exit_crashes():
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)


def eevee_engine() -> str:
    """Eevee's engine id: 'BLENDER_EEVEE_NEXT' in 4.2-4.5, 'BLENDER_EEVEE' again from 5.0."""
    items = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    return "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in items else "BLENDER_EEVEE"


def set_multilayer_exr(image_settings, set_=setattr) -> None:
    """32-bit float multilayer EXR: every pass (AOVs included) in its own part.
    *set_(owner, attribute, value)* does the setting."""
    if hasattr(image_settings, "media_type"):  # 5.0+
        set_(image_settings, "media_type", "MULTI_LAYER_IMAGE")
    set_(image_settings, "file_format", "OPEN_EXR_MULTILAYER")
    set_(image_settings, "color_depth", "32")
    set_(image_settings, "exr_codec", "ZIP")


def set_png(image_settings) -> None:
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = "IMAGE"
    image_settings.file_format = "PNG"
    image_settings.color_mode = "RGB"
    image_settings.color_depth = "8"


def uses_nodes(id_block) -> bool:
    """Whether a material or world draws from its node tree (always from 5.0 on, where
    ``use_nodes`` is deprecated)."""
    return VERSION >= (5, 0, 0) or id_block.use_nodes


def animated_paths(id_block):
    """The data paths that *id_block*'s drivers and active action animate (a set), or None
    where that cannot be told (NLA strips).  Blender 4.4+ keeps an action's F-Curves per slot
    (layered actions; 5.0 removed ``Action.fcurves``), earlier releases on the action."""
    anim = id_block.animation_data
    if anim is None:
        return set()
    paths = {driver.data_path for driver in anim.drivers}
    if len(anim.nla_tracks):
        return None
    action = anim.action
    if action is None:
        return paths
    if hasattr(anim, "action_slot"):
        from bpy_extras import anim_utils  # noqa: PLC0415 (4.4+)

        bag = anim_utils.action_get_channelbag_for_slot(action, anim.action_slot)
        fcurves = bag.fcurves if bag is not None else ()
    else:
        fcurves = action.fcurves
    return paths | {fcurve.data_path for fcurve in fcurves}


def new_material_tree(material):
    """The node tree of a material, switched on where Blender still needs ``use_nodes``."""
    if not uses_nodes(material):
        material.use_nodes = True
    return material.node_tree


def black_world(world) -> None:
    """A world that adds no light and shows black (5.0 gives new worlds a grey Background)."""
    world.color = (0.0, 0.0, 0.0)
    if not uses_nodes(world):
        return
    background = world.node_tree.nodes.get("Background") if world.node_tree else None
    if background is not None:
        background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)


#: The first release verified to render a float ``custom_normal`` corner attribute right in
#: Cycles (4.5.15 and 5.0.1 do not; 5.1 was not tried).
FLOAT_CUSTOM_NORMALS = (5, 2, 0)


def set_corner_normals(mesh, normals) -> None:
    """Custom normals of *mesh*, one unit vector per corner (*normals*: float32 (corners, 3)).
    From Blender 5.2 on they are written at once as the float vector attribute
    ``custom_normal`` of the corners.  Blender 4.5 and 5.0 hold such an attribute too, but
    their Cycles renders it wrongly (an X3D Cylinder's side shows the normal of another
    corner: tests/test_compat.py), so there, as before 4.5, ``normals_split_custom_set``
    encodes them (it reads a numpy array fastest; 1.6 M corners: seconds through a list of
    tuples)."""
    if VERSION >= FLOAT_CUSTOM_NORMALS:
        old = mesh.attributes.get("custom_normal")
        if old is not None:
            mesh.attributes.remove(old)
        attribute = mesh.attributes.new("custom_normal", "FLOAT_VECTOR", "CORNER")
        attribute.data.foreach_set("vector", normals.reshape(-1))
    else:
        mesh.normals_split_custom_set(normals.reshape(-1, 3))


def smooth_by_angle(mesh, angle: float) -> None:
    """Shade *mesh* as VRML97 / X3D's ``creaseAngle`` says: smooth across an edge whose faces
    meet at less than *angle* (radians), sharp elsewhere; 0 flat, π or more smooth everywhere.
    From 4.1 on (every supported release) faces are smooth unless ``sharp_face`` and edges
    sharp where ``sharp_edge`` (``shade_smooth`` / ``set_sharp_from_angle``, Blender's "Smooth
    by Angle" without a modifier); before, Auto Smooth held the angle on the mesh."""
    if angle <= 0.0:
        mesh.shade_flat()
        return
    mesh.shade_smooth()
    if angle >= 3.141592653589793:
        return
    if hasattr(mesh, "set_sharp_from_angle"):
        mesh.set_sharp_from_angle(angle=float(angle))
    else:  # Blender 4.0 and earlier (not supported, kept for a reader of the recipe)
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = float(angle)


def rename(id_block, name: str) -> None:
    """``id_block.name = name`` (a numeric suffix where the name is taken), by ``ID.rename``
    where Blender has it (4.3+): setting ``name`` from Python first checks that the ID is in
    the file by walking its list from the start (``BKE_id_is_in_main``), so naming each of
    N new materials cost O(N) (Apply at 10,000 objects: 40 of its 62 s)."""
    if hasattr(id_block, "rename"):
        id_block.rename(name, mode="NEVER")
    else:
        id_block.name = name
