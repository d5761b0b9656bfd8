# SPDX-License-Identifier: GPL-3.0-or-later
"""core/mtl.py without Blender: MTL statements as Alias|Wavefront's File Formats 4.2 define
them, read as leniently as other readers read other programs' files (real files in
tests/data/obj/real), several libraries per OBJ, warnings that name file and line, numbers
written as the shortest decimals of the same float32."""

from __future__ import annotations

import os

import pytest

from phong_nodes.core import mtl

TWO = (
    "# two materials, Windows line ends\r\n"
    "newmtl brick\r\n"
    "Ka 0.2\r\n"                              # one value: g = b = r
    "Kd 0.8 0.3 0.1  # trailing comment\r\n"
    "Ks 0.5 0.5 \\\r\n"                         # continued on the next line
    "0.4\r\n"
    "Ns 96.078431\r\n"
    "illum 2\r\n"
    "\r\n"
    "newmtl glass\r\n"
    "KD 0.1 0.1 0.1\r\n"                      # keywords are case-insensitive
    "d 0.25\r\n"
    "Ni 1.45\r\n"
    "illum 4\r\n"
    "Pr 0.5\r\n"                              # a PBR extension: kept, not understood
    "refl -type sphere sky.hdr\r\n"
)


def write(folder, name, text):
    path = os.path.join(folder, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as fh:
        fh.write(text)
    return path


def test_statements_values_and_what_phong_cannot_represent(tmp_path):
    path = write(tmp_path, "two.mtl", TWO)
    brick, glass = mtl.load(path)
    assert (brick.name, brick.line, glass.name, glass.line) == ("brick", 2, "glass", 10)
    assert brick.colors == {"Ka": (0.2, 0.2, 0.2), "Kd": (0.8, 0.3, 0.1), "Ks": (0.5, 0.5, 0.4)}
    assert brick.scalars == {"Ns": 96.078431} and brick.illum == 2
    assert brick.unsupported() == []
    assert glass.colors == {"Kd": (0.1, 0.1, 0.1)}
    assert glass.others == [(15, "Pr")]
    assert glass.maps["refl"].options == {"-type": ("sphere",)}
    assert glass.unsupported() == ["d 0.25 (transparency)", "Ni 1.45 (refraction)",
                                   "illum 4 (only 0, 1 and 2 are Phong models)",
                                   "refl sky.hdr", "Pr"]


def test_map_options_file_names_with_spaces_and_relative_paths(tmp_path):
    text = ("newmtl wood\n"
            "map_Kd -s 2 2 1 -o 0.5 0.5 -bm 0.3 -clamp ON textures/my wood.png\n"
            "map_Bump -bm 0.5 textures\\bump.png\n"
            "bump bump2.png\n"
            "map_Ks spec.png\n")
    path = write(tmp_path, "lib/wood.mtl", text)
    write(tmp_path, "lib/textures/my wood.png", "not really a png")
    (wood,) = mtl.load(path)
    kd = wood.maps["map_Kd"]
    assert kd.path == "textures/my wood.png" and kd.line == 2
    assert kd.options == {"-s": (2.0, 2.0, 1.0), "-o": (0.5, 0.5), "-bm": (0.3,),
                          "-clamp": ("on",)}
    assert kd.resolved == os.path.join(str(tmp_path), "lib", "textures", "my wood.png")
    assert kd.exists
    # bump and map_Bump are one statement: the later one wins
    assert wood.maps["bump"].path == "bump2.png" and wood.maps["bump"].line == 4
    assert [t.path for t in wood.missing_textures()] == ["bump2.png", "spec.png"]


@pytest.mark.parametrize("text, line, message", [
    ("newmtl a\nKd 0.5 abc 0.1\n", 2, "Kd: 'abc' is not a number; left out"),
    ("newmtl a\nKd 0.5 0.1\n", 2, "Kd needs 1 or 3 numbers (r [g b]), got 2; left out"),
    ("newmtl a\nNs nan\n", 2, "Ns: 'nan' is not a finite number; left out"),
    ("newmtl a\nillum 2.5\n", 2,
     "illum '2.5' is not an illumination model (0 to 10); read as illum 2"),
    ("newmtl a\n\nillum 11\n", 3,
     "illum '11' is not an illumination model (0 to 10); read as illum 2"),
    ("# header\nKd 1 1 1\n", 2, "Kd before any newmtl; left out"),
    ("newmtl\nKd 1 1 1\n", 1, "newmtl without a name; its statements are left out"),
    ("newmtl a\nmap_Kd\n", 2, "map_Kd: no file name; left out"),
    ("newmtl a\nmap_Kd -s\n", 2, "map_Kd: no file name; left out"),
    ("newmtl a\nmap_Kd -mm 0.1 x.png\n", 2,
     "map_Kd: option -mm needs 2 value(s); option left out"),
    ("newmtl a\nmap_Kd -bm abc x.png\n", 2,
     "map_Kd: option -bm needs a number, got 'abc'; option left out"),
    ("newmtl a\nmap_Kd -halftone 3 x.png\n", 2,
     "map_Kd: unknown option -halftone: '-halftone 3' left out, file name 'x.png'"),
])
def test_unreadable_statements_are_left_out_with_one_warning(tmp_path, text, line, message):
    """Never refused: a statement the model uses that cannot be read is left out, with one
    warning naming file and line; the rest of the file is read."""
    path = write(tmp_path, "bad.mtl", text + "newmtl after\nKd 0.25 0.5 0.75\n")
    warnings = []
    materials = mtl.load(path, warnings)
    assert warnings == [f"{path}:{line}: {message}"]
    assert materials[-1].name == "after" and materials[-1].colors["Kd"] == (0.25, 0.5, 0.75)
    assert all(m.illum is None for m in materials), "an unreadable illum reads as none (2)"
    if "map_Kd" in text and "x.png" in text:
        assert materials[0].maps["map_Kd"].path == "x.png", "never part of the file name"


@pytest.mark.parametrize("text", [
    "newmtl a\nNi -1.000000\n", "newmtl a\nd 123.0\n", "newmtl a\nd -2\nTr 7\n",
    "newmtl a\nNi abc\nTf 1 2\nsharpness x y\n", "newmtl a\nmap_d -s x\n",
])
def test_values_the_model_does_not_use_never_refuse_nor_warn(tmp_path, text):
    """Ni, d, Tr, Tf, sharpness and maps the model has no input for: whatever their values,
    the file is read; what cannot be read of them changes nothing in the picture."""
    path = write(tmp_path, "unused.mtl", text + "Kd 0.5 0.5 0.5\n")
    warnings = []
    (material,) = mtl.load(path, warnings)
    assert warnings == [] and material.colors["Kd"] == (0.5, 0.5, 0.5)


def test_negative_ns_is_clamped_to_0_with_one_warning(tmp_path):
    # as Blender's older OBJ exporter wrote it for a hardness of 0: (0 - 1) * 1.960784
    path = write(tmp_path, "old.mtl", "newmtl Material\nNs -1.960784\nKd 0.8 0.8 0.8\n")
    warnings = []
    (material,) = mtl.load(path, warnings)
    assert material.scalars["Ns"] == 0.0
    assert warnings == [f"{path}:2: Ns -1.960784 is below 0; read as 0"]


def test_tabs_and_spaces_separate_keywords_and_values(tmp_path):
    path = write(tmp_path, "tabs.mtl", "newmtl\tred paint\n"
                                       "Kd\t0.1 0.2\t0.3\n"
                                       "\tNs\t12\n"
                                       "illum\t0.0\n"
                                       "map_Kd\t-o 0.5\ttex.png\n")
    obj = write(tmp_path, "tabs.obj", "mtllib\ttabs.mtl\nusemtl\tred paint\n")
    (material,) = mtl.load(path)
    assert material.name == "red paint" and material.colors == {"Kd": (0.1, 0.2, 0.3)}
    assert material.scalars == {"Ns": 12.0} and material.illum == 0
    assert material.maps["map_Kd"].path == "tex.png"
    assert material.maps["map_Kd"].options == {"-o": (0.5,)}
    assert mtl.libraries(obj) == [(str(tmp_path / "tabs.mtl"), 1)]


@pytest.mark.parametrize("token, illum", [("0.0", 0), ("1.000", 1), ("2", 2), ("2.0e0", 2)])
def test_illum_accepts_integral_floats(tmp_path, token, illum):
    path = write(tmp_path, "i.mtl", f"newmtl a\nillum {token}\n")
    warnings = []
    assert mtl.load(path, warnings)[0].illum == illum and warnings == []


def test_map_options_by_arity_and_after_the_file_name(tmp_path):
    text = ("newmtl a\n"
            "map_Kd -colorspace sRGB -o 0.1 0.2 -bm 3 -imfchan l -texres 512 -boost 2 k d.png\n"
            "map_Ks -colorspace linear -cc on -t 0.1 s.png\n"
            "bump b.png -bm 0.5\n")
    path = write(tmp_path, "opt.mtl", text)
    warnings = []
    (material,) = mtl.load(path, warnings)
    kd, ks, bump = (material.maps[k] for k in ("map_Kd", "map_Ks", "bump"))
    assert warnings == []
    assert (kd.path, kd.options) == ("k d.png", {
        "-colorspace": ("srgb",), "-o": (0.1, 0.2), "-bm": (3.0,), "-imfchan": ("l",),
        "-texres": ("512",), "-boost": (2.0,)})
    assert (ks.path, ks.options) == ("s.png", {"-colorspace": ("linear",), "-cc": ("on",),
                                               "-t": (0.1,)})
    assert (bump.path, bump.options) == ("b.png", {"-bm": (0.5,)})
    # -o and -s are applied (the map's placement: see placement()), -bm to bump maps
    assert kd.placement() == ((0.1, 0.2, 0.0), (1.0, 1.0, 1.0))
    assert ks.placement() is None and bump.placement() is None
    assert material.unsupported() == ["map_Ks -colorspace linear (not applied)",
                                      "map_Ks -cc on (not applied)",
                                      "map_Ks -t 0.1 (not applied)"]


def test_textures_are_found_as_other_readers_find_them(tmp_path):
    text = ("newmtl a\n"
            "map_Kd C:\\Users\\me\\Documents\\tex.png\n"
            "map_Ka .\\tex.png\n"
            "map_Ks sub\\spec.png\n"
            "bump maps/bump.png\n"
            "map_Ke \\\\server\\share\\glow.png\n")
    path = write(tmp_path, "lib/w.mtl", text)
    for name in ("lib/tex.png", "lib/sub/spec.png", "lib/bump.png"):
        write(tmp_path, name, "not really a png")
    (material,) = mtl.load(path)
    lib = tmp_path / "lib"
    found = {k: t.resolved for k, t in material.maps.items()}
    assert found == {"map_Kd": str(lib / "tex.png"), "map_Ka": str(lib / "tex.png"),
                     "map_Ks": str(lib / "sub" / "spec.png"), "bump": str(lib / "bump.png"),
                     "map_Ke": str(lib / "glow.png")}
    assert material.maps["map_Kd"].looked_at == (str(lib / "tex.png"),), "no C: folder"
    assert material.maps["bump"].looked_at == (str(lib / "maps" / "bump.png"),
                                               str(lib / "bump.png"))
    assert [t.path for t in material.missing_textures()] == ["\\\\server\\share\\glow.png"]


def test_several_libraries_of_one_obj(tmp_path):
    write(tmp_path, "a.mtl", "newmtl red\nKd 1 0 0\nnewmtl shared\nKd 0 0 1\n")
    write(tmp_path, "sub/b.mtl", "newmtl green\nKd 0 1 0\n")
    write(tmp_path, "sub/c.mtl", "newmtl shared\nKd 1 1 1\n")
    obj = write(tmp_path, "model.obj", "# model\nmtllib a.mtl\nv 0 0 0\n"
                                       "mtllib sub/b.mtl sub/c.mtl\nusemtl red\n")
    assert mtl.libraries(obj) == [(str(tmp_path / "a.mtl"), 2), (str(tmp_path / "sub/b.mtl"), 4),
                                  (str(tmp_path / "sub/c.mtl"), 4)]
    materials, warnings = mtl.load_for_obj(obj)
    assert list(materials) == ["red", "shared", "green"]
    assert materials["shared"].colors["Kd"] == (0.0, 0.0, 1.0), "the first definition is kept"
    assert warnings == [f"{tmp_path / 'sub/c.mtl'}:1: material 'shared' is already defined "
                        f"at {tmp_path / 'a.mtl'}:3; kept the first"]


def test_libraries_named_by_windows_paths_are_found_beside_the_obj(tmp_path):
    write(tmp_path, "lib.mtl", "newmtl a\nKd 1 1 1\n")
    obj = write(tmp_path, "m.obj", "mtllib C:\\Users\\me\\lib.mtl\nmtllib .\\lib.mtl\n")
    assert mtl.libraries(obj) == [(str(tmp_path / "lib.mtl"), 1), (str(tmp_path / "lib.mtl"), 2)]


def test_library_name_with_spaces(tmp_path):
    write(tmp_path, "my materials.mtl", "newmtl a\nKd 1 1 1\n")
    obj = write(tmp_path, "m.obj", "mtllib my materials.mtl\n")
    assert list(mtl.load_for_obj(obj)[0]) == ["a"]


def test_missing_library_or_obj_names_the_file_and_line(tmp_path):
    obj = write(tmp_path, "m.obj", "v 0 0 0\nmtllib gone.mtl\n")
    with pytest.raises(mtl.MtlError) as excinfo:
        mtl.load_for_obj(obj)
    assert str(excinfo.value) == f"{obj}:2: material library {tmp_path / 'gone.mtl'} not found"
    with pytest.raises(mtl.MtlError, match="cannot read"):
        mtl.load(str(tmp_path / "nothing.mtl"))


def test_latin1_names_are_read(tmp_path):
    path = tmp_path / "old.mtl"
    path.write_bytes("newmtl Béton\nKd 0.5 0.5 0.5\n".encode("latin-1"))
    assert [m.name for m in mtl.load(str(path))] == ["Béton"]
    path.write_bytes("newmtl Béton\nKd 0.5 0.5 0.5\n".encode("utf-8-sig"))  # with a BOM
    assert [m.name for m in mtl.load(str(path))] == ["Béton"]


def test_dumps_reads_back_the_same_float32_values(tmp_path):
    import numpy as np

    f32 = [float(np.float32(v)) for v in (0.1, 0.7, 1 / 3)]
    wood = mtl.Material("wood", "", 0, colors={"Ka": (f32[0], f32[1], f32[2]),
                                               "Kd": (f32[0], f32[1], f32[2]),
                                               "Ks": (1.0, 1.0, 1.0), "Ke": (0.0, 0.0, 0.0)},
                        scalars={"Ns": 30.0}, illum=2,
                        comments=["Phong highlight (r·v)^Ns: MTL illum 2 is Blinn"])
    wood.maps["map_Kd"] = mtl.TextureMap("textures/my wood.png", "", {"-s": (2.0, 2.0, 1.0)}, 0)
    text = mtl.dumps([wood, mtl.Material("flat", "", 0, colors={"Kd": (0.5, 0.5, 0.5)},
                                         illum=1)], header="made by a test")
    assert text.splitlines()[:4] == ["# made by a test", "",
                                     "# Phong highlight (r·v)^Ns: MTL illum 2 is Blinn",
                                     "newmtl wood"]
    assert "Kd 0.1 0.7 0.33333334\n" in text, "a 0.1 read as float32 is written 0.1"
    assert "Ks 1 1 1" in text and "Ns 30\n" in text
    assert "map_Kd -s 2 2 1 textures/my wood.png" in text
    path = write(tmp_path, "out.mtl", text)
    back_wood, back_flat = mtl.load(path)
    for key, value in wood.colors.items():
        assert np.float32(back_wood.colors[key]).tobytes() == np.float32(value).tobytes(), \
            "float32 read back bit for bit"
    assert back_wood.scalars == {"Ns": 30.0} and back_wood.illum == 2
    assert back_wood.maps["map_Kd"].path == "textures/my wood.png"
    assert back_wood.maps["map_Kd"].options == {"-s": (2.0, 2.0, 1.0)}
    assert back_flat.colors == {"Kd": (0.5, 0.5, 0.5)} and back_flat.illum == 1


def test_numbers_are_the_shortest_decimal_of_the_same_float32():
    """Against a search by significant digits: the fewest digits (%g) whose text reads back as
    the same float32; the written text has that many and reads back bit for bit."""
    import numpy as np

    rng = np.random.default_rng(19)
    values = np.concatenate([rng.random(2000, dtype=np.float32),
                             (rng.random(500) * 1000).astype(np.float32),
                             np.float32([0.2, 0.1, 562.5, 1e-7, 96.078431, 0.50196078, 0, 1])])
    for value in values:
        text = mtl._number_text(float(value))
        assert np.float32(text) == value, (value, text)
        fewest = next(n for n in range(1, 10) if np.float32(f"{value:.{n}g}") == value)
        digits = text.replace(".", "").replace("-", "").lstrip("0")
        assert len(digits.rstrip("0") or "0") <= fewest, (value, text, fewest)


REAL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "obj", "real")


@pytest.mark.parametrize("file_name, expected", [
    # 3ds Max (guruware's exporter): tabs, Ni 1.5, d 1, Tr 0, Tf 1 1 1 on opaque materials
    ("mustang-y.mtl", {"_mustang01Car_interior": ({"Kd": (1.0,) * 3, "Ks": (0.35,) * 3,
                                                   "Ke": (1.0,) * 3}, 0.0, 2, []),
                       "wire_028089177": ({"Ka": (1.0,) * 3, "Ks": (0.35,) * 3}, 32.0, 2, [])}),
    # 3ds Max (Max2Mtl 4.0): two spaces between keyword and values, a transparent window
    ("regr01.mtl", {"Base": ({"Kd": (0.2,) * 3, "Ks": (0.9,) * 3}, 0.0, 2, []),
                    "Windows": ({"Kd": (0.6, 0.7, 0.8)}, 0.0, 2, ["d 0.5 (transparency)"])}),
    # three.js's test file: indented by tabs
    ("verify.mtl", {"red": ({"Ka": (1.0, 0.0, 0.0), "Kd": (1.0, 0.0, 0.0)}, 0.0, 2, []),
                    "blue": ({"Kd": (0.0, 0.0, 1.0)}, 0.0, 1, [])}),
    # Ni 1, d 1: neutral, nothing to say
    ("male02.mtl", {"_01_-_Default1noCulli__01_-_Default1noCulli": (
        {"Ka": (0.64,) * 3, "Ks": (0.05,) * 3}, 30.0, 2, [])}),
    # tinyobjloader's texture options: -o with 1 to 3 values, -blendu/-blendv, -bm after
    # the file name; Kt (tinyobjloader's transmittance) is Tf
    ("texture-options-issue-85.mtl", {
        "default": ({"Kd": (0.0,) * 3}, None, None, ["map_Ns specular_highlight.jpg"]),
        "bm2": ({"Kd": (0.0,) * 3}, None, None, ["map_Ks -blendv off (not applied)"])}),
])
def test_files_of_other_programs(file_name, expected):
    warnings = []
    materials = {m.name: m for m in mtl.load(os.path.join(REAL, file_name), warnings)}
    assert warnings == []
    assert list(materials) == list(expected)
    for name, (colors, ns, illum, unsupported) in expected.items():
        material = materials[name]
        assert {k: material.colors[k] for k in colors} == colors, name
        assert material.scalars.get("Ns") == ns and material.illum == illum, name
        assert material.unsupported() == unsupported, name
    if file_name == "texture-options-issue-85.mtl":
        default, bm2 = materials["default"], materials["bm2"]
        assert default.maps["map_Ns"].options == {"-o": (0.1, 0.2, 0.3)}
        assert default.maps["bump"].options == {"-bm": (3.0,)}
        assert bm2.maps["map_Kd"].options == {"-blendu": ("on",)}
        assert (bm2.maps["bump"].path, bm2.maps["bump"].options) == ("bumpmap2.jpg",
                                                                    {"-bm": (1.5,)})


@pytest.mark.parametrize("file_name, texture, written", [
    ("spider.mtl", "wal67ar_small.jpg", ".\\wal67ar_small.jpg"),   # Windows separators
    ("mustang-y.mtl", "texture-y.jpg", "cars/texture-y.jpg"),      # relative to the OBJ's
])                                                                 # parent, not the MTL
def test_textures_of_real_files_are_found_by_their_bare_name(tmp_path, file_name, texture,
                                                            written):
    import shutil

    shutil.copy(os.path.join(REAL, file_name), tmp_path / file_name)
    first = mtl.load(str(tmp_path / file_name))[0].maps["map_Kd"]
    assert first.path == written and not first.exists
    write(tmp_path, texture, "not really an image")
    first = mtl.load(str(tmp_path / file_name))[0].maps["map_Kd"]
    assert first.exists and first.resolved == str(tmp_path / texture)


def test_meshlab_file():
    """MeshLab's writer (pymeshlab 2025.7.post1): Tr 0 of opaque materials is neutral."""
    obj = os.path.join(os.path.dirname(REAL), "meshlab_two.obj")
    materials, warnings = mtl.load_for_obj(obj)
    assert warnings == [] and list(materials) == ["material_0", "material_1"]
    assert materials["material_1"].colors["Kd"] == (0.098039, 0.298039, 0.6)
    assert materials["material_0"].scalars == {"Tr": 0.0, "Ns": 0.0}
    assert all(m.unsupported() == [] for m in materials.values())
