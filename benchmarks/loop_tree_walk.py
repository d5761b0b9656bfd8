# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender 5.3's Eevee: a material with light-loop nodes walks every node tree of the file when
its shader is made (no Phong code here: a reproduction for Blender's tracker).

Each case runs in a process of its own: N cubes with their own materials, each material one
of the kinds below, in a file with E unused materials more (fake users); one Eevee F12 (1
sample, 64²) untimed, then one timed.  The kinds:

* ``emission``: Emission → Material Output;
* ``group``: the same Emission inside a node group;
* ``loop``: Light Evaluation (Factor) → Combine Color → Light Accumulation (Diffuse Light) →
  Material Output: Eevee's light loop, as Phong materials use it;
* ``loop_group``: the same inside a node group.

    .venv/bin/python -m phong_nodes.benchmarks.loop_tree_walk            # ~3 min
    .venv/bin/python -m phong_nodes.benchmarks.loop_tree_walk --objects 300 --extra 2000

What it shows (benchmarks/README.md, "Eevee: the light loop's shaders walk the file"):
``GPU_material_from_nodetree`` → ``ntree_exec_begin`` →
``BKE_ntree_update_after_single_tree_change`` on the inlined tree; with light-loop nodes in
it, the update rebuilds the group-user relations of every node tree in ``G.main``
(``get_tree_update_order``), once per material shader.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

KINDS = ("emission", "group", "loop", "loop_group")


def _loop_nodes(tree):
    evaluation = tree.nodes.new("ShaderNodeLightEvaluation")
    combine = tree.nodes.new("ShaderNodeCombineColor")
    accumulation = tree.nodes.new("ShaderNodeLightAccumulation")
    tree.links.new(evaluation.outputs["Factor"], combine.inputs[0])
    tree.links.new(combine.outputs[0], accumulation.inputs["Diffuse Light"])
    return accumulation.outputs["Shader"]


def worker(kind: str, objects: int, extra: int) -> float:
    import bpy  # noqa: PLC0415
    import bmesh  # noqa: PLC0415  (importable once bpy is)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.taa_render_samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 64
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, 0.0, 40.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    light = bpy.data.objects.new("Light", bpy.data.lights.new("Light", "POINT"))
    light.location = (0.0, 0.0, 5.0)
    scene.collection.objects.link(light)
    group = None
    if kind in ("group", "loop_group"):
        group = bpy.data.node_groups.new("Inside", "ShaderNodeTree")
        group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
        output = group.nodes.new("NodeGroupOutput")
        shader = (_loop_nodes(group) if kind == "loop_group"
                  else group.nodes.new("ShaderNodeEmission").outputs[0])
        group.links.new(shader, output.inputs[0])
    for index in range(objects):
        mesh = bpy.data.meshes.new(f"Cube {index:05d}")
        bm = bmesh.new()
        bmesh.ops.create_cube(bm, size=0.5)
        bm.to_mesh(mesh)
        bm.free()
        obj = bpy.data.objects.new(mesh.name, mesh)
        obj.location = (index % 40 - 20.0, index // 40 - 12.0, 0.0)
        scene.collection.objects.link(obj)
        material = bpy.data.materials.new(f"Material {index:05d}")
        material.use_nodes = True
        tree = material.node_tree
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        if group is not None:
            node = tree.nodes.new("ShaderNodeGroup")
            node.node_tree = group
            shader = node.outputs[0]
        elif kind == "loop":
            shader = _loop_nodes(tree)
        else:
            shader = tree.nodes.new("ShaderNodeEmission").outputs[0]
        tree.links.new(shader, out.inputs["Surface"])
        mesh.materials.append(material)
    for index in range(extra):
        bpy.data.materials.new(f"Unused {index:05d}").use_fake_user = True
    bpy.ops.render.render()
    start = time.perf_counter()
    bpy.ops.render.render()
    return time.perf_counter() - start


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--extra", type=int, default=4000)
    parser.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        kind, objects, extra = args.worker
        print("RESULT " + json.dumps(worker(kind, int(objects), int(extra))), flush=True)
        os._exit(0)  # noqa: SLF001  (bpy's exit after Eevee is slow and not measured)
    results = {}
    for kind in KINDS:
        for extra in (0, args.extra):
            run = subprocess.run([sys.executable, "-m", "phong_nodes.benchmarks.loop_tree_walk",
                                  "--worker", kind, str(args.objects), str(extra)],
                                 capture_output=True, text=True, check=True)
            line = [x for x in run.stdout.splitlines() if x.startswith("RESULT ")][-1]
            results[(kind, extra)] = json.loads(line.removeprefix("RESULT "))
        print(f"{kind:11s} F12 {results[(kind, 0)]:.2f} s; with {args.extra} unused materials "
              f"{results[(kind, args.extra)]:.2f} s "
              f"({results[(kind, args.extra)] - results[(kind, 0)]:+.2f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
