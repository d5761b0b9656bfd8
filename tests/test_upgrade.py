# SPDX-License-Identifier: GPL-3.0-or-later
"""The files users already have (issue 42): a Phong scene saved by each earlier supported
release opens and renders right on this one, and the newest release's file on the LTS before it.

The files are ``tests/data/upgrade/phong_<bpy>.blend``, one per release of
requirements/releases.txt, each saved by that release (``tests/data/make_upgrade_scene.py``,
tests/data/README.md): Apply Phong Material on four objects, a Blinn material, a Per Vertex
one, point lights with the quadratic and the power falloff, a spot under a turned and scaled
empty with an edge exponent, a sun.  Each file is opened as a user opens it (the load handlers
upgrade it, no click) and checked three ways:

- the lights group's inputs are fed by the controls whose names the contract gives them (a
  rebuilt interface once moved every control to another input: 90.7% of Eevee's pixels within
  1/255, the highlights gone), and each control holds the value the maker set;
- Compare Phong Scene (``engine.run``, what ``phong compare`` runs): Eevee within 1/255 of the
  reference on at least 99.5% of the pixels, Cycles within 1e-4;
- Cycles' picture equals, within 1e-4, the picture of the same scene made on this release
  (the maker run here): the reference is computed from what the lights group sees, so it
  alone would not see a control on the wrong input.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
MAKER = os.path.join(DATA, "make_upgrade_scene.py")

#: input of the lights group -> the control node that feeds it (docs/contract.md).
FEEDS = {"Object Color": "phong_object_color", "Specular Color": "phong_specular_color",
         "Exponent": "phong_exponent", "Blinn": "phong_blinn",
         "Irradiant Color": "phong_irradiant_color",
         "Specular Strength": "phong_specular_strength"}
#: what make_upgrade_scene.py sets: material -> {control: value}.
SET = {"Phong Clay": {"phong_specular_color": (0.9, 0.8, 0.6), "phong_exponent": 24.0,
                      "phong_irradiant_color": (0.03, 0.0, 0.02),
                      "phong_object_color": (0.7, 0.3, 0.1)},
       "Phong Enamel": {"phong_blinn": 1.0, "phong_exponent": 60.0,
                        "phong_specular_color": (0.6, 0.7, 1.0),
                        "phong_object_color": (0.1, 0.35, 0.8)},
       "Phong Jade": {"phong_exponent": 12.0, "phong_object_color": (0.2, 0.7, 0.4),
                      "phong_specular_color": (1.0, 1.0, 1.0)},
       "Phong Floor Paint": {"phong_object_color": (0.5, 0.55, 0.6),
                             "phong_specular_color": (1.0, 1.0, 1.0)}}


def _version(release: str) -> tuple:
    return tuple(int(part) for part in release.split("."))


def _cases() -> list:
    """The releases whose file this release must open right: every earlier one, and on the
    LTS before the newest the newest's."""
    releases = {bpy: flags for bpy, _python, flags in be.supported_releases()}
    running = be.bpy_release()
    newest = max(releases, key=_version)
    lts = [r for r, flags in releases.items()
           if "lts" in flags and _version(r) < _version(newest)]
    cases = sorted((r for r in releases if _version(r) < _version(running)), key=_version)
    if lts and running == max(lts, key=_version):
        cases.append(newest)
    return cases


def _file(release: str) -> str:
    return os.path.join(DATA, "upgrade", f"phong_{release}.blend")


def test_every_supported_release_has_its_file():
    """One file per supported release, so the matrix below is whole."""
    missing = [r for r, _python, _flags in be.supported_releases()
               if not os.path.exists(_file(r))]
    assert not missing, f"no tests/data/upgrade file saved by {missing}"


def _render_cycles(bpy, scene, path: str) -> np.ndarray:
    from phong_nodes.addon.scene import render  # noqa: PLC0415

    render.plain_picture(scene, 64, 48)
    be.configure_engine(scene, "cycles")
    be.set_output_multilayer_exr(scene)
    be.render_exr(scene, path)
    return be.read_multilayer_exr(path)["Combined"][..., :3]


@pytest.mark.eevee
@pytest.mark.cycles
# The quick tests (tools/phong.sh test) open the file of the newest of these releases; the
# older ones' render in the slow run (CI's `test --all -m slow`).
@pytest.mark.parametrize("saved_by", [pytest.param(r, id=r, marks=() if r == _cases()[-1]
                                                   else pytest.mark.slow) for r in _cases()])
def test_a_file_of_another_release_renders_right(bpy_clean, tmp_path, saved_by):
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    # The same scene made here, now: the picture the upgraded file must show.
    fresh = str(tmp_path / "made_here.blend")
    made = subprocess.run([sys.executable, MAKER, fresh], capture_output=True, text=True,
                          timeout=600, cwd=be.REPO_ROOT)
    assert made.returncode == 0 and os.path.exists(fresh), made.stdout[-2000:] + made.stderr[-2000:]
    bpy.ops.wm.open_mainfile(filepath=fresh)
    expected = _render_cycles(bpy, bpy.data.scenes["Upgrade"], str(tmp_path / "here.exr"))

    bpy.ops.wm.open_mainfile(filepath=_file(saved_by))
    scene = bpy.data.scenes["Upgrade"]
    phong = {m.name: m for m in bpy.data.materials if recipe.is_phong_material(m)}
    assert sorted(phong) == sorted(SET)
    for name, material in phong.items():
        nodes = material.node_tree.nodes
        node = nodes[recipe.LIGHTS_NODE]
        fed = {s.name: [l.from_node.name for l in s.links] for s in node.inputs}
        assert {i: fed.get(i) for i in FEEDS} == {i: [c] for i, c in FEEDS.items()}, name
        for control, value in SET[name].items():
            got = nodes[control].outputs[0].default_value
            got = tuple(got)[:3] if hasattr(got, "__len__") else got
            assert got == pytest.approx(value, abs=1e-6), (name, control)
    assert phong["Phong Jade"].phong.shading == "VERTEX"

    metrics = engine.run(scene, str(tmp_path / "report"))
    pairs = metrics["pairs"]
    eevee_share = 1.0 - pairs["eevee-reference"]["share_over_1_255"]
    cycles_max = pairs["cycles-reference"]["max_abs"]
    got = _render_cycles(bpy, scene, str(tmp_path / "upgraded.exr"))
    against_fresh = float(np.abs(got - expected).max())
    be.report(f"[upgrade {saved_by} -> {be.bpy_release()}] Eevee {eevee_share:.3%} within "
              f"1/255 (max {pairs['eevee-reference']['max_abs']:.2e}), Cycles max "
              f"{cycles_max:.2e}; Cycles vs the scene made here: max {against_fresh:.2e}")
    assert eevee_share >= 0.995, metrics["verdict"]
    assert cycles_max <= 1e-4, metrics["verdict"]
    assert against_fresh <= 1e-4


@pytest.mark.parametrize("users", [1, 3])
def test_a_rewritten_group_keeps_its_users_links_by_name(bpy_clean, users):
    """``rig.rewrite`` of a group whose interface is made again (cleared, its sockets in
    another order, one more): each group node using it keeps its links, and its unlinked input
    values, on the sockets of the same name, in place (one user) and through a new group (several
    users)."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import rig  # noqa: PLC0415

    def write(names):
        def writer(tree):
            tree.interface.clear()
            for name in names:
                tree.interface.new_socket(name, in_out="INPUT", socket_type="NodeSocketFloat")
            tree.interface.new_socket("Out", in_out="OUTPUT", socket_type="NodeSocketFloat")
        return writer

    group = bpy.data.node_groups.new("Kept", "ShaderNodeTree")
    write(["A", "B", "C"])(group)
    made = []
    for index in range(users):
        material = bpy.data.materials.new(f"User {index}")
        material.use_nodes = True
        tree = material.node_tree
        node = tree.nodes.new("ShaderNodeGroup")
        node.node_tree = group
        a, c = tree.nodes.new("ShaderNodeValue"), tree.nodes.new("ShaderNodeValue")
        a.name, c.name = "feeds A", "feeds C"
        tree.links.new(a.outputs[0], node.inputs["A"])
        tree.links.new(c.outputs[0], node.inputs["C"])
        node.inputs["B"].default_value = 0.25 + index
        math = tree.nodes.new("ShaderNodeMath")
        tree.links.new(node.outputs["Out"], math.inputs[1])
        made.append((material, node.name, math.name))
    assert group.users == users
    kept = rig.rewrite(group, write(["New", "C", "B", "A"]))
    assert [i.name for i in kept.interface.items_tree if i.in_out == "INPUT"] == [
        "New", "C", "B", "A"]
    for index, (material, node_name, math_name) in enumerate(made):
        node = material.node_tree.nodes[node_name]
        assert node.node_tree == kept
        fed = {s.name: [l.from_node.name for l in s.links] for s in node.inputs}
        assert fed == {"New": [], "C": ["feeds C"], "B": [], "A": ["feeds A"]}
        assert node.inputs["B"].default_value == pytest.approx(0.25 + index)
        math = material.node_tree.nodes[math_name]
        assert [l.from_socket.name for l in math.inputs[1].links] == ["Out"]
