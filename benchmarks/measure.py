# SPDX-License-Identifier: GPL-3.0-or-later
"""The measuring half of the benchmarks: worker processes that import ``bpy``.

``run.py`` starts each worker as ``python -m phong_nodes.benchmarks.measure NAME PARAMS``
(PARAMS: JSON with the configuration and the file to write the result to):

* ``cycles``: figures 1, 2 (Cycles), 4 and 5 in one warm process;
* ``eevee``: first and second Eevee render of each case (cold shader caches when run.py
  points them at an empty folder);
* ``artist``: figure 6, one artist scene size (issue 10's lights at scale).

Everything here returns raw seconds and counts; ``analyse.py`` turns them into figures.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
import tempfile
import time

THRESHOLD = 1.0 / 255.0
OBJECT_COLOR = (1.0, 0.246, 0.091)  # 0xFF8855 of seed 004 slide 50, linear


def _bpy():
    import bpy  # noqa: PLC0415

    return bpy


def worker_setup():
    """Import bpy (with a throw-away user folder) and register the extension from source."""
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="phong_bench_res_"))
    bpy = _bpy()
    import phong_nodes  # noqa: PLC0415  (the source tree, linked by tools/phong.sh setup)

    phong_nodes.register()
    return bpy


def uv_sphere(name, segments):
    from phong_nodes.addon.scene import meshes  # noqa: PLC0415

    return meshes.uv_sphere(name, 1.0, segments, max(segments // 2, 3))


def build_scene(name, *, res, grid, n_lights, material, segments=32, shared_mesh=False,
                n_objects=None, select=True):
    """Spheres on a grid in front of an orthographic camera, lit by *n_lights* point lights.

    material: 'phong' (apply_material; timed), 'emission' (the floor: Emission of the object
    colour, strength 1), 'principled' (Principled BSDF of that colour, lit by the lights).
    Each object has its own mesh and material unless *shared_mesh* (linked duplicates: one
    mesh, one material).  Returns (scene, apply_material seconds or None).
    """
    bpy = _bpy()
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415

    scene = bpy.data.scenes.new(name)
    scene.render.resolution_x = scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = False
    world = bpy.data.worlds.new(name)
    world.color = (0.0, 0.0, 0.0)
    background = world.node_tree.nodes.get("Background") if world.node_tree else None
    if background is not None:
        background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        background.inputs["Strength"].default_value = 0.0
    scene.world = world

    count = n_objects if n_objects is not None else grid * grid
    cols = max(1, math.ceil(math.sqrt(count)))
    rows = math.ceil(count / cols)
    spacing = 2.2
    objects = []
    shared = uv_sphere(f"{name} sphere", segments) if shared_mesh else None
    for index in range(count):
        mesh = shared if shared_mesh else uv_sphere(f"{name} sphere {index}", segments)
        obj = bpy.data.objects.new(f"{name} {index:04d}", mesh)
        obj.location = ((index % cols - (cols - 1) / 2) * spacing, 0.0,
                        (index // cols - (rows - 1) / 2) * spacing)
        scene.collection.objects.link(obj)
        objects.append(obj)

    camera = bpy.data.objects.new(f"{name} camera", bpy.data.cameras.new(f"{name} camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = max(cols, rows) * spacing
    camera.data.clip_end = 1000.0
    camera.location = (0.0, -20.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    extent = max(cols, rows) * spacing / 2
    for k in range(n_lights):
        angle = 2 * math.pi * (k + 0.125) / n_lights
        data = bpy.data.lights.new(f"{name} light {k}", "POINT")
        data.use_shadow = False  # the figures compare the model without shadows (add_light)
        data.energy = 4000.0 * extent * extent / 16 / n_lights  # Principled: similar exposure
        data.shadow_soft_size = 0.25
        properties.write_light(data, {"intensity": 2.0 * (extent + 4) ** 2 / n_lights})
        light = bpy.data.objects.new(f"{name} light {k}", data)
        light.location = (extent * math.cos(angle), -6.0, extent * math.sin(angle) + 2.0)
        scene.collection.objects.link(light)

    build_seconds = None
    if material == "phong":
        build_seconds = apply_phong(bpy, scene, objects)
        for mat in {slot.material for obj in objects for slot in obj.material_slots}:
            mat.node_tree.nodes["phong_object_color"].outputs[0].default_value = (*OBJECT_COLOR, 1)
    else:
        mats = {}
        for obj in objects:
            key = obj.data.name
            if key not in mats:
                mats[key] = simple_material(f"{name} {material} {len(mats)}", material)
                obj.data.materials.append(mats[key])
    return scene, build_seconds


def simple_material(name, kind):
    bpy = _bpy()
    from phong_nodes.addon import compat  # noqa: PLC0415

    mat = bpy.data.materials.new(name)
    tree = compat.new_material_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    if kind == "emission":
        node = tree.nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = (*OBJECT_COLOR, 1.0)
        node.inputs["Strength"].default_value = 1.0
        tree.links.new(node.outputs["Emission"], out.inputs["Surface"])
    elif kind == "principled":
        node = tree.nodes.new("ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (*OBJECT_COLOR, 1.0)
        node.inputs["Roughness"].default_value = 0.3
        tree.links.new(node.outputs["BSDF"], out.inputs["Surface"])
    else:
        raise ValueError(kind)
    return mat


def set_cycles(scene, samples, seed=0):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = seed
    cycles.use_animated_seed = False


def set_eevee(scene, samples):
    from phong_nodes.addon import compat  # noqa: PLC0415

    scene.render.engine = compat.eevee_engine()
    scene.eevee.taa_render_samples = samples


def render(scene, path=None):
    """Render *scene* (PNG 16-bit to *path* when given); returns the wall-clock seconds."""
    bpy = _bpy()
    from phong_nodes.addon import compat  # noqa: PLC0415

    if path is not None:
        compat.set_png(scene.render.image_settings)
        scene.render.image_settings.color_depth = "16"
        scene.render.filepath = path
    start = time.perf_counter()
    with bpy.context.temp_override(scene=scene):
        bpy.ops.render.render(write_still=path is not None, scene=scene.name)
    return time.perf_counter() - start


def read_image(path):
    import numpy as np  # noqa: PLC0415
    import OpenImageIO as oiio  # noqa: PLC0415

    buf = oiio.ImageBuf(path)
    return np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)[..., :3]


def rmse(a, b):
    import numpy as np  # noqa: PLC0415

    return float(np.sqrt(np.mean((a - b) ** 2)))


def remove_scene(scene):
    bpy = _bpy()
    objects = list(scene.collection.objects)
    meshes = {o.data for o in objects if o.type == "MESH"}
    lights = {o.data for o in objects if o.type == "LIGHT"}
    materials = {m for me in meshes for m in me.materials if m is not None}
    world = scene.world
    doomed = [scene, *objects, *meshes, *lights, *materials]
    if world is not None:
        doomed.append(world)
    bpy.data.batch_remove(doomed)  # one pass: removing 1000 objects one by one is O(N^2)


def rotated(items, r):
    """Order of the cases in repeat *r*: rotated so that no case always runs first."""
    r %= len(items)
    return list(items[r:]) + list(items[:r])


# --------------------------------------------------------------------- Cycles worker

def worker_cycles(cfg):
    """Figures 1, 2 (Cycles), 4 and 5 in one warm process."""
    out = {}
    reps = cfg["repeats"]

    # warm-up: loads the Cycles kernels once
    scene, _ = build_scene("warm", res=16, grid=1, n_lights=1, material="emission", segments=8)
    set_cycles(scene, 1)
    render(scene)
    remove_scene(scene)

    # 1 + 2: node cost and light scaling, same sphere grid
    section = time.perf_counter()
    cases = [("emission", 1)] + [("phong", n) for n in cfg["lights"]]
    scenes = {}
    builds = {}
    for material, n in cases:
        scene, build = build_scene(f"{material} {n}", res=cfg["cycles_res"], grid=cfg["grid"],
                                   n_lights=n, material=material, segments=cfg["segments"])
        set_cycles(scene, cfg["cycles_spp"])
        scenes[(material, n)] = scene
        builds[(material, n)] = build
        render(scene)  # first render: syncs the scene (not timed)
    times = {case: [] for case in cases}
    for r in range(reps):
        for case in rotated(cases, r):
            times[case].append(render(scenes[case]))
    for scene in scenes.values():
        remove_scene(scene)
    out["section_seconds"] = {"lights": time.perf_counter() - section}
    out["cycles_times"] = {f"{m}:{n}": t for (m, n), t in times.items()}
    out["apply_material_seconds"] = {f"{m}:{n}": b for (m, n), b in builds.items() if b}

    # 4: quality per second at a small resolution
    section = time.perf_counter()
    out["quality"] = quality(cfg)
    out["section_seconds"]["quality"] = time.perf_counter() - section

    # 5: scale, one material shared by linked duplicates
    section = time.perf_counter()
    out["scale"] = scale(cfg)
    out["section_seconds"]["scale"] = time.perf_counter() - section
    return out


def quality(cfg):
    """RMSE against the material's own reference render, as a function of the sample count.

    Against a reference of N_ref samples the measured RMSE includes the reference's own
    noise: for an unbiased renderer rmse^2(N) = s^2 (1/N + 1/N_ref).  The criterion "RMSE
    below 1/255" is applied to the noise of the test render alone,
    rmse * sqrt(N_ref / (N + N_ref)) (without the correction no sample count up to N_ref
    could pass: two 4096-spp renders of the Principled scene already differ by more than
    1/255).  A power law rmse_noise ~ N^-p fitted to two probe renders predicts the sample
    count N*; N* is rendered and checked, and raised while it still misses (at most 4
    renders).  The figure is the time of the render that passed.
    """
    tmp = tempfile.mkdtemp(prefix="phong_bench_q_")
    res = cfg["quality_res"]
    n_ref = cfg["quality_ref_spp"]
    result = {}

    def measure(scene, ref, samples, seed, tag):
        path = os.path.join(tmp, f"{tag}.png")
        set_cycles(scene, samples, seed=seed)
        seconds = render(scene, path)
        error = rmse(read_image(path), ref)
        corrected = error * math.sqrt(n_ref / (samples + n_ref))
        return {"spp": samples, "rmse": error, "rmse_noise": corrected, "seconds": seconds}

    try:
        for material in ("principled", "phong"):
            scene, _ = build_scene(f"q {material}", res=res, grid=cfg["grid"], n_lights=1,
                                   material=material, segments=cfg["segments"])
            ref_path = os.path.join(tmp, f"{material}_ref.png")
            set_cycles(scene, n_ref, seed=1000)
            render(scene)  # sync once, untimed
            ref_seconds = render(scene, ref_path)
            ref = read_image(ref_path)
            repeats = []
            for r in range(cfg["repeats"]):
                seed = r + 1
                probes = [measure(scene, ref, n, seed, f"{material}_{r}_{n}")
                          for n in cfg["quality_probe_spp"]]
                # rmse_noise ~ N^-p: p = 1/2 for path-tracing noise, more for the
                # anti-aliasing of a noise-free shader (stratified samples)
                (n1, e1), (n2, e2) = [(p["spp"], p["rmse_noise"]) for p in probes[-2:]]
                slope = min(max(math.log(e1 / e2) / math.log(n2 / n1), 0.5), 1.5)
                # aim 5% above the prediction, so that one render usually settles it
                target = max(1, math.ceil(n2 * (e2 / THRESHOLD) ** (1 / slope) * 1.05))
                checks = []
                for _attempt in range(4):
                    target = min(target, cfg["quality_max_spp"])
                    check = measure(scene, ref, target, seed, f"{material}_{r}_t{target}")
                    checks.append(check)
                    if check["rmse_noise"] < THRESHOLD or target >= cfg["quality_max_spp"]:
                        break
                    target = math.ceil(target * (check["rmse_noise"] / THRESHOLD)
                                       ** (1 / slope) * 1.05)
                converged = checks[-1]
                one = probes[0] if probes[0]["spp"] == 1 else measure(scene, ref, 1, seed,
                                                                         f"{material}_{r}_1")
                repeats.append({"probes": probes, "slope": slope, "checks": checks,
                                "converged": converged,
                                "reached": converged["rmse_noise"] < THRESHOLD,
                                "one_spp": one})
            result[material] = {"reference_spp": n_ref, "reference_seconds": ref_seconds,
                                "mean_value": float(ref.mean()), "repeats": repeats}
            remove_scene(scene)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return result


def _scale_pair(cfg, tag, r, shared_mesh):
    """The Phong and the Emission scene of figure 5 side by side: apply_material seconds,
    Phong materials made, and each scene's first render (scene sync included)."""
    scenes, out = {}, {}
    for material in ("phong", "emission"):
        scene, build = build_scene(f"{tag} {material}", res=cfg["scale_res"], grid=0,
                                   n_lights=1, material=material, n_objects=cfg["scale_objects"],
                                   segments=cfg["scale_segments"], shared_mesh=shared_mesh)
        set_cycles(scene, cfg["scale_spp"])
        if build is not None:
            out["apply"] = build
            objects = [o for o in scene.collection.objects if o.type == "MESH"]
            out["phong_materials"] = len({s.material for o in objects for s in o.material_slots})
        scenes[material] = scene
    for material in rotated(["phong", "emission"], r):
        out[material] = render(scenes[material])
    for scene in scenes.values():
        remove_scene(scene)
    return out


def scale(cfg):
    """N objects, 1 light: linked duplicates sharing one material (build with apply_material;
    render Phong vs Emission), and the same number of objects with their own meshes and
    materials, so apply_material makes N Phong materials."""
    n = cfg["scale_objects"]
    out = {"objects": n, "apply_seconds": [], "phong_render": [],
           "emission_render": [], "distinct_apply_seconds": [], "distinct_phong_render": [],
           "distinct_emission_render": []}
    for r in range(cfg["repeats"]):
        shared = _scale_pair(cfg, f"s{r}", r, shared_mesh=True)
        out["apply_seconds"].append(shared["apply"])
        out["phong_materials"] = shared["phong_materials"]
        out["phong_render"].append(shared["phong"])
        out["emission_render"].append(shared["emission"])
        if cfg["scale_distinct"]:
            distinct = _scale_pair(cfg, f"d{r}", r, shared_mesh=False)
            out["distinct_apply_seconds"].append(distinct["apply"])
            out["distinct_phong_render"].append(distinct["phong"])
            out["distinct_emission_render"].append(distinct["emission"])
    return out


# --------------------------------------------------------------------- artist-scale worker

ARTIST_LIGHTS = ("POINT", "SUN", "SPOT", "POINT")  # the light mix of issue 10's table
CUBE = ([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
         (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)],
        [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)])


def apply_phong(bpy, scene, meshes) -> float:
    """Apply Phong Material to *meshes*, selected in *scene*'s first view layer; returns the
    seconds of the operator alone (the selection not timed); RuntimeError unless the operator
    finishes."""
    view_layer = scene.view_layers[0]
    for obj in meshes:
        obj.select_set(True, view_layer=view_layer)
    start = time.perf_counter()
    with bpy.context.temp_override(scene=scene, view_layer=view_layer, selected_objects=meshes):
        result = bpy.ops.phong.apply_material()
    seconds = time.perf_counter() - start
    if result != {"FINISHED"}:
        raise RuntimeError(f"apply_material returned {result}")
    return seconds


#: Environment variable: set (to anything but "" or "0"), ``artist_scene`` builds the scene of
#: issue 43's speed goals (``shadow_speed.py``): every light casts shadows and the cubes stand
#: on a floor of their own (its own Principled material: Phong too after Apply).  An
#: environment variable so that the child processes of ``light_move --files`` build it too.
SHADOWS_ENV = "PHONG_BENCH_SHADOWS"


def shadows_wanted() -> bool:
    return os.environ.get(SHADOWS_ENV, "") not in ("", "0")


def artist_scene(name, n_objects, n_lights):
    """An artist's scene: *n_objects* cubes, each with its own mesh and its own Principled
    material (one colour each), lit by *n_lights* lights cycling point, sun, spot, point;
    with ``SHADOWS_ENV`` set, the lights cast shadows and a floor is the last object."""
    bpy = _bpy()
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415

    scene = bpy.data.scenes.new(name)
    template = simple_material(f"{name} principled", "principled")
    cols = max(1, math.ceil(math.sqrt(n_objects)))
    objects = []
    for index in range(n_objects):
        mesh = bpy.data.meshes.new(f"{name} cube {index}")
        mesh.from_pydata(*CUBE[:1], [], CUBE[1])
        material = template if index == 0 else template.copy()
        material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (
            (index % 7) / 7, (index % 11) / 11, (index % 13) / 13, 1.0)
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"{name} {index:05d}", mesh)
        obj.location = (3.0 * (index % cols), 3.0 * (index // cols), 0.0)
        scene.collection.objects.link(obj)
        objects.append(obj)
    lights = [add_light(scene, f"{name} light {k}", ARTIST_LIGHTS[k % len(ARTIST_LIGHTS)],
                        (3.0 * cols * (k + 0.5) / n_lights, -10.0, 20.0))
              for k in range(n_lights)]
    if shadows_wanted():
        for light in lights:
            light.data.use_shadow = True
        objects.append(_floor(scene, name, template, cols))
    scene.world = bpy.data.worlds.new(name)
    properties.write_world(scene.world, 0.1, (1.0, 1.0, 1.0))
    return scene, objects, lights


def _floor(scene, name, template, cols):
    """A square under the cubes (1 below their bottoms, 3 beyond the grid on every side),
    its own mesh and a copy of *template* (grey)."""
    bpy = _bpy()
    mesh = bpy.data.meshes.new(f"{name} floor")
    low, high = -4.0, 3.0 * cols + 1.0
    mesh.from_pydata([(low, low, -2.0), (high, low, -2.0), (high, high, -2.0), (low, high, -2.0)],
                     [], [(0, 1, 2, 3)])
    material = template.copy()
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (
        0.5, 0.5, 0.5, 1.0)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(f"{name} floor", mesh)
    scene.collection.objects.link(obj)
    return obj


def add_light(scene, name, kind, location):
    bpy = _bpy()
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415

    data = bpy.data.lights.new(name, kind)
    # The figures of issues 5-38 compare the model without shadows, on both sides (Principled
    # too); Blender's lights cast them by default, and Phong materials do since issue 43.
    data.use_shadow = False
    properties.write_light(data, {"intensity": 400.0} if kind != "SUN" else {})
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    obj.rotation_euler = (0.6, 0.0, 0.3)
    scene.collection.objects.link(obj)
    return obj


def drivers_in_file():
    """Every driver of the file (materials' trees, node groups, lights, worlds, objects)."""
    bpy = _bpy()
    ids = [*bpy.data.node_groups, *bpy.data.lights, *bpy.data.worlds, *bpy.data.objects,
           *bpy.data.materials, *(m.node_tree for m in bpy.data.materials if m.node_tree)]
    return sum(len(i.animation_data.drivers) for i in ids if i.animation_data)


def move_updates(view_layer, light, moves):
    """Seconds of the depsgraph update after each of *moves* small moves of *light*."""
    times = []
    for i in range(moves):
        light.location.x += 0.25 if i % 2 == 0 else -0.25
        start = time.perf_counter()
        view_layer.update()
        times.append(time.perf_counter() - start)
    return times


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def worker_artist(cfg, n_objects, n_lights):
    """Issue 10's table for one scene size, side by side in one process: the scene with its
    Principled materials, then converted by Apply Phong Material."""
    bpy = _bpy()
    out = {"objects": n_objects, "lights": n_lights}
    scene, objects, lights = artist_scene("artist", n_objects, n_lights)
    view_layer = scene.view_layers[0]
    view_layer.update()  # first evaluation, untimed
    moves = cfg["scale_moves"]
    out["principled_move"] = move_updates(view_layer, lights[0], moves)
    out["principled_drivers"] = drivers_in_file()

    for obj in objects:
        obj.select_set(True, view_layer=view_layer)
    with bpy.context.temp_override(scene=scene, view_layer=view_layer,
                                   selected_objects=objects):
        out["apply_operator"], result = timed(bpy.ops.phong.apply_material)
    if result != {"FINISHED"}:
        raise RuntimeError(f"apply_material returned {result}")
    out["apply_update"], _ = timed(view_layer.update)
    out["phong_materials"] = len({s.material for o in objects for s in o.material_slots})
    out["phong_move"] = move_updates(view_layer, lights[0], moves)
    out["drivers"] = drivers_in_file()

    # a light added without a click: the depsgraph handler relinks on the next update
    add_light(scene, "added light", "POINT", (0.0, -10.0, 10.0))
    out["add_light_update"], _ = timed(view_layer.update)
    out["drivers_after_add"] = drivers_in_file()
    with bpy.context.temp_override(scene=scene, view_layer=view_layer):
        out["relink_operator"], result = timed(bpy.ops.phong.relink_lights)
    if result != {"FINISHED"}:
        raise RuntimeError(f"relink_lights returned {result}")
    out["relink_update"], _ = timed(view_layer.update)
    return out


# --------------------------------------------------------------------- Eevee worker

def worker_eevee(cfg, cases):
    """One cold process: warm the engine with the Emission floor, then time the first
    (compile included) and second render of each case (material, n_lights)."""
    out = {}
    scene, _ = build_scene("ewarm", res=cfg["eevee_res"], grid=cfg["eevee_grid"], n_lights=1,
                           material="emission", segments=cfg["segments"])
    set_eevee(scene, cfg["eevee_samples"])
    out["warmup_first"] = render(scene)
    out["warmup_second"] = render(scene)
    remove_scene(scene)
    for material, n in cases:
        scene, _ = build_scene(f"e {material} {n}", res=cfg["eevee_res"], grid=cfg["eevee_grid"],
                               n_lights=n, material=material, segments=cfg["segments"])
        set_eevee(scene, cfg["eevee_samples"])
        first = render(scene)
        second = render(scene)
        out[f"{material}:{n}"] = {"first": first, "second": second}
        remove_scene(scene)
    return out

# --------------------------------------------------------------------- demo scenes

def distinct_layouts(scene):
    """Give every Phong material of *scene* its own node layout without changing a value:
    material k gets a chain of k Math ADD 0 nodes on its Exponent (a shader per material,
    what a recipe that wires per-object values into each material would compile)."""
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    found = {slot.material for obj in scene.objects for slot in obj.material_slots
             if recipe.is_phong_material(slot.material)}
    for k, material in enumerate(sorted(found, key=lambda m: m.name), start=1):
        tree = material.node_tree
        socket = tree.nodes["phong_exponent"].outputs[0]
        target = tree.nodes[recipe.LIGHTS_NODE].inputs["Exponent"]
        for _ in range(k):
            add = tree.nodes.new("ShaderNodeMath")
            add.operation = "ADD"
            add.inputs[1].default_value = 0.0
            tree.links.new(socket, add.inputs[0])
            socket = add.outputs[0]
        tree.links.new(socket, target)
    return len(found)


def worker_demos(cfg, names):
    """One cold process: warm the engine with the Emission floor, then per demo scene (built
    by build_demo_scene's code) the first and second Eevee render, and the same with one
    layout per material (distinct_layouts)."""
    from phong_nodes.addon.demos import builder  # noqa: PLC0415
    from phong_nodes.core import scenes  # noqa: PLC0415

    out = {}
    scene, _ = build_scene("dwarm", res=cfg["eevee_res"], grid=1, n_lights=1,
                           material="emission", segments=cfg["segments"])
    set_eevee(scene, cfg["eevee_samples"])
    out["warmup_first"] = render(scene)
    remove_scene(scene)
    for name in names:
        data = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))
        for variant in ("shared", "distinct"):
            scene = builder.build(data, cfg["eevee_res"])
            count = distinct_layouts(scene) if variant == "distinct" else None
            set_eevee(scene, cfg["eevee_samples"])
            first = render(scene)
            second = render(scene)
            out[f"{name}:{variant}"] = {"first": first, "second": second, "materials": count}
            builder.remove(scene)
    return out


def main(name, params):
    cfg = params["cfg"]
    worker_setup()
    if name == "cycles":
        result = worker_cycles(cfg)
    elif name == "eevee":
        result = worker_eevee(cfg, [tuple(c) for c in params["cases"]])
    elif name == "artist":
        result = worker_artist(cfg, *params["case"])
    elif name == "demos":
        result = worker_demos(cfg, params["names"])
    else:
        raise SystemExit(f"unknown worker {name}")
    with open(params["result_path"], "w") as fh:
        json.dump(result, fh)
    sys.stdout.flush()
    os._exit(0)  # skip bpy's clean-up at exit (slow, and it can crash after Eevee)




if __name__ == "__main__":
    main(sys.argv[1], json.loads(sys.argv[2]))
