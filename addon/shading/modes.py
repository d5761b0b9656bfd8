# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex and Per Face shading, live, without Python at render time (docs/shading_modes.md):
the setting's life (a material's mode put into effect, followed, upgraded), with its
Geometry Nodes group in ``geometry.py`` and its shader groups in ``groups.py``.

A Phong material's Shading (``material["phong_shading"]``: PIXEL, VERTEX, FACE) says where
the model is evaluated.  PIXEL is the lights group in the shader (``lighting/rig.py``).
VERTEX and FACE evaluate the same model (``node_groups/shading_modes.py``: the library's own
group expressions, composed as the lights group composes them) in the shader too, but at the
vertices of the pixel's triangle or at the centre of its face: a Geometry Nodes modifier
stores the mesh data they read (``geometry.py``), and the material shows a shader group of
its light set and mode (``groups.py``).  This module puts a mode into effect (the modifier,
the group, the material's surface and AOVs), follows the objects that get such a material,
and removes what no material needs any more.

Moving a light or the camera evaluates no Geometry Nodes and, where the lights group reads the
lights' transforms from the World, re-evaluates no material either: a light drag costs what it
costs Per Pixel.  Everything is data of the file: a saved file renders the same
without the extension.
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from ...node_groups import shading_modes as model
from ..lighting import opacity, recipe, world_copies
from . import geometry as geometry_nodes
from .geometry import (GEOMETRY_TREE, MODIFIER_NAME, ensure_geometry_tree, geometry_tree,
                       modifiers_off)
from .groups import GROUP_MODE_KEY, VERTEX_OUTPUTS, build_shading_group, shading_group

#: Custom property of the material: its shading mode (docs/contract.md).
SHADING_KEY = "phong_shading"
MODES = model.MODES
PIXEL, VERTEX, FACE = MODES
#: Nodes of the material in these modes: the shading group and the Emission it feeds.
SHADING_NODE = "phong_shading_group"
EMISSION_NODE = recipe.SHADING_EMISSION  # "phong_shading_emission"
#: The design before (a Geometry Nodes group per material storing a colour attribute that an
#: Attribute node showed): removed on load and by Relink.
LEGACY_TREE_KEY = "phong_shading_material"
LEGACY_ATTRIBUTE_NODE = "phong_shading_attribute"


def mode_of(material) -> str:
    """The material's shading mode (PIXEL when unset or unknown)."""
    value = material.get(SHADING_KEY, PIXEL) if material is not None else PIXEL
    return value if value in MODES else PIXEL


def set_mode(material, mode: str) -> None:
    """Set *material*'s shading mode and put it into effect."""
    if mode not in MODES:
        raise ValueError(f"unknown shading {mode!r}: expected one of {', '.join(MODES)}")
    material[SHADING_KEY] = mode
    update(material)


def group_of(material):
    """The shading group *material* shows (Per Vertex / Per Face), or None."""
    tree = material.node_tree if material is not None else None
    node = tree.nodes.get(SHADING_NODE) if tree is not None else None
    return node.node_tree if node is not None and node.bl_idname == "ShaderNodeGroup" else None


def users(material) -> list:
    """The mesh objects whose material slots hold *material*."""
    return [o for o in bpy.data.objects if o.type == "MESH" and o.library is None
            and any(slot.material == material for slot in o.material_slots)]


def needs_modifier(obj) -> bool:
    """Whether a material of *obj* is a Phong material shaded Per Vertex or Per Face."""
    return obj.type == "MESH" and any(
        mode_of(s.material) != PIXEL and recipe.is_phong_material(s.material)
        for s in obj.material_slots)


# -- putting a mode into effect ----------------------------------------------------------

def update(material, objects=None, groups=None) -> None:
    """Make *material* and its objects show its shading mode; *objects* (its users) when the
    caller has looked them up, *groups* a cache of shading groups shared by the calls of one
    refresh."""
    if not recipe.is_phong_material(material):
        return
    _remove_legacy_nodes(material)
    mode = mode_of(material)
    objects = users(material) if objects is None else objects
    if mode == PIXEL:
        had, geometry = group_of(material), geometry_tree()
        _surface_per_pixel(material)
        if geometry is not None:
            for obj in objects:
                if not needs_modifier(obj):
                    geometry_nodes.remove_modifier(obj, geometry)
        _remove_unused(had, geometry)
        return
    group = shading_group(material, mode, groups)
    _surface_per_mesh(material, group)
    geometry = ensure_geometry_tree()
    for obj in objects:
        geometry_nodes.ensure_modifier(obj, geometry)
    world_copies.follow_readers()  # Eevee compiles the group: it reads the World's copies


def refresh(scene=None) -> int:
    """Update every Phong material that is not Per Pixel (or still shows a shading group);
    remove what no material needs any more; returns how many materials.  Run after the lights
    groups changed (``sync``) and on load."""
    legacy = _remove_legacy_trees()
    todo = [m for m in recipe.phong_materials()
            if mode_of(m) != PIXEL or group_of(m) is not None
            or (legacy and LEGACY_ATTRIBUTE_NODE in m.node_tree.nodes)]
    if todo:
        wanted = {m.as_pointer() for m in todo}
        uses = {pointer: [] for pointer in wanted}
        for obj in bpy.data.objects:
            if obj.type != "MESH" or obj.library is not None:
                continue
            for pointer in {s.material.as_pointer() for s in obj.material_slots
                            if s.material is not None} & wanted:
                uses[pointer].append(obj)
        groups: dict = {}
        for material in todo:
            update(material, uses[material.as_pointer()], groups)
    _prune()
    return len(todo)


def _prune() -> None:
    """Remove the modifiers of objects that need them no more, the shading groups no material
    shows and the geometry group no modifier runs."""
    geometry = geometry_tree()
    if geometry is not None:
        for obj in bpy.data.objects:
            if obj.library is None and obj.type == "MESH" and not needs_modifier(obj):
                geometry_nodes.remove_modifier(obj, geometry)
    _remove_unused(geometry, *[t for t in bpy.data.node_groups
                               if GROUP_MODE_KEY in t.keys() and t.library is None])


_BUSY: list = []


@persistent
def follow_objects(_scene, depsgraph=None) -> None:
    """After an edit of mesh objects: one that got a Per Vertex / Per Face material (a slot
    assigned by hand) gets the modifier, and a modifier the user added after Phong Shading
    puts Phong Shading last again.  Only the updated objects are looked at."""
    if _BUSY or depsgraph is None or not (depsgraph.id_type_updated("OBJECT")
                                          or depsgraph.id_type_updated("MESH")):
        return
    geometry = geometry_tree()
    if geometry is None:
        return  # no Per Vertex / Per Face material was set up in the file: nothing to follow
    objects, meshes = set(), set()
    for change in depsgraph.updates:
        if not change.is_updated_geometry:  # a slot or a modifier changed: geometry is tagged
            continue  # (a light move re-shades every object: not looked at)
        original = getattr(change.id, "original", None)
        if isinstance(original, bpy.types.Object):
            if original.type == "MESH":
                objects.add(original)
        elif isinstance(original, bpy.types.Mesh):  # a slot of the mesh was assigned
            meshes.add(original.as_pointer())
    if meshes:
        objects.update(o for o in bpy.data.objects
                       if o.type == "MESH" and o.data.as_pointer() in meshes)
    todo = []
    for obj in objects:
        if obj.library is not None or not needs_modifier(obj):
            continue
        modifiers = obj.modifiers
        if not len(modifiers) or modifiers[-1].type != "NODES" \
                or modifiers[-1].node_group != geometry:
            todo.append(obj)
    if not todo:
        return
    _BUSY.append(True)
    try:
        for obj in todo:
            for slot in obj.material_slots:  # a material set up in another file or by hand
                if mode_of(slot.material) != PIXEL and group_of(slot.material) is None:
                    update(slot.material)
            geometry_nodes.ensure_modifier(obj, geometry)
    finally:
        _BUSY.pop()


@persistent
def upgrade_on_load(*_args) -> None:
    """A file of the design before (a Geometry Nodes group per material): refreshed into
    this one, nothing lost (the materials keep their Shading)."""
    if any(LEGACY_TREE_KEY in t.keys() for t in bpy.data.node_groups if t.library is None):
        refresh()


#: The shading room's handlers, (event of ``bpy.app.handlers``, function) in the order they
#: run (``addon/__init__.py`` registers them, before the lighting room's relink).
HANDLERS = (("depsgraph_update_post", follow_objects), ("load_post", upgrade_on_load))


def _remove_unused(*trees) -> None:
    """Remove those of *trees* (None skipped) that nothing uses."""
    for tree in trees:
        if tree is not None and tree.users == 0:
            bpy.data.node_groups.remove(tree)


def _remove_legacy_trees() -> bool:
    """Remove the Geometry Nodes groups (and their modifiers) of the design before."""
    legacy = [t for t in bpy.data.node_groups
              if LEGACY_TREE_KEY in t.keys() and t.library is None]
    for tree in legacy:
        for obj in bpy.data.objects:
            if obj.library is None and obj.type == "MESH":
                geometry_nodes.remove_modifier(obj, tree)
        bpy.data.node_groups.remove(tree)
    return bool(legacy)


def _remove_legacy_nodes(material) -> None:
    node = material.node_tree.nodes.get(LEGACY_ATTRIBUTE_NODE)
    if node is not None:
        material.node_tree.nodes.remove(node)


# -- the material's surface -----------------------------------------------------------

def _surface_per_pixel(material) -> None:
    tree = material.node_tree
    for name in (SHADING_NODE, EMISSION_NODE):
        node = tree.nodes.get(name)
        if node is not None:
            tree.nodes.remove(node)
    lights = tree.nodes.get(recipe.LIGHTS_NODE)
    output = tree.nodes.get(recipe.OUTPUT)
    if lights is None or output is None:
        return
    opacity.apply_opacity(material)  # the lights group's Shader into the output (or mix)
    for aov_name, socket in recipe.AOVS.items():  # every AOV from the lights group again
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if aov is not None:
            tree.links.new(lights.outputs[socket], aov.inputs["Color"])


def _surface_per_mesh(material, group) -> None:
    tree = material.node_tree
    node = recipe.named_node(tree, SHADING_NODE, "ShaderNodeGroup", (-20.0, 420.0))
    if node.node_tree != group:
        node.node_tree = group
    node.label = "Phong Per Vertex" if group.get(GROUP_MODE_KEY) == VERTEX else "Phong Per Face"
    node.width = 200.0
    lights = tree.nodes.get(recipe.LIGHTS_NODE)
    for socket in node.inputs:  # the material's controls, as its lights group node has them
        source = lights.inputs.get(socket.name) if lights is not None else None
        for link in list(socket.links):
            if source is None or not source.is_linked \
                    or link.from_socket != source.links[0].from_socket:
                tree.links.remove(link)
        if source is None:
            continue
        if source.is_linked:
            if not socket.is_linked:
                tree.links.new(source.links[0].from_socket, socket)
        else:
            socket.default_value = source.default_value
    emission = recipe.named_node(tree, EMISSION_NODE, "ShaderNodeEmission", (260.0, 420.0))
    emission.inputs["Strength"].default_value = 1.0
    if not any(l.from_socket == node.outputs["Color"] for l in emission.inputs["Color"].links):
        tree.links.new(node.outputs["Color"], emission.inputs["Color"])
    opacity.apply_opacity(material)  # the emission into the output (or the opacity mix)
    for aov_name in recipe.AOVS:
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if aov is None:
            continue
        if aov_name == recipe.AOV_NAME:  # Phong Color: the colour shown
            tree.links.new(node.outputs["Color"], aov.inputs["Color"])
        else:  # the per-pixel terms are not computed in this mode (and not compiled by Eevee)
            for link in list(aov.inputs["Color"].links):
                tree.links.remove(link)
            aov.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)


__all__ = ["SHADING_KEY", "MODES", "PIXEL", "VERTEX", "FACE", "SHADING_NODE", "EMISSION_NODE",
           "LEGACY_TREE_KEY", "LEGACY_ATTRIBUTE_NODE", "HANDLERS", "mode_of", "set_mode",
           "group_of", "users", "needs_modifier", "update", "refresh", "follow_objects",
           "upgrade_on_load",
           # from geometry.py and groups.py, for the callers of this module
           "GEOMETRY_TREE", "MODIFIER_NAME", "geometry_tree", "ensure_geometry_tree",
           "modifiers_off", "GROUP_MODE_KEY", "VERTEX_OUTPUTS", "shading_group",
           "build_shading_group"]
