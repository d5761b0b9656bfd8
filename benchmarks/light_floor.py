# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 30 item 5: the Cycles cost of each extra light, Phong materials against a
hand-minimal node chain that computes the same point-light Phong colour, side by side in one
process.

    .venv/bin/python -m phong_nodes.benchmarks.light_floor [--lights 1 16] [--repeats 3]
        [--res 512] [--spp 8]

Figure 2's scene (``measure.build_scene``: 5x5 spheres of 32 segments, their own meshes and
materials, point lights, 512², 8 samples, Cycles on the CPU).  Per number of lights: the
Phong scene (Apply Phong Material), the same spheres with the **minimal** material and the
Emission floor (one light).  The minimal material reads the values the Phong scene's lights
group holds (after its drivers ran) and computes, with Cycles' Math and Vector Math nodes,

    min(ambient + Σ_k i0_k/|S_k-P|² · (max(ℓ·n, 0)·kd·Cl⊗Cl_obj
                                        + [ℓ·n > 0]·clamp(r·v, 0, 1)^e·ks·Cl⊗Cl_spec), 1)

with the colour products, the ambient and the strengths folded into constants, r = -reflect(ℓ,
n) (Vector Math REFLECT), 15 nodes per light and one sum (``minimal_nodes``).  It holds only
for what these scenes use: quadratic falloff α = 1 (β = γ = 0), Phong (Blinn 0), no irradiant,
the shading normal and the camera's view vector; the Phong material handles everything else
(the other falloffs, Blinn, a Normal input, ...), so the minimal chain is the floor for this
one case, not a replacement.  The pictures of both are compared (largest difference printed).

Each figure is the median of *repeats* renders after one untimed render per scene (the order
of the scenes rotates).  "extra light" is figure 2's (t(N)/t(1) - 1)/(N - 1) of each
material, and also the seconds of one extra light over the Phong one-light render.
Prints one JSON object (seconds, fractions, node counts, load averages, bpy release).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time

from ..node_groups import library
from .measure import (build_scene, read_image, remove_scene, render, rotated, set_cycles,
                      worker_setup)


def _light_object(node):
    import bpy  # noqa: PLC0415

    return bpy.data.objects[node.name[len("light:"):]]


def _values(material):
    """The values the Phong *material* computes with: per light (position, i0, falloff,
    kd·Cl⊗Cl_obj, ks·Cl⊗Cl_spec), the ambient colour, the exponent."""
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415  (imports bpy)

    tree = material.node_tree
    nodes = tree.nodes
    group = nodes["phong_lights"].node_tree.nodes
    oc = tuple(nodes["phong_object_color"].outputs[0].default_value)[:3]
    sc = tuple(nodes["phong_specular_color"].outputs[0].default_value)[:3]
    exponent = float(nodes["phong_exponent"].outputs[0].default_value)
    if float(nodes["phong_blinn"].outputs[0].default_value) != 0.0:
        raise ValueError("the minimal chain is Phong's (Blinn 0)")
    lights = []
    for light in [n for n in group if n.name.startswith("light:")]:
        if light.node_tree.name not in {library.rig_light_group("seeds", "POINT", "QUADRATIC",
                                                                 shadows, highlight)
                                        for shadows in (False, True)
                                        for highlight in library.HIGHLIGHTS}:
            raise ValueError("the minimal chain is for point lights (i0/(αr²+βr+γ))")
        shading = light  # the lights group's one group a light: its colour and strengths
        falloff = tuple(light.inputs[k].default_value for k in ("Quadratic", "Linear", "Constant"))
        if falloff != (1.0, 0.0, 0.0):
            raise ValueError(f"the minimal chain is for i0/r² (falloff {falloff})")
        lc = tuple(shading.inputs["Light Color"].default_value)[:3]
        kd = shading.inputs["Diffuse Strength"].default_value
        ks = shading.inputs["Specular Strength"].default_value
        lights.append({
            # the light's world location (the Position socket is read from the World)
            "position": tuple(_light_object(light).matrix_world.translation),
            "i0": properties.intensity(_light_object(light).data),  # its own or its Power's
            "diffuse": tuple(kd * a * b for a, b in zip(lc, oc)),
            "specular": tuple(ks * a * b for a, b in zip(lc, sc))})
    ambient = group["ambient"]
    ai = ambient.inputs["Intensity"].default_value
    ac = tuple(ambient.inputs["Light Color"].default_value)[:3]
    return {"lights": lights, "exponent": exponent,
            "ambient": tuple(ai * a * b for a, b in zip(ac, oc))}


def minimal_nodes(tree, values) -> None:
    """Write the minimal chain of *values* (``_values``) into the material tree *tree*."""
    nodes, links = tree.nodes, tree.links
    nodes.clear()

    def node(kind, operation=None, clamp=False):
        new = nodes.new(kind)
        if operation is not None:
            new.operation = operation
        if clamp:
            new.use_clamp = True
        return new

    def vmath(operation):
        return node("ShaderNodeVectorMath", operation)

    geometry = node("ShaderNodeNewGeometry")
    position, normal, view = (geometry.outputs[k] for k in ("Position", "Normal", "Incoming"))
    total = None
    for light in values["lights"]:
        d = vmath("SUBTRACT")
        d.inputs[0].default_value = light["position"]
        links.new(position, d.inputs[1])
        l = vmath("NORMALIZE")
        links.new(d.outputs["Vector"], l.inputs[0])
        rr = vmath("DOT_PRODUCT")
        links.new(d.outputs["Vector"], rr.inputs[0])
        links.new(d.outputs["Vector"], rr.inputs[1])
        i = node("ShaderNodeMath", "DIVIDE")
        i.inputs[0].default_value = light["i0"]
        links.new(rr.outputs["Value"], i.inputs[1])
        ln = vmath("DOT_PRODUCT")
        links.new(l.outputs["Vector"], ln.inputs[0])
        links.new(normal, ln.inputs[1])
        q = vmath("REFLECT")  # ℓ - 2(ℓ·n)n = -r
        links.new(l.outputs["Vector"], q.inputs[0])
        links.new(normal, q.inputs[1])
        qv = vmath("DOT_PRODUCT")
        links.new(q.outputs["Vector"], qv.inputs[0])
        links.new(view, qv.inputs[1])
        rv = node("ShaderNodeMath", "MULTIPLY", clamp=True)  # clamp(r·v, 0, 1)
        links.new(qv.outputs["Value"], rv.inputs[0])
        rv.inputs[1].default_value = -1.0
        spec = node("ShaderNodeMath", "POWER")
        links.new(rv.outputs[0], spec.inputs[0])
        spec.inputs[1].default_value = values["exponent"]
        lam = node("ShaderNodeMath", "MAXIMUM")
        links.new(ln.outputs["Value"], lam.inputs[0])
        lam.inputs[1].default_value = 0.0
        front = node("ShaderNodeMath", "GREATER_THAN")
        links.new(ln.outputs["Value"], front.inputs[0])
        front.inputs[1].default_value = 0.0
        masked = node("ShaderNodeMath", "MULTIPLY")
        links.new(spec.outputs[0], masked.inputs[0])
        links.new(front.outputs[0], masked.inputs[1])
        diffuse = vmath("SCALE")
        diffuse.inputs[0].default_value = light["diffuse"]
        links.new(lam.outputs[0], diffuse.inputs["Scale"])
        both = vmath("MULTIPLY_ADD")  # specular colour · factor + diffuse
        both.inputs[0].default_value = light["specular"]
        links.new(masked.outputs[0], both.inputs[1])
        links.new(diffuse.outputs["Vector"], both.inputs[2])
        color = vmath("SCALE")
        links.new(both.outputs["Vector"], color.inputs[0])
        links.new(i.outputs[0], color.inputs["Scale"])
        if total is None:
            total = color.outputs["Vector"]
        else:
            add = vmath("ADD")
            links.new(total, add.inputs[0])
            links.new(color.outputs["Vector"], add.inputs[1])
            total = add.outputs["Vector"]
    ambient = vmath("ADD")
    links.new(total, ambient.inputs[0])
    ambient.inputs[1].default_value = values["ambient"]
    clamp = vmath("MINIMUM")
    links.new(ambient.outputs["Vector"], clamp.inputs[0])
    clamp.inputs[1].default_value = (1.0, 1.0, 1.0)
    emission = node("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    links.new(clamp.outputs["Vector"], emission.inputs["Color"])
    output = node("ShaderNodeOutputMaterial")
    links.new(emission.outputs["Emission"], output.inputs["Surface"])


def minimal_scene(bpy, phong_scene, name):
    """A copy of *phong_scene*'s spheres, lights and camera whose materials are the minimal
    chain of the values of their Phong materials."""
    from phong_nodes.addon import compat  # noqa: PLC0415

    scene = phong_scene.copy()  # a linked copy: the same objects
    scene.name = name
    scene.world = phong_scene.world
    for collection_object in list(scene.collection.objects):
        scene.collection.objects.unlink(collection_object)
    for obj in phong_scene.collection.objects:
        if obj.type != "MESH":
            scene.collection.objects.link(obj)
            continue
        copy = obj.copy()
        copy.data = obj.data.copy()
        material = copy.data.materials[0]
        minimal = bpy.data.materials.new(f"{name} {obj.name}")
        minimal_nodes(compat.new_material_tree(minimal), _values(material))
        copy.data.materials[0] = minimal
        scene.collection.objects.link(copy)
    return scene


def run(lights, repeats, res, spp) -> dict:
    bpy = worker_setup()
    out = {"lights": lights, "repeats": repeats, "res": res, "spp": spp,
           "bpy": bpy.app.version_string, "load_average": [os.getloadavg()],
           "render_s": {}, "nodes_per_material": {}, "largest_difference": {}}
    warm, _ = build_scene("warm", res=16, grid=1, n_lights=1, material="emission", segments=8)
    set_cycles(warm, 1)
    render(warm)
    remove_scene(warm)
    scenes = {}
    floor, _ = build_scene("emission 1", res=res, grid=5, n_lights=1, material="emission",
                           segments=32)
    scenes["emission:1"] = floor
    for n in lights:
        phong, _ = build_scene(f"phong {n}", res=res, grid=5, n_lights=n, material="phong",
                               segments=32)
        phong.view_layers[0].update()  # the drivers' values, read by the minimal chain
        scenes[f"phong:{n}"] = phong
        scenes[f"minimal:{n}"] = minimal_scene(bpy, phong, f"minimal {n}")
        material = next(o for o in scenes[f"minimal:{n}"].objects
                        if o.type == "MESH").material_slots[0].material
        out["nodes_per_material"][f"minimal:{n}"] = len(material.node_tree.nodes)
    tmp = tempfile.mkdtemp(prefix="phong_light_floor_")
    for key, scene in scenes.items():
        set_cycles(scene, spp)
        bpy.context.window.scene = scene
        render(scene, os.path.join(tmp, f"{key.replace(':', '_')}.png"))  # untimed: the sync
    for n in lights:
        a = read_image(os.path.join(tmp, f"phong_{n}.png"))
        b = read_image(os.path.join(tmp, f"minimal_{n}.png"))
        out["largest_difference"][str(n)] = float(abs(a - b).max())
    keys = list(scenes)
    for repeat in range(repeats):
        for key in rotated(keys, repeat):
            bpy.context.window.scene = scenes[key]
            out["render_s"].setdefault(key, []).append(render(scenes[key]))
    out["load_average"].append(os.getloadavg())
    med = {key: statistics.median(times) for key, times in out["render_s"].items()}
    out["median_s"] = med
    first, last = lights[0], lights[-1]
    if last > first:
        out["extra_light_fraction"] = {
            kind: (med[f"{kind}:{last}"] / med[f"{kind}:{first}"] - 1) / (last - first)
            for kind in ("phong", "minimal")}
        out["extra_light_over_phong_one_light"] = {
            kind: (med[f"{kind}:{last}"] - med[f"{kind}:{first}"]) / (last - first)
            / med[f"phong:{first}"] for kind in ("phong", "minimal")}
        out["extra_light_seconds"] = {
            kind: (med[f"{kind}:{last}"] - med[f"{kind}:{first}"]) / (last - first)
            for kind in ("phong", "minimal")}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lights", type=int, nargs="+", default=[1, 16])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--res", type=int, default=512)
    parser.add_argument("--spp", type=int, default=8)
    args = parser.parse_args(argv)
    started = time.perf_counter()
    result = run(sorted(args.lights), args.repeats, args.res, args.spp)
    result["seconds"] = time.perf_counter() - started
    print(json.dumps(result, indent=1), flush=True)
    sys.stderr.flush()
    os._exit(0)  # skip bpy's clean-up at exit


if __name__ == "__main__":
    sys.exit(main())
