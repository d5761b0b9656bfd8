# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong apply FILE.blend -o OUT.blend`` and ``phong compare FILE.blend --apply``: Apply
Phong Material, headless, on every scene of a file with no Phong material yet; the report of
what was converted and what not; OUT.blend written whole, never the input; bad input exits 2
with one line."""

import hashlib
import os

import pytest

import blender_env as be
from test_cli import run_cli
from test_compare_files import _metrics

SCENES = ("Alpha", "Beta")


def _plain_scene(bpy, name):
    """A sphere with a Principled material, a Point light, a volume (which Phong cannot
    shade), a camera: a scene as an artist has it, no Phong material."""
    scene = bpy.data.scenes.new(name)
    scene.render.resolution_x, scene.render.resolution_y = 48, 32
    world = bpy.data.worlds.new(name)
    be.compat().black_world(world)
    scene.world = world
    material = bpy.data.materials.new(f"{name} paint")
    be.compat().new_material_tree(material)
    be.add_uv_sphere(scene, f"{name} ball", (0.0, 0.0, 0.0), 1.0, material, segments=24,
                     rings=12)
    lamp = bpy.data.objects.new(f"{name} lamp", bpy.data.lights.new(f"{name} lamp", "POINT"))
    lamp.data.use_shadow = False
    lamp.data.energy = 500.0
    scene.collection.objects.link(lamp)
    lamp.location = (2.0, -3.0, 3.0)
    fog = bpy.data.objects.new(f"{name} fog", bpy.data.volumes.new(f"{name} fog"))
    scene.collection.objects.link(fog)
    be.add_persp_camera(scene, (0.0, -6.0, 1.0), (0.0, 0.0, 0.0))
    return scene


@pytest.fixture
def plain_file(bpy_clean, tmp_path):
    """Two such scenes saved (the window shows Alpha); returns (path, its sha256)."""
    bpy = bpy_clean
    for name in SCENES:
        _plain_scene(bpy, name)
    bpy.context.window.scene = bpy.data.scenes["Alpha"]
    bpy.data.scenes.remove(bpy.data.scenes["Scene"])
    bpy.data.workspaces[0].name = "Artist's layout"   # the file's own UI, kept by apply
    path = tmp_path / "plain.blend"
    # Beta's colour from an image beside the file, by a relative path
    image = bpy.data.images.new("paint", 4, 4)
    image.filepath_raw = str(tmp_path / "paint.png")
    image.file_format = "PNG"
    image.save()
    image.filepath = "//paint.png"
    tree = bpy.data.materials["Beta paint"].node_tree
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    tree.links.new(texture.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)
    return path, hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.slow
@pytest.mark.cycles
def test_apply_converts_every_scene_into_a_new_file_that_compares_ok(bpy_clean, plain_file,
                                                                      tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415
    path, digest = plain_file
    out = tmp_path / "made" / "phong.blend"
    result = run_cli(tmp_path, "apply", str(path), "-o", str(out))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "Traceback" not in result.stderr
    for name in SCENES:
        assert f"scene '{name}':\n  1 object(s) converted, 1 Phong material(s), 1 light(s)" \
            in result.stdout
        assert f"{name} fog: a volume (Phong shades surfaces)" in result.stdout
    assert f"2 object(s) in 2 scene(s) take Phong materials; written: {out}" in result.stdout
    assert hashlib.sha256(path.read_bytes()).hexdigest() == digest, "the input is not written"
    assert sorted(p.name for p in out.parent.iterdir()) == ["phong.blend"], "no leftovers"

    bpy.ops.wm.open_mainfile(filepath=str(out))
    for name in SCENES:
        ball = bpy.data.objects[f"{name} ball"]
        assert recipe.is_phong_material(ball.material_slots[0].material), name
    assert "Artist's layout" in bpy.data.workspaces, "the file's own workspaces are kept"
    # relative paths remapped to OUT.blend's folder: the image is still found
    image = bpy.data.images["paint"]
    assert image.filepath == "//../paint.png"
    assert os.path.samefile(bpy.path.abspath(image.filepath), tmp_path / "paint.png")
    result = run_cli(tmp_path, "compare", str(out), "--engines", "cycles", "--resolution", "24",
                     "--out", str(tmp_path / "check"))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    for name in SCENES:
        assert _metrics(tmp_path / "check", name)["ok"]


@pytest.mark.slow
@pytest.mark.cycles
def test_compare_apply_converts_then_compares_each_shard(plain_file, tmp_path):
    """``compare --apply`` converts in memory (the file is not written) and compares; two
    shards into one folder make the whole run."""
    path, digest = plain_file
    out = tmp_path / "out"
    for shard in ("1/2", "2/2"):
        result = run_cli(tmp_path, "compare", str(path), "--apply", "--shard", shard,
                         "--engines", "cycles", "--resolution", "24", "--out", str(out))
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
        assert "1 scene(s) of 2" in result.stdout
        assert "Alpha fog: a volume" in result.stdout
    for name in SCENES:
        metrics = _metrics(out, name)
        assert metrics["ok"] and metrics["pixels"]["compared"] > 50
        assert metrics["notes"] == ["applied: 1 object(s) given Phong materials first "
                                    "(--apply; the file is not written)"]
    assert hashlib.sha256(path.read_bytes()).hexdigest() == digest
    assert run_cli(tmp_path, "report", str(out)).returncode == 0


@pytest.mark.parametrize("case", ["missing", "not-blend", "same-file", "not-blend-output",
                                  "unknown-scene", "nothing", "no-output"])
def test_apply_bad_input_exits_2_with_one_line_and_writes_nothing(bpy_clean, tmp_path, case):
    bpy = bpy_clean
    empty = tmp_path / "empty.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(empty), copy=True)   # an empty scene
    notes = tmp_path / "notes.txt"
    notes.write_text("hello")
    out = tmp_path / "out" / "x.blend"
    args, message = {
        "missing": ([str(tmp_path / "nope.blend"), "-o", str(out)], "nope.blend: no such file"),
        "not-blend": ([str(notes), "-o", str(out)], "notes.txt: not a .blend file"),
        "same-file": ([str(empty), "-o", str(empty)], "is the input file; apply never writes"),
        "not-blend-output": ([str(empty), "-o", str(tmp_path / "out" / "x.txt")],
                             "expected a .blend path"),
        "unknown-scene": ([str(empty), "-o", str(out), "--scenes", "Nope"],
                          "--scenes: no scene 'Nope'"),
        "nothing": ([str(empty), "-o", str(out)],
                    "empty.blend: no object that renders with materials in scene 'Scene'"),
        "no-output": ([str(empty)], "the following arguments are required: -o/--output"),
    }[case]
    before = empty.read_bytes()
    result = run_cli(tmp_path, "apply", *args)
    assert result.returncode == 2, result.stdout[-2000:] + result.stderr[-2000:]
    lines = [l for l in result.stderr.splitlines() if l.startswith("phong")]
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists(), "nothing written"
    assert empty.read_bytes() == before
