# SPDX-License-Identifier: GPL-3.0-or-later
"""Node inputs at their extremes never give NaN or infinity (issue 6, item 4).

Every SPEC group gets one TILE x TILE tile of one orthographic scene; each pixel is one case
whose inputs come from float32 textures (full precision: ``use_half_precision`` off) and
are drawn from lists of extreme values: distances and positions from 1e-20 to 1e15 (and P
exactly at the light), exponents -10,000 .. 10,000, zero, tiny, huge and opposite vectors
(Light Vector = -Normal, View Vector = -Light Vector, so ℓ+v = 0, the exact mirror direction,
zero Direction), α = β = γ = 0 and negative, half angles 0 and π (and beyond), colours and
intensities up to |x| = 1e6 of either sign.

* Cycles: one render, every output of every group in its own AOV (32-bit EXR): all finite.
* Eevee: one render, one AOV per material holding Σ|output components| of the group, scaled
  by 2^-100 so that every legitimate value fits the half-float film (a NaN or infinity stays
  one under abs, sum and scale; GPU min / max are not used, they may hide a NaN).
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest

import blender_env as be
from blender_env import report

TILE = 32
COLS = 4
GROUPS = be.SPEC_GROUPS
NAMES = list(GROUPS)
ROWS = math.ceil(len(NAMES) / COLS)
EE_SCALE = 2.0 ** -100

INTENSITY = [0.0, 1e-20, 1e-6, 1.0, 3.0, 1e6, -1.0, -1e6]
COEFFICIENT = [0.0, 0.0, 1e-20, 1.0, 1e6, -1.0, -1e6]          # α, β, γ
EXPONENT = [0.0, 0.0, 1e-6, 0.5, 1.0, 30.0, 1000.0, 10000.0, -1.0, -10000.0]
FALLOFF_EXPONENT = [0.0, 1.0, 2.0, 16.0, 100.0, 10000.0, -2.0, -10000.0]
DISTANCE = [0.0, 1e-20, 1e-6, 1.0, 1e6, 1e15, -1.0]
HALF_ANGLE = [0.0, 1e-6, math.pi / 2, math.pi, -1.0, 10.0]
BLINN = [0.0, 0.5, 1.0, -1.0, 2.0]
SCALAR = [0.0, 1.0, 1e6, -1e6]                                    # Factor, strengths
COLOR = [0.0, 1e-20, 1.0, 1e6, -1.0, -1e6]
MAGNITUDE = [0.0, 1e-20, 1e-6, 1.0, 1.0, 1.0, 1e6, 1e15]           # vector lengths
OFFSET = [0.0, 0.0, 1e-7, 1e-3, 1.0, 1e6, 1e15]                   # |S - P| (0: at the light)


def _unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _pick(rng, values, n):
    return np.asarray(values, dtype=np.float64)[rng.integers(0, len(values), n)]


def _vectors(rng, n):
    v = _unit(rng, n)
    axis = rng.random(n) < 0.3  # exact axes, also negative
    v[axis] = np.eye(3)[rng.integers(0, 3, axis.sum())] * rng.choice([-1.0, 1.0], (axis.sum(), 1))
    return v * _pick(rng, MAGNITUDE, n)[:, None]


def _colors(rng, n):
    c = _pick(rng, COLOR, 3 * n).reshape(n, 3)
    same = rng.random(n) < 0.5
    c[same] = c[same, :1]
    return c


def gen_cases(group, rng, n, P):
    """Extreme inputs for the n pixels of one tile; P: (n, 3) pixel centres on z = 0."""
    ins, _outs = GROUPS[group]
    x, flags = {}, None
    for name, kind in ins:
        if kind == be.V:
            if "Color" in name or name in ("A", "B"):
                x[name] = _colors(rng, n)
            else:
                x[name] = _vectors(rng, n)
        elif name in ("Intensity", "Light Intensity", "Ambient Intensity"):
            x[name] = _pick(rng, INTENSITY, n)
        elif name in ("Quadratic", "Linear", "Constant"):
            x[name] = _pick(rng, COEFFICIENT, n)
        elif name == "Exponent":
            x[name] = _pick(rng, FALLOFF_EXPONENT if group == "Phong Power Falloff" else EXPONENT, n)
        elif name == "Edge Exponent":
            x[name] = _pick(rng, EXPONENT, n)
        elif name == "Distance":
            x[name] = _pick(rng, DISTANCE, n)
        elif name == "Half Angle":
            x[name] = _pick(rng, HALF_ANGLE, n)
        elif name == "Blinn":
            x[name] = _pick(rng, BLINN, n)
        else:
            x[name] = _pick(rng, SCALAR, n)
    if "Position" in x:
        # half the cases relative to the shaded point: S = P + offset (offset 0: P at the light)
        flags = (rng.random(n) < 0.5).astype(np.float64)
        rel = flags > 0
        x["Position"][rel] = _unit(rng, rel.sum()) * _pick(rng, OFFSET, rel.sum())[:, None]
        if "Direction" in x:  # aim part of the cones at P (inside / on the edge of the cone)
            aim = rng.random(n) < 0.4
            S = np.where(rel[:, None], P + x["Position"], x["Position"])
            d = P - S
            x["Direction"][aim] = d[aim] * _pick(rng, [1.0, 1e-20, 1e6], aim.sum())[:, None]
    if "Light Vector" in x and "Normal" in x:
        k = rng.random(n)
        opp = k < 0.15                       # Light Vector = -Normal
        x["Light Vector"][opp] = -x["Normal"][opp]
        if "View Vector" in x:
            lv = (k >= 0.15) & (k < 0.35)    # View Vector = -Light Vector: ℓ+v = 0
            x["View Vector"][lv] = -x["Light Vector"][lv]
            mirror = (k >= 0.35) & (k < 0.55)  # v exactly along r = 2(ℓ·n)n - ℓ (unit ℓ, n)
            ell = _unit(rng, mirror.sum())
            nrm = _unit(rng, mirror.sum())
            r = 2.0 * np.sum(ell * nrm, axis=1, keepdims=True) * nrm - ell
            x["Light Vector"][mirror], x["Normal"][mirror], x["View Vector"][mirror] = ell, nrm, r
    return {k: v.astype(np.float32) for k, v in x.items()}, flags


def float_image(name, data):
    """Full-precision float32 Non-Color image (row 0 = bottom)."""
    bpy = be.import_bpy()
    h, w, c = data.shape
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[..., :c] = data
    img = bpy.data.images.new(name, width=w, height=h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    img.use_half_precision = False
    img.pixels.foreach_set(rgba.ravel())
    img.update()
    img.pack()
    return img


def build_material(name, group, values, flags, mode):
    """mode 'cycles': every output in AOV out<j>; 'eevee': Σ|outputs|·2^-100 in AOV 'eout'."""
    bpy = be.import_bpy()
    mat = bpy.data.materials.new(name)
    nt = be.compat().new_material_tree(mat)
    nt.nodes.clear()
    new, link = nt.nodes.new, nt.links.new
    out = new("ShaderNodeOutputMaterial")
    geo = new("ShaderNodeNewGeometry")
    uv = new("ShaderNodeUVMap").outputs["UV"]
    node = new("ShaderNodeGroup")
    node.node_tree = bpy.data.node_groups[group]

    def texture(data, key):
        t = new("ShaderNodeTexImage")
        t.image = float_image(f"{name} {key}", data)
        t.interpolation = "Closest"
        t.extension = "EXTEND"
        link(uv, t.inputs["Vector"])
        return t.outputs["Color"]

    def vmath(op, a, b=None, scale=None):
        m = new("ShaderNodeVectorMath")
        m.operation = op
        link(a, m.inputs[0])
        if b is not None:
            link(b, m.inputs[1])
        if scale is not None:
            link(scale, m.inputs["Scale"])
        return m.outputs["Vector"] if op != "DOT_PRODUCT" else m.outputs["Value"]

    def aov(aov_name, sock):
        a = new("ShaderNodeOutputAOV")
        a.aov_name = aov_name
        link(sock, a.inputs["Color"])

    ins, outs = GROUPS[group]
    scalars = [s for s, k in ins if k != be.V]
    for s, k in ins:
        if k == be.V:
            src = texture(values[s].reshape(TILE, TILE, 3), s)
            if s == "Position" and flags is not None:  # S = offset + flag·P
                sep = new("ShaderNodeSeparateColor")
                link(texture(np.repeat(flags.reshape(TILE, TILE, 1), 3, -1), "flags"), sep.inputs[0])
                src = vmath("ADD", src, vmath("SCALE", geo.outputs["Position"], scale=sep.outputs[0]))
            link(src, node.inputs[s])
    for i in range(0, len(scalars), 3):
        chunk = scalars[i:i + 3]
        data = np.zeros((TILE, TILE, 3), np.float32)
        for c, s in enumerate(chunk):
            data[..., c] = values[s].reshape(TILE, TILE)
        sep = new("ShaderNodeSeparateColor")
        link(texture(data, f"scalars{i}"), sep.inputs[0])
        for c, s in enumerate(chunk):
            link(sep.outputs[c], node.inputs[s])
    if "Shader" in dict(outs):
        link(node.outputs["Shader"], out.inputs["Surface"])
    else:
        emit = new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        link(emit.outputs[0], out.inputs["Surface"])
    if mode == "cycles":
        for j, (s, k) in enumerate(outs):
            if k != be.SH:
                aov(f"out{j}", node.outputs[s])
        return mat
    total = None
    for s, k in outs:
        if k == be.SH:
            continue
        sock = node.outputs[s]
        if k == be.S:
            comb = new("ShaderNodeCombineXYZ")
            link(sock, comb.inputs[0])
            sock = comb.outputs[0]
        ones = new("ShaderNodeVectorMath")
        ones.operation = "DOT_PRODUCT"
        link(vmath("ABSOLUTE", sock), ones.inputs[0])
        ones.inputs[1].default_value = (1.0, 1.0, 1.0)
        part = ones.outputs["Value"]
        if total is None:
            total = part
        else:
            add = new("ShaderNodeMath")
            add.operation = "ADD"
            link(total, add.inputs[0])
            link(part, add.inputs[1])
            total = add.outputs[0]
    scale = new("ShaderNodeMath")
    scale.operation = "MULTIPLY"
    link(total, scale.inputs[0])
    scale.inputs[1].default_value = EE_SCALE
    aov("eout", scale.outputs[0])
    return mat


def _pixel_centres(t):
    col, row = t % COLS, t // COLS
    jj, ii = np.meshgrid(np.arange(TILE), np.arange(TILE))
    return np.stack([col + (jj.ravel() + 0.5) / TILE, row + (ii.ravel() + 0.5) / TILE,
                     np.zeros(TILE * TILE)], axis=1)


@pytest.fixture(scope="module")
def sweep(extension, blender_tmp):
    bpy = be.import_bpy()
    be.reset_empty_file()
    be.load_groups()
    rng = np.random.default_rng(6)
    scene = be.new_scene("PhongExtremes", COLS * TILE, ROWS * TILE, "cycles")
    be.add_ortho_camera(scene, (COLS / 2.0, ROWS / 2.0), float(COLS), float(ROWS))
    for j in range(6):
        be.add_aov(scene, f"out{j}")
    cases, eevee_mats = {}, []
    for t, group in enumerate(NAMES):
        col, row = t % COLS, t // COLS
        values, flags = gen_cases(group, rng, TILE * TILE, _pixel_centres(t))
        cases[group] = values
        mat_c = build_material(f"XC {group}", group, values, flags, "cycles")
        mat_e = build_material(f"XE {group}", group, values, flags, "eevee")
        obj = be.add_uv_plane(scene, f"x{t}", float(col), float(row), 1.0, mat_c)
        eevee_mats.append((obj, mat_e))
    result = {"cases": cases, "seconds": {}}
    for engine in ("cycles", "eevee"):
        if engine == "eevee":
            be.switch_to_eevee(scene, eevee_mats)
        path = os.path.join(str(blender_tmp), f"extremes_{engine}.exr")
        t0 = time.perf_counter()
        be.render_exr(scene, path)
        result["seconds"][engine] = time.perf_counter() - t0
        report(f"[timing] extremes sweep, {engine}: {result['seconds'][engine]:.1f} s "
               f"({len(NAMES)} groups x {TILE * TILE} cases)")
        result[engine] = {k: v[::-1] for k, v in be.read_multilayer_exr(path).items()}
    bpy.data.scenes.remove(scene)
    return result


def _tile(passes, key, t):
    col, row = t % COLS, t // COLS
    a = passes[key][row * TILE:(row + 1) * TILE, col * TILE:(col + 1) * TILE]
    return a.reshape(TILE * TILE, -1)


def _first_bad(values, bad):
    i = int(np.flatnonzero(bad)[0])
    return ", ".join(f"{k}={np.asarray(v[i]).tolist()}" for k, v in values.items())


@pytest.mark.cycles
@pytest.mark.parametrize("group", NAMES)
def test_cycles_outputs_finite_at_extremes(sweep, group):
    t = NAMES.index(group)
    _ins, outs = GROUPS[group]
    problems = []
    keys = [(f"out{j}", s, k) for j, (s, k) in enumerate(outs) if k != be.SH]
    if group == "Phong Shading":
        keys.append(("Combined", "Shader", be.V))
    for key, name, kind in keys:
        got = _tile(sweep["cycles"], key, t)[:, :3 if kind == be.V else 1]
        bad = ~np.isfinite(got).all(axis=1)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            problems.append(f"{group}.{name}: {int(bad.sum())} of {bad.size} non-finite, e.g. "
                            f"{got[i].tolist()} for {_first_bad(sweep['cases'][group], bad)}")
    assert not problems, "\n".join(problems)


@pytest.mark.eevee
@pytest.mark.parametrize("group", NAMES)
def test_eevee_outputs_finite_at_extremes(sweep, group):
    got = _tile(sweep["eevee"], "eout", NAMES.index(group))[:, 0]
    bad = ~np.isfinite(got)
    assert not bad.any(), (f"{group}: {int(bad.sum())} of {bad.size} non-finite (Σ|outputs|), "
                           f"e.g. {got[bad][0]} for {_first_bad(sweep['cases'][group], bad)}")


def test_sweep_covers_the_extremes(sweep):
    """The cases hold what the issue names (so the sweep cannot silently shrink)."""
    c = sweep["cases"]
    assert (c["Phong Specular"]["Exponent"] == 10000).any()
    assert (c["Phong Spot Light"]["Edge Exponent"] == -10000).any()
    assert (c["Phong Power Falloff"]["Exponent"] == -10000).any()
    assert (c["Phong Power Falloff"]["Distance"] == np.float32(1e-20)).any()
    assert (c["Phong Spot Light"]["Half Angle"] == np.float32(math.pi)).any()
    assert (np.abs(c["Phong Color Multiply"]["A"]) == 1e6).any()
    spec = c["Phong Blinn Specular"]
    assert (np.abs(spec["Light Vector"] + spec["View Vector"]).sum(axis=1) == 0).any()
    assert ((spec["Light Vector"] == -spec["Normal"]).all(axis=1)
            & (np.abs(spec["Normal"]).sum(axis=1) > 0)).any()
    assert (np.abs(c["Phong Directional Light"]["Direction"]).sum(axis=1) == 0).any()
    assert max(sweep["seconds"].values()) < 120
