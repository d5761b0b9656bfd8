# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison: Eevee, Cycles and the numpy reference of any scene with Phong
materials (a demo scene, an artist's scene, a production file).

* Cycles renders the picture as the user's F12 does, then, in a second render, the
  materials' term passes ("Phong Irradiant" ...) and the probes: for that render only, every
  lights group of the scene is swapped for a copy that also writes, as AOVs, what it sees
  per pixel (``core.compare.PROBES``: position, normal, incoming, the material's inputs, and
  the object's number).  Two renders, because the probes can change the picture they
  observe: on a real character file, a black unlit pupil (an Emission folded to nothing)
  vanished from Cycles' picture whenever its lights group held the Geometry or Object Info
  probes, and the eye behind it showed through.  Eevee never compiles the probes (each AOV
  costs Eevee shader compile time).  1 sample at the pixel centres, box filter
  0.01, SVM (Open Shading Language writes no AOVs: a scene with it on is rendered without,
  saying so in the notes).
* Eevee renders the picture: 1 TAA sample, filter size 0: its first sample sits at the
  pixel centre too.
* ``describe.describe`` reads the lights, Light Linking and World ambient as Blender
  evaluates them; ``core.compare`` computes the reference from them and the probes, and the
  metrics; ``core.report`` writes the pictures, the sheet and metrics.json.

Every setting the comparison changes (render settings, view layers, passes, object pass
indices, lights groups) is put back afterwards, also after an error.  Everything is
written into a hidden temporary folder beside the destination and renamed into place at
the end, so an interrupted comparison leaves no folder that looks finished.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time

import bpy

from ...core import browser, compare, outputs, report, threejs, x_ite
from ...core.wording import name_list
from .. import compat
from ..lighting import loop as light_loop
from ..lighting import convert, engine_outputs, recipe, rig, shadows
from ..lighting import sync as sync_mod
from ..interchange import threejs_export
from ..scene import describe, render
from ..scene.render import Overrides, render_exr
from ..shading import modes as shading_modes
from . import x_ite_peer


class ComparisonError(ValueError):
    """A scene that cannot be compared; the message says why."""


# -- what is compared ----------------------------------------------------------------

def check(scene, view_layer=None, camera=True):
    """(view layer, Phong objects) of *scene*, or ComparisonError saying why it cannot be
    compared; without *camera* a scene without camera passes (the caller frames one)."""
    if scene.library is not None:   # its settings cannot be changed for the renders here
        raise ComparisonError(f"scene {scene.name!r} is linked from the library "
                              f"{scene.library.filepath!r}: compare it in that file")
    layer = describe.view_layer_of(scene, view_layer)
    phong = describe.phong_objects(scene, layer, instanced=True)
    # Per Vertex / Per Face materials are not the per-pixel model: shown, not compared
    objects = [obj for obj in phong
               if any(recipe.is_phong_material(slot.material)
                      and shading_modes.mode_of(slot.material) == shading_modes.PIXEL
                      for slot in obj.material_slots)]
    if phong and not objects:
        raise ComparisonError(f"scene {scene.name!r}: its Phong materials shade Per Vertex or "
                              "Per Face, and the comparison checks Per Pixel shading only "
                              "(set a material's Shading to Per Pixel to compare it)")
    if not objects:
        raise ComparisonError(f"scene {scene.name!r} has no object with a Phong material in view "
                        f"layer {layer.name!r} (Apply Phong Material first)")
    # the render's geometry is evaluated for it: no relink there (the comparison checks the
    # lights groups as they are, a stale one too)
    with sync_mod.paused():
        rendering = describe.rendering_phong(scene, layer, objects)
    if not rendering:
        names = name_list(obj.name for obj in objects)
        raise ComparisonError(
            f"scene {scene.name!r}: its Phong objects ({names}) render no Phong surface: what "
            "renders of them (their Geometry Nodes output: points, instances) carries none of "
            "their Phong materials; give that geometry the object's material (a Set Material "
            "node) to compare it")
    if camera and scene.camera is None:
        raise ComparisonError(f"scene {scene.name!r} has no camera")
    return layer, objects


# -- rendering ------------------------------------------------------------------------

def _render(scene, engine, folder, o: Overrides) -> dict:
    render.exact(scene, engine, o.set)
    path = os.path.join(folder, f"{engine}.exr")
    render_exr(scene, path, o.set)
    try:
        return compare.read_exr(path)
    finally:
        os.remove(path)


def _add_aovs(layer, names, o: Overrides) -> None:
    for name in engine_outputs.add_view_layer_aovs(layer, names):
        o.later(lambda aov_name=name: _remove_aov(layer, aov_name))


def _remove_aov(layer, name) -> None:
    aov = next((a for a in layer.aovs if a.name == name), None)
    if aov is not None:
        layer.aovs.remove(aov)


def _probe_groups(objects, o: Overrides) -> None:
    """Swap each lights group the objects' materials use for a copy with the probes."""
    groups = {}
    for obj in objects:
        for slot in obj.material_slots:
            if recipe.is_phong_material(slot.material):
                node = slot.material.node_tree.nodes.get(recipe.LIGHTS_NODE)
                if node is not None and node.node_tree is not None:
                    groups[node.node_tree.name] = node.node_tree
    for group in groups.values():
        probe = group.copy()
        probe.name = f"{group.name} (probe)"
        for key in (rig.SCENE_KEY, rig.SET_KEY):
            if key in probe.keys():
                del probe[key]  # not a lights group of the scene for Sync or the handler
        _add_probes(probe)
        o.set(group, "use_fake_user", True)
        group.user_remap(probe)
        o.later(lambda g=group, p=probe: _unswap(g, p))


def _unswap(group, probe) -> None:
    probe.user_remap(group)
    bpy.data.node_groups.remove(probe)


def _add_probes(tree) -> None:
    """AOV outputs of what the lights group sees (``compare.PROBES``) inside *tree*."""
    group_in = next(n for n in tree.nodes if n.bl_idname == "NodeGroupInput")
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    info = tree.nodes.new("ShaderNodeObjectInfo")
    params = tree.nodes.new("ShaderNodeCombineXYZ")
    tree.links.new(group_in.outputs["Exponent"], compat.input_socket(params, "X"))
    tree.links.new(group_in.outputs["Blinn"], compat.input_socket(params, "Y"))
    tree.links.new(info.outputs["Object Index"], compat.input_socket(params, "Z"))
    sources = {"P": geometry.outputs["Position"], "N": geometry.outputs["Normal"],
               "I": geometry.outputs["Incoming"], "normal": group_in.outputs["Normal"],
               "view": group_in.outputs["View Vector"],
               "color": group_in.outputs["Object Color"],
               "ambient": group_in.outputs[recipe.AMBIENT_INPUT],
               "specular": group_in.outputs["Specular Color"],
               "irradiant": group_in.outputs["Irradiant Color"],
               "params": params.outputs["Vector"],
               "strength": group_in.outputs["Specular Strength"]}
    for index, probe in enumerate(compare.PROBES):
        aov = tree.nodes.new("ShaderNodeOutputAOV")
        aov.aov_name = compare.probe_name(probe)
        aov.location = (-600.0, 900.0 + 120.0 * index)
        tree.links.new(sources[probe], aov.inputs["Color"])
    if light_loop.has_loop(tree) or shadows.has_shadows(tree):
        _add_term_aovs(tree)


def _add_term_aovs(tree) -> None:
    """The term passes as AOV outputs inside *tree*: a lights group with the loop part
    (Blender 5.3+) or shadow rays (5.1+), whose materials hold no AOV outputs
    (``writer.wire``), for Cycles' render only."""
    group_out = next(n for n in tree.nodes if n.bl_idname == "NodeGroupOutput")
    for index, (aov_name, output) in enumerate(recipe.AOVS.items()):
        aov = tree.nodes.new("ShaderNodeOutputAOV")
        aov.aov_name = aov_name
        aov.location = (group_out.location.x, group_out.location.y - 200.0 - 120.0 * index)
        target = group_out.inputs[output]
        if target.is_linked:
            tree.links.new(target.links[0].from_socket, aov.inputs["Color"])
        else:
            aov.inputs["Color"].default_value = target.default_value


def _culled(objects) -> list:
    """The materials of *objects* with Backface Culling (an imported ``solid``).  The
    comparison judges the lighting equation on both sides of every face: Cycles ignores
    Backface Culling and the reference knows none, so Eevee (and X_ITE, ``x_ite_peer``) are
    made to draw both sides too while it renders."""
    out = {}
    for obj in objects:
        for slot in obj.material_slots:
            material = slot.material
            if material is not None and material.use_backface_culling:
                out[material.name] = material
    return list(out.values())


def render_all(scene, layer, objects, engines, folder, resolution=None, progress=None):
    """({engine: picture}, probe and term passes of Cycles) of *scene*, rendered with exact
    settings that are put back afterwards; call it inside ``sync.paused()`` (the lights
    groups are swapped meanwhile)."""
    progress = progress or (lambda f, t: None)
    o = Overrides()
    images = {}
    try:
        if resolution is not None:
            aspect = scene.render.resolution_x / scene.render.resolution_y
            width, height = max(1, round(resolution * aspect)), resolution
        else:
            percent = scene.render.resolution_percentage / 100.0
            width = max(1, round(scene.render.resolution_x * percent))
            height = max(1, round(scene.render.resolution_y * percent))
        render.plain_picture(scene, width, height, o.set)
        compat.set_multilayer_exr(scene.render.image_settings, o.set)
        for other in scene.view_layers:
            o.set(other, "use", other == layer)
        for index, obj in enumerate(objects, start=1):
            o.set(obj, "pass_index", index)
        for material in _culled(objects):   # both sides, as Cycles and the reference see them
            o.set(material, "use_backface_culling", False)
        if "eevee" in engines:
            progress(0.35, "Eevee (picture)")
            images["eevee"] = _render(scene, "eevee", folder, o)["Combined"][..., :3]
        progress(0.05 if "eevee" not in engines else 0.5, "Cycles (picture)")
        images["cycles"] = _render(scene, "cycles", folder, o)["Combined"][..., :3]
        progress(0.2 if "eevee" not in engines else 0.65, "Cycles (terms, probes)")
        _add_aovs(layer, list(recipe.AOVS) + [compare.probe_name(p) for p in compare.PROBES],
                  o)
        _probe_groups(objects, o)
        passes = _render(scene, "cycles", folder, o)
    finally:
        o.restore()  # the caller holds the handler paused (sync.paused)
    terms = {term: passes[f"Phong {term}"][..., :3] for term in compare.TERMS}
    return images, passes, terms


# -- the comparison -----------------------------------------------------------------------

def check_peers(peers) -> None:
    """ComparisonError naming what to install when a peer cannot run here (before anything is
    written)."""
    unknown = [p for p in peers if p not in compare.PEERS]
    if unknown:
        raise ComparisonError(f"unknown peer {unknown[0]!r}; expected one of {', '.join(compare.PEERS)}")
    problem = threejs.unavailable() if "threejs" in peers else None
    if problem is None and "x_ite" in peers:
        problem = x_ite.unavailable()
    if problem is not None:
        raise ComparisonError(problem)


def _threejs_peer(scene, layer, objects, data, width, height, folder) -> tuple:
    """(three.js's RGBA picture, seconds in the browser, warnings): the scene exported as
    a page into *folder*/threejs/ (kept in the report) and rendered by Chromium."""
    page = os.path.join(folder, "threejs", "scene.html")
    os.makedirs(os.path.dirname(page), exist_ok=True)
    page_data, warnings = threejs_export.scene_dict(scene, layer, width, height, objects, data)
    threejs.write_page(page, page_data)
    result = browser.render_page(page)
    if result.errors:
        raise browser.BrowserError("the three.js page reported: " + "; ".join(result.errors))
    if result.rgba.shape[:2] != (height, width):
        raise browser.BrowserError(f"the three.js page drew {result.rgba.shape[1]}×"
                                   f"{result.rgba.shape[0]} pixels, not {width}×{height}")
    return result.rgba, result.seconds, warnings


def run(scene, out_dir: str, engines=compare.ENGINES, progress=None, view_layer=None,
         resolution=None, on_folder=None, peers=(), notes=()) -> dict:
    """Render and compare *scene* into *out_dir* (replaced whole).

    *view_layer*: the name of the view layer to render (default: the first that renders);
    *resolution*: the picture height in pixels (default: the scene's own size).
    *progress(fraction, text)* is called between steps; *on_folder(folder)* may add files
    to the report folder before it is put in place; *notes*: lines the report shows with
    the verdicts (metrics["notes"], e.g. "framed: the file has no camera").  Returns the
    metrics dict (also written as metrics.json), whose "ok" is False also when the camera sees
    (almost) no Phong surface (metrics["coverage"]).  ComparisonError when the scene cannot
    be compared.
    """
    layer, objects = check(scene, view_layer)
    check_peers(peers)
    notes = list(notes) + ([render.OSL_NOTE] if render.uses_osl(scene) else [])
    engines = [e for e in compare.ENGINES if e in engines]
    progress = progress or (lambda f, t: None)
    parent = os.path.dirname(os.path.abspath(out_dir)) or "."
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=outputs.temp_prefix("partial", os.path.basename(out_dir)),
                           dir=parent)
    try:
        t0 = time.perf_counter()
        with sync_mod.paused():
            data = describe.describe(scene, layer, objects)
            if "eevee" in engines:
                notes += describe.warped_notes(scene, layer, objects)
                notes += convert.engine_notes(sorted(
                    {slot.material for obj in objects for slot in obj.material_slots
                     if recipe.is_phong_material(slot.material)},
                    key=lambda m: m.name_full), compared=True)
            images, passes, terms = render_all(scene, layer, objects, engines, tmp,
                                               resolution, progress)
        timings = {"renders_s": time.perf_counter() - t0}
        t0 = time.perf_counter()
        progress(0.8, "reference and report")
        metrics, refimg, mask = compare.evaluate(data, images, passes, engines, terms)
        height, width = images["cycles"].shape[:2]
        metrics["resolution"] = [width, height]
        if notes:
            metrics["notes"] = list(notes)
        timings["reference_s"] = time.perf_counter() - t0
        peer_mask = None
        # the peers' pages have no shadows: the pixels in a light's shadow are theirs to skip
        peer_region = mask & ~refimg["in_shadow"]
        if peers:
            metrics["peer_shadow_pixels"] = int((mask & refimg["in_shadow"]).sum())
        if "threejs" in peers:
            progress(0.85, "three.js in Chromium")
            t0 = time.perf_counter()
            rgba, seconds, warnings = _threejs_peer(scene, layer, objects, data, width, height,
                                                    tmp)
            pairs, peer_verdict, peer_mask = compare.evaluate_peer(data, rgba, images,
                                                                   peer_region)
            images["threejs"] = compare.srgb_decode(rgba[..., :3] / 255.0)
            metrics["pairs"].update(pairs)
            metrics["threejs"] = {"browser_s": seconds, "warnings": warnings,
                                  "covered": int((rgba[..., 3] > 0).sum()),
                                  "compared": int(peer_mask.sum()),
                                  "in_verdict": peer_verdict is not None}
            if peer_verdict is not None:
                metrics["verdict"]["threejs"] = peer_verdict
                metrics["ok"] = metrics["ok"] and peer_verdict["ok"]
            timings["threejs_s"] = time.perf_counter() - t0
        if "x_ite" in peers:
            progress(0.9, "X_ITE in Chromium")
            t0 = time.perf_counter()
            rgba, seconds, warnings = x_ite_peer.render(scene, layer, objects, data, width,
                                                        height, tmp)
            pairs, x_verdict, x_mask = compare.evaluate_x3d_peer(data, rgba, images,
                                                                 peer_region, refimg["object"])
            images["x_ite"] = rgba[..., :3] / 255.0   # the canvas holds I (ColorSpace SRGB)
            metrics["pairs"].update(pairs)
            metrics["x_ite"] = {"browser_s": seconds, "warnings": warnings,
                                "version": x_ite.X_ITE_VERSION,
                                "covered": int((rgba[..., 3] > 0).sum()),
                                "compared": int(x_mask.sum()),
                                "in_verdict": x_verdict is not None}
            if x_verdict is not None:
                metrics["verdict"]["x_ite"] = x_verdict
                metrics["ok"] = metrics["ok"] and x_verdict["ok"]
            peer_mask = {"threejs": peer_mask, "x_ite": x_mask}
            timings["x_ite_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        report.write_scene(tmp, data, images, refimg, mask, metrics, terms, peer_mask)
        timings["report_s"] = time.perf_counter() - t0
        metrics["timings"] = timings
        with open(os.path.join(tmp, "metrics.json"), "w", encoding="utf-8") as handle:
            json.dump(metrics, handle, indent=2, ensure_ascii=False)
        if on_folder is not None:
            on_folder(tmp)
        progress(0.95, "finishing")
        outputs.replace_dir(tmp, out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    progress(1.0, "done")
    return metrics
