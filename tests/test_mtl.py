# SPDX-License-Identifier: GPL-3.0-or-later
"""core/mtl.py without Blender: MTL statements as Alias|Wavefront's File Formats 4.2 define
them, several libraries per OBJ, and errors that name file and line."""

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
    ("newmtl a\nKd 0.5 abc 0.1\n", 2, "Kd: 'abc' is not a number"),
    ("newmtl a\nKd 0.5 0.1\n", 2, "Kd needs 1 or 3 numbers (r [g b]), got 2"),
    ("newmtl a\nNs nan\n", 2, "Ns: 'nan' is not a finite number"),
    ("newmtl a\nNs -3\n", 2, "Ns -3 is out of range"),
    ("newmtl a\nd 1.5\n", 2, "d 1.5 is out of range"),
    ("newmtl a\nillum 2.5\n", 2, "illum needs an integer from 0 to 10, got '2.5'"),
    ("newmtl a\n\nillum 11\n", 3, "illum needs an integer from 0 to 10, got '11'"),
    ("# header\nKd 1 1 1\n", 2, "Kd before any newmtl"),
    ("newmtl\n", 1, "newmtl without a name"),
    ("newmtl a\nmap_Kd\n", 2, "map_Kd: no file name"),
    ("newmtl a\nmap_Kd -s\n", 2, "map_Kd: option -s needs 1 value(s)"),
    ("newmtl a\nmap_Kd -mm 0.1 x.png\n", 2, "map_Kd: option -mm needs 2 value(s)"),
    ("newmtl a\nmap_Kd -bm abc x.png\n", 2, "map_Kd -bm: 'abc' is not a number"),
])
def test_bad_statements_name_file_and_line(tmp_path, text, line, message):
    path = write(tmp_path, "bad.mtl", text)
    with pytest.raises(mtl.MtlError) as excinfo:
        mtl.load(path)
    assert str(excinfo.value) == f"{path}:{line}: {message}"
    assert (excinfo.value.path, excinfo.value.line) == (path, line)


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


def test_dumps_reads_back_the_same_values(tmp_path):
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
    assert "Ks 1 1 1" in text and "Ns 30\n" in text
    assert "map_Kd -s 2 2 1 textures/my wood.png" in text
    path = write(tmp_path, "out.mtl", text)
    back_wood, back_flat = mtl.load(path)
    assert back_wood.colors == wood.colors, "floats read back bit for bit"
    assert back_wood.scalars == {"Ns": 30.0} and back_wood.illum == 2
    assert back_wood.maps["map_Kd"].path == "textures/my wood.png"
    assert back_wood.maps["map_Kd"].options == {"-s": (2.0, 2.0, 1.0)}
    assert back_flat.colors == {"Kd": (0.5, 0.5, 0.5)} and back_flat.illum == 1
