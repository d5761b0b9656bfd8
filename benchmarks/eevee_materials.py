# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 30 item 4: a full Eevee render (F12) of many objects with their own materials,
Principled against Phong, side by side in one run (a process per case).

    .venv/bin/python -m phong_nodes.benchmarks.eevee_materials [--objects 1000] [--lights 4]
        [--repeats 2] [--renders 1] [--cases principled,phong,phong_0_3,...]

The scene is figure 6's artist scene (``measure.artist_scene``: cubes with their own mesh and
Principled material, 4 lights cycling point, sun, spot, point) seen from above by an
orthographic camera, 256² pixels, Eevee at 1 sample; each case is built and rendered in a
process of its own, started one after the other by this one (the order of the cases
alternates from repeat to repeat), and each figure is the wall time of
``bpy.ops.render.render`` after one untimed render (the shader compiles and the first sync
are out of it: every F12 render pays the rest again).  Cases:

* ``principled``: the artist's scene as it is;
* ``emission``: each cube its own Emission material (one node: the floor);
* ``phong``: after Apply Phong Material (this version; on Blender 5.3+ its Eevee side is the
  light loop, ``addon/lighting/loop.py``);
* ``phong_lights_group``: the same with the lights group in Eevee too (on 5.3+ the recipe of
  5.2: what the term passes switch to; before 5.3 the same as ``phong``);
* ``phong_noaov``: the same without the five AOV outputs of each material;
* ``phong_ungrouped``: the lights group with every nested group node replaced by its nodes
  (the same nodes, no nesting; the lights' drivers dropped, their values frozen);
* ``phong_0_3``: the lights group as version 0.3 built it, a Phong Shading per light summed
  with Phong Color Add (``write_per_light_shading``; same light groups and values, the
  drivers dropped): the layout this version replaced, measured beside it;
* ``phong_lights0``, ``phong_lights1``: Apply with no light / one light (a smaller group);
* ``phong_noshadow``: ``phong`` with the cubes' shadow visibility off (not a fix: it shows
  what one of the passes Eevee builds for each material costs).

Prints one JSON object: seconds per case and repeat, nodes of each case's material once its
groups are expanded, ratios to Principled, load averages, bpy release.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import time

from .measure import (apply_phong, artist_scene, render, set_eevee, simple_material,
                      worker_setup)

CASES = ("principled", "emission", "phong", "phong_lights_group", "phong_noaov",
         "phong_ungrouped", "phong_0_3", "phong_lights0", "phong_lights1", "phong_noshadow")


# -- the scene ----------------------------------------------------------------------

def _camera(bpy, scene, count):
    cols = max(1, math.ceil(math.sqrt(count)))
    camera = bpy.data.objects.new(f"{scene.name} camera", bpy.data.cameras.new(scene.name))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 3.0 * cols + 3.0
    camera.location = (1.5 * (cols - 1), 1.5 * (cols - 1), 50.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x = scene.render.resolution_y = 256
    scene.render.resolution_percentage = 100


def build(bpy, case, objects, n_lights):
    """The scene of *case*; returns (scene, one of its materials)."""
    if case == "phong_lights0":
        n_lights = 0
    elif case == "phong_lights1":
        n_lights = 1
    scene, meshes, _lights = artist_scene(case, objects, n_lights)
    bpy.context.window.scene = scene
    _camera(bpy, scene, objects)
    set_eevee(scene, 1)
    if case == "emission":
        for index, obj in enumerate(meshes):
            material = simple_material(f"{case} {index}", "emission")
            material.node_tree.nodes["Emission"].inputs["Color"].default_value = (
                (index % 7) / 7, (index % 11) / 11, (index % 13) / 13, 1.0)
            obj.data.materials[0] = material
    elif case != "principled":
        if case == "phong_lights_group":  # the groups of 5.2: no loop part
            from phong_nodes.addon.lighting import rig  # noqa: PLC0415

            rig.wants_loop = lambda _scene: False
        apply_phong(bpy, scene, meshes)
        scene.view_layers[0].update()  # the drivers' values, frozen by the two cases below
        materials = {slot.material for obj in meshes for slot in obj.material_slots}
        lights_group = next(iter(materials)).node_tree.nodes["phong_lights"].node_tree
        if case == "phong_noaov":
            for material in materials:
                tree = material.node_tree
                for node in [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputAOV"]:
                    tree.nodes.remove(node)
        elif case == "phong_ungrouped":
            ungroup_all(lights_group)
        elif case == "phong_0_3":
            write_per_light_shading(lights_group)
        elif case == "phong_noshadow":  # Eevee then builds no shadow pass of the materials
            for obj in meshes:
                obj.visible_shadow = False
    scene.view_layers[0].update()
    material = meshes[0].material_slots[0].material
    return scene, material


def eevee_nodes(material):
    """The nodes Eevee compiles of *material* once Blender has inlined its groups and folded
    its constants (``Material.inline_shader_nodes``, Blender 5+): the tree of a copy whose
    only Material Output is the one Eevee uses (of target EEVEE, else ALL), AOVs kept; None
    before 5.0."""
    if not hasattr(material, "inline_shader_nodes"):
        return None
    copy = material.copy()
    try:
        outputs = [n for n in copy.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
        eevee = next((n for n in outputs if n.target == "EEVEE"), None) or next(
            (n for n in outputs if n.target == "ALL"), None)
        for node in outputs:
            if node is not eevee:
                copy.node_tree.nodes.remove(node)
        if eevee is not None:
            eevee.target = "ALL"
        inlined = copy.inline_shader_nodes()
        return len(inlined.node_tree.nodes)
    finally:
        import bpy  # noqa: PLC0415

        bpy.data.materials.remove(copy)


def expanded_nodes(tree) -> int:
    """Nodes of *tree* once every group node is replaced by its nodes (recursively)."""
    count = 0
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
            count += expanded_nodes(node.node_tree)
        elif node.bl_idname not in ("NodeFrame", "NodeGroupInput", "NodeGroupOutput"):
            count += 1
    return count


# -- the lights group without nesting (same nodes) ---------------------------------------

_PROPS = ("operation", "attribute_type", "attribute_name", "data_type", "use_clamp")


def _value(socket):
    value = socket.default_value
    return tuple(value) if hasattr(value, "__len__") else value


def _fit(value, target):
    """*value* (a float or a 3 / 4-tuple) as *target*'s default value."""
    want = target.default_value
    if not hasattr(want, "__len__"):
        return value if not isinstance(value, tuple) else sum(value[:3]) / 3.0
    if not isinstance(value, tuple):
        value = (value,) * 3
    return tuple(value[:3]) if len(want) == 3 else (*value[:3], 1.0)


def ungroup_all(tree) -> None:
    """Replace every group node of *tree* by its nodes, recursively (drivers dropped)."""
    if tree.animation_data is not None:
        tree.animation_data_clear()
    while True:
        groups = [n for n in tree.nodes if n.bl_idname == "ShaderNodeGroup" and n.node_tree]
        if not groups:
            return
        for group in groups:
            _ungroup(tree, group)


def _ungroup(tree, group) -> None:
    inner = group.node_tree
    copies = {}
    for node in inner.nodes:
        if node.bl_idname in ("NodeGroupInput", "NodeGroupOutput", "NodeFrame"):
            continue
        new = tree.nodes.new(node.bl_idname)
        for prop in _PROPS:
            if hasattr(node, prop):
                setattr(new, prop, getattr(node, prop))
        if node.bl_idname == "ShaderNodeGroup":
            new.node_tree = node.node_tree
        for index, socket in enumerate(node.inputs):
            if hasattr(socket, "default_value"):
                new.inputs[index].default_value = socket.default_value
        copies[node.name] = new
    inputs = {s.identifier: s for s in group.inputs}

    def source(link):
        if link.from_node.bl_idname == "NodeGroupInput":
            socket = inputs[link.from_socket.identifier]
            return socket.links[0].from_socket if socket.is_linked else _value(socket)
        node = link.from_node
        return copies[node.name].outputs[list(node.outputs).index(link.from_socket)]

    results = {}
    for link in inner.links:
        src = source(link)
        if link.to_node.bl_idname == "NodeGroupOutput":
            results[link.to_socket.identifier] = src
            continue
        node = link.to_node
        target = copies[node.name].inputs[list(node.inputs).index(link.to_socket)]
        if isinstance(src, (float, tuple)):
            target.default_value = _fit(src, target)
        else:
            tree.links.new(src, target)
    for output in group.outputs:
        src = results.get(output.identifier)
        for link in list(output.links):
            target = link.to_socket
            if src is None:
                continue
            if isinstance(src, (float, tuple)):
                tree.links.remove(link)
                target.default_value = _fit(src, target)
            else:
                tree.links.new(src, target)
    tree.nodes.remove(group)


# -- the lights group of version 0.3 (a Phong Shading per light) ---------------------------

def write_per_light_shading(lights_group) -> None:
    """Rewrite *lights_group* (a seeds'-model rig) as version 0.3 built it: per light its
    light group of the library (Phong Point / Directional / Spot Light) and a Phong Shading
    (ambient off, the irradiant on the first only) instead of the lights group's one group a
    light, no Phong Surface, the Color the Phong Color Add chain of the ambient and the
    shadings' colours, Diffuse and Specular the sums of their terms.  The same Attribute
    nodes and values; the drivers dropped (the values they wrote stay)."""
    from phong_nodes.addon import loader  # noqa: PLC0415
    from phong_nodes.node_groups import models  # noqa: PLC0415

    tree = lights_group
    nodes, links = tree.nodes, tree.links
    if tree.animation_data is not None:
        tree.animation_data_clear()
    group_in = next(n for n in nodes if n.bl_idname == "NodeGroupInput")
    group_out = next(n for n in nodes if n.bl_idname == "NodeGroupOutput")
    kinds = {f"{models.MODELS['seeds'].rig} {word}": kind
             for kind, word in (("POINT", "Point"), ("SPOT", "Spot"), ("SUN", "Sun"))}
    rigged = [n for n in nodes if n.name.startswith("light:")]
    shadings = []

    def copy_inputs(old, new):
        for socket in new.inputs:
            source = old.inputs.get(socket.name)
            if socket.name == "Direction" and "Reversed Axis" in old.inputs:
                axis_from(old, socket)  # 0.3 read the -Z axis; this version its unit +Z
                continue
            if source is None:
                continue
            if source.is_linked and source.links[0].from_node.bl_idname != "ShaderNodeGroup":
                links.new(source.links[0].from_socket, socket)  # Attributes, the group input
            elif not source.is_linked:
                socket.default_value = source.default_value

    def axis_from(old, socket):
        """*socket* (a library light group's Direction) = the -Z axis of *old*'s light: its
        World copy of kind AXIS, as 0.3 read it, where *old* reads a copy, else the value."""
        source = old.inputs["Reversed Axis"]
        if not source.is_linked:
            socket.default_value = [-v for v in source.default_value]
            return
        import bpy  # noqa: PLC0415

        from phong_nodes.addon.lighting import world_copies  # noqa: PLC0415

        obj = bpy.data.objects[old.name.removeprefix("light:")]
        world = bpy.context.scene.world
        key = world_copies.world_key(obj, "AXIS")
        world_copies.write(world, key, obj, "AXIS")
        attribute = nodes.new("ShaderNodeAttribute")
        attribute.attribute_type, attribute.attribute_name = "VIEW_LAYER", key
        links.new(attribute.outputs["Vector"], socket)

    for index, old in enumerate(rigged):
        kind = kinds[old.node_tree.name.split(" (")[0].removesuffix(" with Shadow")]
        light = nodes.new("ShaderNodeGroup")
        light.node_tree, _status = loader.ensure_group(models.MODELS["seeds"].light_groups[kind])
        copy_inputs(old, light)
        new = nodes.new("ShaderNodeGroup")
        new.node_tree, _status = loader.ensure_group("Phong Shading")
        copy_inputs(old, new)
        links.new(light.outputs["Light Vector"], new.inputs["Light Vector"])
        links.new(light.outputs["Intensity"], new.inputs["Light Intensity"])
        for name in ("Object Color", "Specular Color", "Normal", "View Vector"):
            links.new(group_in.outputs[name], new.inputs[name])
        if index == 0:
            links.new(group_in.outputs["Irradiant Color"], new.inputs["Irradiant Color"])
        else:
            new.inputs["Irradiant Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        new.inputs["Ambient Intensity"].default_value = 0.0
        shadings.append(new)
    for node in [n for n in nodes if n in rigged or n.name.startswith((
            "surface", "color", "diffuse:", "specular:", "plain "))]:
        nodes.remove(node)
    color = nodes["ambient"].outputs["Color"]
    for shading in shadings:
        add = nodes.new("ShaderNodeGroup")
        add.node_tree, _status = loader.ensure_group("Phong Color Add")
        links.new(color, add.inputs["A"])
        links.new(shading.outputs["Color"], add.inputs["B"])
        color = add.outputs["Color"]
    links.new(color, group_out.inputs["Color"])
    links.new(color, nodes["emission"].inputs["Color"])
    cycles = group_out.inputs.get("Cycles Shader")  # 5.2+: the shadowed shader; 0.3 had none
    if cycles is not None:
        links.new(nodes["emission"].outputs["Emission"], cycles)
    for term in ("Diffuse", "Specular"):
        total = None
        for shading in shadings:
            if total is None:
                total = shading.outputs[term]
                continue
            add = nodes.new("ShaderNodeVectorMath")
            add.operation = "ADD"
            links.new(total, add.inputs[0])
            links.new(shading.outputs[term], add.inputs[1])
            total = add.outputs["Vector"]
        if total is not None:
            links.new(total, group_out.inputs[term])


# -- the picture -----------------------------------------------------------------------------

def largest_difference(objects=16, n_lights=4, case="phong_0_3", engine="cycles") -> float:
    """The largest pixel difference between the render of the ``phong`` scene and that of
    *case* (16-bit PNGs, *engine* "cycles" or "eevee"), in this process."""
    import tempfile  # noqa: PLC0415

    from .measure import read_image, set_cycles  # noqa: PLC0415

    bpy = worker_setup()
    folder = tempfile.mkdtemp(prefix="phong_eevee_materials_")
    images = []
    for name in ("phong", case):
        scene, _material = build(bpy, name, objects, n_lights)
        if engine == "cycles":
            set_cycles(scene, 1)
        bpy.context.window.scene = scene
        path = os.path.join(folder, f"{name}.png")
        render(scene, path)
        images.append(read_image(path))
    return float(abs(images[0] - images[1]).max())


# -- the run -------------------------------------------------------------------------------

def worker(case, objects, n_lights, renders) -> dict:
    """One process, one case: its scene built, rendered once untimed (shader compiles, the
    first sync), then *renders* timed renders."""
    bpy = worker_setup()
    scene, material = build(bpy, case, objects, n_lights)
    bpy.context.window.scene = scene
    render(scene)
    return {"render_s": [render(scene) for _ in range(renders)],
            "expanded_nodes": expanded_nodes(material.node_tree),
            "eevee_nodes": eevee_nodes(material)}


def run(objects: int, n_lights: int, repeats: int, cases, renders: int = 1) -> dict:
    """Each case in a process of its own, the order of the cases alternating from repeat to
    repeat; the figure of a case is the median of its timed renders over the repeats.
    (A first version rendered every case's scene in one file: at 300 objects Principled
    took 5.1-6.3 s there beside six other scenes, load 2.1-3.7, against 4.1-4.3 s for
    1,000 cubes alone in a process, load 2.2-4.7; at 1,000 objects it did not finish two
    repeats of seven cases in 15 minutes.  Not investigated further.)"""
    import subprocess  # noqa: PLC0415

    out = {"objects": objects, "lights": n_lights, "repeats": repeats, "renders": renders,
           "load_average": [os.getloadavg()], "render_s": {}, "expanded_nodes": {},
           "eevee_nodes": {}}
    for repeat in range(repeats):
        for case in cases if repeat % 2 == 0 else cases[::-1]:
            proc = subprocess.run(
                [sys.executable, "-m", "phong_nodes.benchmarks.eevee_materials", "--worker",
                 case, "--objects", str(objects), "--lights", str(n_lights),
                 "--renders", str(renders)], capture_output=True, text=True)
            line = [x for x in proc.stdout.splitlines() if x.startswith("RESULT ")]
            if proc.returncode != 0 or not line:
                raise RuntimeError(proc.stdout[-2000:] + proc.stderr[-2000:])
            result = json.loads(line[-1][7:])
            out["bpy"] = result["bpy"]
            out["render_s"].setdefault(case, []).extend(result["render_s"])
            out["expanded_nodes"][case] = result["expanded_nodes"]
            out["eevee_nodes"][case] = result.get("eevee_nodes")
            out["load_average"].append(os.getloadavg())
    medians = {case: statistics.median(times) for case, times in out["render_s"].items()}
    out["median_s"] = medians
    if "principled" in medians:
        out["ratio_to_principled"] = {case: t / medians["principled"] for case, t in medians.items()}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--lights", type=int, default=4)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--renders", type=int, default=1, help="timed renders per process")
    parser.add_argument("--cases", default="principled,phong,phong_0_3,phong_lights0")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        result = worker(args.worker, args.objects, args.lights, args.renders)
        import bpy  # noqa: PLC0415

        result["bpy"] = bpy.app.version_string
        print("RESULT " + json.dumps(result), flush=True)
        os._exit(0)  # skip bpy's clean-up at exit (slow, and it can crash after Eevee)
    cases = args.cases.split(",")
    unknown = set(cases) - set(CASES)
    if unknown:
        parser.error(f"unknown cases {sorted(unknown)}; choose from {', '.join(CASES)}")
    started = time.perf_counter()
    result = run(args.objects, args.lights, args.repeats, cases, args.renders)
    result["seconds"] = time.perf_counter() - started
    print(json.dumps(result, indent=1), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
