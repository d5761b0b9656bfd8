# SPDX-License-Identifier: GPL-3.0-or-later
"""Real .blend files that other people made (tests/data/blend/, their origin and licence in
tests/data/README.md): interiors, characters, a product studio, game-level pieces, curves,
area lights, several scenes, no camera, linked libraries with collection instances, files
saved by Blender 2.78 to 5.1.

For every scene of every file: Apply (``convert.apply``) converts every object that renders
with materials or names it in the report; the lights that render (hidden in the viewport
or not) are the lights that drive Phong; then the comparison (Cycles and Eevee against the
numpy reference, 32 pixels high) gives its verdicts, which are recorded with their figures
in the run's summary lines.
"""

import os
import types

import pytest

import blender_env as be

DATA = os.path.join(be.REPO_ROOT, "tests", "data", "blend")
#: The files (not the libraries they link, in libraries/).
FILES = sorted(name for name in os.listdir(DATA) if name.endswith(".blend"))
RESOLUTION = 32


def _open(path):
    """Open *path*; a file saved by Blender 5 is skipped on a release before 5, which cannot
    read its format (it says "not a blend file")."""
    bpy = be.import_bpy()
    try:
        bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
    except RuntimeError as error:
        if bpy.app.version < (5, 0, 0) and "not a blend file" in str(error):
            pytest.skip(f"{os.path.basename(path)}: saved by a newer Blender than "
                        f"{bpy.app.version_string} reads")
        raise
    return bpy


def _layer(scene):
    return next((v for v in scene.view_layers if v.use), scene.view_layers[0])


def _rendering(scene):
    """The objects of *scene* that F12 shows, worked out here from the collections' and the
    objects' render switches and the view layer's excluded collections (not from the code
    under test): {name: object}."""
    layer = _layer(scene)
    ok_collections = set()

    def walk(layer_collection):
        if layer_collection.exclude or layer_collection.collection.hide_render:
            return
        ok_collections.add(layer_collection.collection.name_full)
        for child in layer_collection.children:
            walk(child)

    if layer.layer_collection is not None:
        walk(layer.layer_collection)
    out = {}
    for obj in scene.objects:
        if obj.hide_render:
            continue
        if any(c.name_full in ok_collections for c in obj.users_collection):
            out[obj.name] = obj
    return out


def _instanced(objects):
    """The objects that collections instanced by *objects* (Empties) bring, recursively."""
    out, stack, seen = {}, list(objects), set()
    while stack:
        obj = stack.pop()
        collection = obj.instance_collection if obj.instance_type == "COLLECTION" else None
        if collection is None or collection.name_full in seen:
            continue
        seen.add(collection.name_full)
        for child in collection.all_objects:
            out[child.name] = child
            stack.append(child)
    return out


def _framed(path, scene):
    """The scene ready for the comparison as ``phong compare FILE.blend`` makes it: its
    camera object where it sets no scene camera, else a camera framing its Phong objects;
    returns the notes (``cli.runs._file_scene``)."""
    from phong_nodes.cli import runs  # noqa: PLC0415

    job = types.SimpleNamespace(notes=[])
    runs._file_scene(path, scene, job)
    return job.notes


def _figures(metrics):
    verdict = metrics["verdict"]
    parts = []
    for engine in ("cycles", "eevee"):
        if engine in verdict:
            v = verdict[engine]
            parts.append(f"{engine} {'ok' if v['ok'] else 'FAILS'} ({v['rule']}: {v['value']})")
    return "; ".join(parts) + f"; coverage {metrics.get('coverage')}"


@pytest.mark.parametrize("name", FILES)
def test_apply_converts_every_rendering_object_of_every_scene(extension, name):
    """Apply on every scene: every object that renders with material slots (and every
    object its Empties instance) is converted or named in report.skipped with a reason; the
    lights that drive Phong are exactly the scene's lights that render."""
    bpy = _open(os.path.join(DATA, name))
    from phong_nodes.addon.lighting import convert  # noqa: PLC0415

    for scene in list(bpy.data.scenes):
        if scene.library is not None:
            continue
        rendering = _rendering(scene)
        rendering.update(_instanced(rendering.values()))
        with_slots = {n for n, o in rendering.items()
                      if o.type not in ("LIGHT", "CAMERA", "EMPTY", "ARMATURE")
                      and len(getattr(o, "material_slots", ())) > 0}
        lights = {n for n, o in rendering.items() if o.type == "LIGHT"}
        report = convert.apply(scene)
        skipped = dict(report.skipped)
        assert all(why for why in skipped.values()), report.skipped
        missing = with_slots - set(report.converted) - set(skipped)
        assert not missing, f"{name} {scene.name!r}: neither converted nor named: {missing}"
        assert set(report.lights) == lights, (name, scene.name, report.lights, lights)
        hidden = sorted(n for n in lights if rendering[n].hide_get(view_layer=_layer(scene))
                        or rendering[n].hide_viewport)
        kinds = sorted({rendering[n].data.type for n in lights})
        be.report(f"real blend {name} [{scene.name}]: {len(report.converted)} converted, "
                  f"{len(report.skipped)} skipped"
                  + (f" ({'; '.join(f'{n}: {w}' for n, w in report.skipped)})"
                     if report.skipped else "")
                  + f", {len(report.materials)} Phong materials, lights {len(lights)} "
                  f"{kinds}" + (f" (hidden in the viewport: {hidden})" if hidden else "")
                  + (f"; notes: {report.notes}" if report.notes else ""))


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
@pytest.mark.parametrize("name", FILES)
def test_compare_after_apply(extension, name, tmp_path):
    """After Apply, the comparison of each scene that has Phong objects: its verdicts and
    figures are recorded; Cycles (max |Δ| ≤ 1e-4) and Eevee (≥ 99.5% within 1/255) hold
    where the file is known to pass (``EXPECTED_FAILURES`` names the others, with the
    figures measured)."""
    path = os.path.join(DATA, name)
    bpy = _open(path)
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import convert  # noqa: PLC0415

    compared = 0
    for scene in list(bpy.data.scenes):
        if scene.library is not None:
            continue
        report = convert.apply(scene)
        if not report.converted:
            be.report(f"real blend {name} [{scene.name}]: not compared: nothing converted")
            continue
        try:
            engine.check(scene, camera=False)
        except engine.ComparisonError as error:
            be.report(f"real blend {name} [{scene.name}]: not compared: {error}")
            continue
        notes = _framed(path, scene)
        metrics = engine.run(scene, str(tmp_path / f"scene{compared}"),
                             engines=("cycles", "eevee"), resolution=RESOLUTION, notes=notes)
        compared += 1
        line = f"real blend {name} [{scene.name}]: {_figures(metrics)}"
        if metrics.get("notes"):
            line += f"; notes: {metrics['notes']}"
        be.report(line)
        assert metrics["coverage"]["ok"], (name, scene.name, metrics["coverage"])
        # measured on the default release; elsewhere those verdicts are reported, not held
        measured = be.bpy_release() == EXPECTED_ON
        expected = EXPECTED_FAILURES.get((name, scene.name), set())
        for engine_name, verdict in metrics["verdict"].items():
            if engine_name in expected and not measured:
                continue
            if engine_name in expected:
                assert not verdict["ok"], (f"{name} {scene.name!r}: {engine_name} passes now "
                                           f"({verdict['value']}): take it off "
                                           "EXPECTED_FAILURES")
            else:
                assert verdict["ok"], (name, scene.name, engine_name, verdict)
    assert compared, f"{name}: no scene was compared"


#: (file, scene): the engines whose verdict fails on that scene today (measured with bpy
#: 5.3.0 at 32 pixels high), each an open bug of the comparison or of Eevee's picture, not of
#: the file, with its figures.  The earlier three were a black pupil that the comparison's
#: probes made vanish from Cycles' picture (now rendered apart), Blender's Specular factor 0
#: that Eevee's light loop honours (now read by Apply) and Eevee's shadow filter (now 0 in the
#: exact settings).  appleseed_linking's Eevee: 99.014% of the pixels within 1/255 (goal
#: 99.5%) since the comparison also sees the objects of instanced collections (its
#: TeapotGroup, instanced twice): 5 of 507 pixels on the teapots' spouts and handles (max |Δ|
#: 0.28); Cycles matches there (max |Δ| 3.2e-06).  Blender's, not the comparison's: the
#: teapot's flat quads are warped (130 of 760 by more than 1°), Eevee shades a flat polygon
#: with its one normal and Cycles each triangle with its own; a plain Emission of
#: Geometry ▸ Normal differs as much (test_eevee_misses_appleseed_only_on_its_warped_polygons).
EXPECTED_ON = "5.3.0"
EXPECTED_FAILURES: dict = {("appleseed_linking.blend", "Scene"): {"eevee"}}


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_eevee_misses_appleseed_only_on_its_warped_polygons(extension, tmp_path):
    """appleseed_linking's Eevee failure (``EXPECTED_FAILURES``) is its teapot's warped flat
    quads: the comparison's notes name the teapot, and with the teapot triangulated (each
    engine then shades the same flat triangles) the note is gone and Eevee meets its goal
    (measured at 32 px high: 99.014% and 99.606% on bpy 5.3.0, 99.211% and 99.803% on 5.2.3,
    99.084% and 99.817% on 5.0.1, 4.5.15 and 4.2.23)."""
    bpy = _open(os.path.join(DATA, "appleseed_linking.blend"))
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import convert  # noqa: PLC0415

    scene = bpy.data.scenes["Scene"]
    assert convert.apply(scene).converted
    notes = _framed(os.path.join(DATA, "appleseed_linking.blend"), scene)
    before = engine.run(scene, str(tmp_path / "warped"), engines=("cycles", "eevee"),
                        resolution=RESOLUTION, notes=notes)
    warped = [n for n in before.get("notes", []) if "flat polygon(s) not planar" in n]
    assert len(warped) == 1 and "'Teapot'" in warped[0], before.get("notes")
    teapots = [o for o in bpy.data.objects if o.name.startswith("Teapot") and o.type == "MESH"
               and o.library is None]
    assert teapots, "Apply made no local teapot (its override) to triangulate"
    for obj in teapots:
        obj.modifiers.new("Triangulate", "TRIANGULATE").quad_method = "FIXED"
    after = engine.run(scene, str(tmp_path / "triangulated"), engines=("cycles", "eevee"),
                       resolution=RESOLUTION, notes=notes)
    assert not any("not planar" in n for n in after.get("notes", [])), after["notes"]
    be.report(f"real blend appleseed_linking.blend: eevee {before['verdict']['eevee']['value']}"
              f" with the warped teapot, {after['verdict']['eevee']['value']} triangulated")
    assert after["verdict"]["cycles"]["ok"], after["verdict"]
    assert not before["verdict"]["eevee"]["ok"], before["verdict"]
    assert after["verdict"]["eevee"]["ok"], after["verdict"]
