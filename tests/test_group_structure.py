# SPDX-License-Identifier: GPL-3.0-or-later
"""Structural snapshots of the generated node groups, compared with tests/data/group_structure.json.

For each group of the library: how many nodes of each type (``bl_idname``) and how many links
Blender holds once the group is loaded.  For the lights rig (``addon/lighting/rig.py``): the
"Phong Lights <scene>" group that *Apply Phong Material* builds for a scene with 1 and with 3
point lights: its nodes by type (group nodes by the group they use), links, drivers and the
number of nodes the renderer compiles once every group is inlined; the snapshot's "per light"
entry is the difference between the two scenes, divided by two: the cost of one more light.

The point is to fail on purpose: a change that adds nodes to a group, or nodes, links or drivers
per light, must show up here and be accepted by regenerating the snapshot and committing it with
the change (the diff of the JSON file is the review).  Regenerate it with

    PHONG_UPDATE_SNAPSHOTS=1 python -m pytest tests/test_group_structure.py

(the tests then write the file and pass); check ``git diff tests/data/group_structure.json``.
"""

from __future__ import annotations

import json
import os

import blender_env as be
from phong_nodes.node_groups import library

SNAPSHOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data",
                        "group_structure.json")
UPDATE = os.environ.get("PHONG_UPDATE_SNAPSHOTS") == "1"
HOW_TO_UPDATE = ("if the change is intended, regenerate the snapshot with "
                 "PHONG_UPDATE_SNAPSHOTS=1 python -m pytest tests/test_group_structure.py "
                 "and commit tests/data/group_structure.json")
GROUP_IO = ("NodeGroupInput", "NodeGroupOutput")


# -- counting ------------------------------------------------------------------------

def _node_type(node) -> str:
    if node.bl_idname == "ShaderNodeGroup":
        return f"ShaderNodeGroup[{node.node_tree.name}]"
    return node.bl_idname


def structure(tree) -> dict:
    """Nodes by type and the number of links of *tree*."""
    nodes: dict = {}
    for node in tree.nodes:
        nodes[_node_type(node)] = nodes.get(_node_type(node), 0) + 1
    return {"nodes": dict(sorted(nodes.items())), "links": len(tree.links)}


def inlined_nodes(tree) -> int:
    """The nodes of *tree* once every group node is replaced by its contents (without the
    groups' Group Input / Output nodes): what the renderer compiles."""
    total = 0
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeGroup":
            total += inlined_nodes(node.node_tree)
        elif node.bl_idname not in GROUP_IO:
            total += 1
    return total


# -- the snapshot file -----------------------------------------------------------------

def _load() -> dict:
    if not os.path.exists(SNAPSHOT):
        return {}
    with open(SNAPSHOT, encoding="utf-8") as f:
        return json.load(f)


def check(section: str, got: dict) -> None:
    """Compare *got* with the snapshot's *section*, or write it there (PHONG_UPDATE_SNAPSHOTS=1)."""
    data = _load()
    if UPDATE:
        data[section] = got
        with open(SNAPSHOT, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=1, sort_keys=True)
            f.write("\n")
        return
    assert section in data, f"{SNAPSHOT} has no {section!r}: {HOW_TO_UPDATE}"
    want, now = _flat(data[section]), _flat(got)
    differences = [f"  {key}: {want.get(key, '-')} in the snapshot, {now.get(key, '-')} now"
                   for key in sorted(set(want) | set(now)) if want.get(key) != now.get(key)]
    assert not differences, (f"the structure of {section} changed:\n" + "\n".join(differences)
                             + f"\n{HOW_TO_UPDATE}")


def _flat(tree: dict, prefix: str = "") -> dict:
    """{"a ▸ b ▸ c": value} for nested dicts."""
    out = {}
    for key, value in tree.items():
        path = f"{prefix} ▸ {key}" if prefix else str(key)
        out.update(_flat(value, path) if isinstance(value, dict) else {path: value})
    return out


# -- the library's groups ----------------------------------------------------------------

def test_library_groups_match_the_snapshot(bpy_clean):
    be.load_groups()
    got = {name: structure(bpy_clean.data.node_groups[name]) for name in library.NAMES}
    check("groups", got)


# -- the lights rig ---------------------------------------------------------------------

def _scene_with_point_lights(bpy, count: int):
    """A scene with a plane and *count* point lights, converted by Apply Phong Material;
    returns its "Phong Lights" group."""
    scene = be.new_scene(f"Rig{count}", 8, 8)
    material = bpy.data.materials.new(f"Clay{count}")
    be.compat().new_material_tree(material)
    plane = be.add_uv_plane(scene, f"Plane{count}", -1.0, -1.0, 2.0, material)
    for index in range(count):
        light = bpy.data.objects.new(f"Point{count}.{index}",
                                     bpy.data.lights.new(f"Point{count}.{index}", "POINT"))
        light.location = (index - 1.0, -2.0, 3.0)
        scene.collection.objects.link(light)
    bpy.context.window.scene = scene
    be.apply_phong(scene, [plane])
    tree = plane.active_material.node_tree.nodes["phong_lights"].node_tree
    assert tree.name == f"Phong Lights {scene.name}"
    assert list(tree["phong_lights"]) == [f"Point{count}.{i}" for i in range(count)]
    return tree


def _rig_structure(tree) -> dict:
    drivers = tree.animation_data.drivers if tree.animation_data is not None else ()
    return {**structure(tree), "nodes_total": len(tree.nodes), "nodes_inlined": inlined_nodes(tree),
            "drivers": len(drivers)}


def test_lights_rig_cost_per_light_matches_the_snapshot(bpy_clean):
    one = _rig_structure(_scene_with_point_lights(bpy_clean, 1))
    three = _rig_structure(_scene_with_point_lights(bpy_clean, 3))
    per_light = {key: (three[key] - one[key]) / 2
                 for key in ("nodes_total", "nodes_inlined", "links", "drivers")}
    types = set(one["nodes"]) | set(three["nodes"])
    per_light["nodes"] = {t: (three["nodes"].get(t, 0) - one["nodes"].get(t, 0)) / 2
                          for t in sorted(types)
                          if three["nodes"].get(t, 0) != one["nodes"].get(t, 0)}
    # Blender 5.2+: the lights' transforms come from World properties (View Layer attributes);
    # before, where compat.VIEW_LAYER_LOOKUPS is 0, from drivers in the group (the 0.2 rig)
    # Blender 5.3+: the group also holds the loop part of Eevee's light loop (lighting/loop.py),
    # the same whatever the number of lights
    section = ("lights rig (light loop)" if be.compat().HAS_LIGHT_LOOP
               else "lights rig" if be.compat().VIEW_LAYER_LOOKUPS else "lights rig (drivers)")
    check(section, {"1 point light": one, "3 point lights": three, "per light": per_light})


def _dead_inlined_nodes(material) -> tuple:
    """(nodes, dead nodes) of *material*'s Cycles output once Blender has inlined its groups
    (``Material.inline_shader_nodes``): a dead node reaches no Material Output, yet Cycles
    converts and optimises it, once per material."""
    from phong_nodes.addon.lighting import node_copy  # noqa: PLC0415

    with be.inlined_cycles_tree(material) as tree:
        nodes = tree.nodes
        output = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        return len(nodes), len(nodes) - len(node_copy.upstream(output))


def _material_of(bpy, tree):
    """The Phong material whose lights-group node uses *tree*."""
    return next(m for m in bpy.data.materials
                if m.node_tree and m.node_tree.nodes.get("phong_lights")
                and m.node_tree.nodes["phong_lights"].node_tree is tree)


def _light_group(tree):
    """The light group (``library.rig_light_group``) of the point lights of *tree*."""
    names = {n.node_tree.name for n in tree.nodes if n.name.startswith("light:")}
    assert len(names) == 1, names
    return names.pop()


def test_a_constant_blinn_leaves_no_dead_highlight_in_cycles(bpy_clean):
    """Blender 5.3 (Switch nodes in shader trees): a material whose Blinn is 0 (the default)
    gives Cycles no node of the Blinn-Phong highlight, nor of the blend; with the light
    group that releases before 5.3 write, 5.3's inliner folds the blend but keeps the other
    highlight's nodes: BLEND_DEAD more a light (the node budget: benchmarks/README.md)."""
    import pytest  # noqa: PLC0415

    if library.SWITCH_FEATURE not in be.compat().NODE_FEATURES:
        pytest.skip("shader trees have no Switch node before Blender 5.3")
    tree = _scene_with_point_lights(bpy_clean, 3)
    material = _material_of(bpy_clean, tree)
    total, dead = _dead_inlined_nodes(material)
    from phong_nodes.addon import loader  # noqa: PLC0415

    name = _light_group(tree)
    loader._write(bpy_clean.data.node_groups[name],
                  library.RIG_GROUPS[name])  # the blend, as 5.2 writes it
    blend_total, blend_dead = _dead_inlined_nodes(material)
    be.report(f"[constant Blinn] 3 point lights: {total} inlined nodes, {dead} dead; with "
              f"the blend {blend_total}, {blend_dead} dead")
    assert dead == AMBIENT_DEAD and blend_dead == 3 * BLEND_DEAD + AMBIENT_DEAD
    assert blend_total - total == 3 * BLEND_MORE


#: What the light group as releases before 5.3 write it leaves a light in Cycles on 5.3 where
#: Blinn is 0 and the falloff i0/(αr² + γ): the Blinn-Phong highlight's nodes, dead (they
#: reach no output), and in all (the blend's 7, and r as a length with its multiply-add
#: where 5.3 takes r² as one dot product).
BLEND_DEAD, BLEND_MORE = 5, 8
#: The ambient layer of the converted Principled material (Ka = Kd × scale + offset): dead
#: here, where the World is black (the ambient light 0 folds the ambient term away).
AMBIENT_DEAD = 1


def test_a_file_with_the_former_light_group_gets_the_switch_on_load(bpy_clean, blender_tmp):
    """A file saved where the light group was written without the Switch (the blend, as
    releases before 5.3 write it) gets the Switch on load: the group rewritten in place, the
    lights group's links kept, and Cycles then gets BLEND_MORE nodes a light fewer."""
    import pytest  # noqa: PLC0415

    if library.SWITCH_FEATURE not in be.compat().NODE_FEATURES:
        pytest.skip("shader trees have no Switch node before Blender 5.3")
    from phong_nodes.addon import loader  # noqa: PLC0415

    bpy = bpy_clean
    tree = _scene_with_point_lights(bpy, 3)
    material = _material_of(bpy, tree)
    name = _light_group(tree)
    loader._write(bpy.data.node_groups[name], library.RIG_GROUPS[name])
    former, links = _dead_inlined_nodes(material), len(tree.links)
    names = (material.name, tree.name)
    path = os.path.join(blender_tmp, "former_terms.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    terms = bpy.data.node_groups[name]
    switched = library.VARIANTS[name][library.SWITCH_FEATURE]
    assert terms[loader.STAMP_FINGERPRINT] == switched.fingerprint
    assert len(bpy.data.node_groups[names[1]].links) == links
    total, dead = _dead_inlined_nodes(bpy.data.materials[names[0]])
    assert former[1] == 3 * BLEND_DEAD + AMBIENT_DEAD and dead == AMBIENT_DEAD
    assert former[0] - total == 3 * BLEND_MORE
