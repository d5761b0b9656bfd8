# SPDX-License-Identifier: GPL-3.0-or-later
"""Sample-pixel render tests: every SPEC node group against the numpy reference.

One small orthographic scene holds one 48x48 tile per (group, Eevee output pack); every pixel
centre samples the centre of one texel of float32 input textures, so every pixel is an
independent random test case.  Cycles writes every group input and output and Geometry
Position / Normal / Incoming as AOVs (one multilayer EXR); the reference is evaluated on the
inputs *as read back*.  The same scene is then rendered with Eevee, one output pack per tile in
a single AOV (Eevee's compile time grows fast with the number of AOVs), and compared with the
reference evaluated on the Cycles inputs of the same pixel.

A second scene (UV spheres, perspective camera) leaves Normal and View Vector unlinked, so the
groups must fall back to Geometry Normal / Incoming.

Tolerances
  Cycles: |got - ref| <= 1e-4 * max(1, |ref|) for every compared sample (the relative scale
          only matters for outputs larger than 1, e.g. point-light intensities near the light).
  Eevee:  >= 99.5 % of samples within 5e-3 * max(1, |ref|), none beyond 5e-2 * max(1, |ref|).
  Samples within 1e-5 of a discontinuity (|l.n|, |r.v|, |h.n|, |l+v|, |cos w - cos th|)
  are left out of the comparison and counted (they must stay a tiny fraction).
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest

import blender_env as be
from blender_env import report
from phong_nodes.node_groups import reference

TILE = 48
EPS_DISC = 1e-5
CY_TOL = 1e-4
EE_TOL, EE_MAX, EE_FRACTION = 5e-3, 5e-2, 0.995
EE_SCALE = 2.0 ** -10  # Eevee AOVs are half floats: scale by a power of two to extend the range
MAX_EXCLUDED_FRACTION = 0.01

GROUPS = be.SPEC_GROUPS

# Eevee: which outputs one tile's material writes into its single AOV (<= 3 channels).
EEVEE_PACKS = {
    "Phong Directional Light": [["Light Vector"], ["Intensity"]],
    "Phong Point Light": [["Light Vector"], ["Intensity", "Distance"]],
    "Phong Spot Light": [["Light Vector"], ["Intensity", "Distance", "Cos Angle"], ["In Cone"]],
    "Phong Power Falloff": [["Intensity"]],
    "Phong Irradiant": [["Color"]],
    "Phong Ambient": [["Color"]],
    "Phong Diffuse": [["Color"]],
    "Phong Specular": [["Color"]],
    "Phong Blinn Specular": [["Color"]],
    "Phong Color Add": [["Color"]],
    "Phong Color Multiply": [["Color"]],
    "Phong Shading": [["Irradiant"], ["Ambient"], ["Diffuse"], ["Specular"], ["Color"]],
    "three.js Point Light": [["Light Vector"], ["Intensity", "Distance"]],
    "three.js Spot Light": [["Light Vector"], ["Intensity", "Distance", "Cos Angle"]],
    "three.js Ambient": [["Color"]],
    "three.js Phong": [["Diffuse"], ["Specular"], ["Color"]],
    "X3D Directional Light": [["Light Vector"], ["Intensity", "Ambient"]],
    "X3D Point Light": [["Light Vector"], ["Intensity", "Ambient", "Distance"]],
    "X3D Spot Light": [["Light Vector"], ["Intensity", "Ambient", "Distance"], ["Spot Angle"]],
}
TILES = [(g, k) for g in GROUPS for k in range(len(EEVEE_PACKS[g]))]
COLS = 5
ROWS = math.ceil(len(TILES) / COLS)

CURVED_GROUPS = ["Phong Diffuse", "Phong Specular", "Phong Blinn Specular", "Phong Shading",
                 "three.js Phong"]
CURVED_RES = 160  # picture height; spheres in CURVED_COLS columns of two rows
CURVED_COLS = 3

GEO_POS_SOCKETS = {"Phong Point Light": "Position", "Phong Spot Light": "Position",
                   "three.js Point Light": "Position", "three.js Spot Light": "Position",
                   "X3D Point Light": "Position", "X3D Spot Light": "Position"}
SPOTS = ("Phong Spot Light", "three.js Spot Light", "X3D Spot Light")


# ============================================================== random inputs

def _unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _f16(a):
    """Round to float16-representable values: both engines then see the same texture values."""
    return np.asarray(a, dtype=np.float16).astype(np.float32)


def gen_inputs(group, rng, n, P, N, I, curved=False):
    """Random inputs for n samples (dict socket -> (n,3)|(n,)) and the 'use geometry P' flag."""
    ins, _outs = GROUPS[group]
    x = {}
    degenerate = rng.random(n) < 0.08
    for name, kind in ins:
        if kind == be.V:
            if name in ("Light Vector",):
                v = _unit(rng, n)
                v[rng.random(n) < 0.04] = 0.0
            elif name in ("Normal", "View Vector"):
                v = _unit(rng, n) * rng.uniform(0.3, 2.0, (n, 1))
                v[rng.random(n) < 0.25] = 0.0
            elif name == "Direction":
                v = _unit(rng, n) * rng.uniform(0.2, 3.0, (n, 1))
                v[rng.random(n) < 0.05] = 0.0
            elif name == "Position":
                v = rng.uniform(-4.0, 4.0, (n, 3))
            else:  # colours
                v = rng.uniform(0.0, 1.2, (n, 3))
            x[name] = v
        else:
            if name in ("Intensity", "Light Intensity", "Ambient Intensity"):
                s = rng.uniform(0.0, 3.0, n)
            elif name in ("Quadratic", "Linear", "Constant"):
                s = rng.uniform(0.0, 2.0, n)
            elif name == "Half Angle":
                s = rng.uniform(0.0, math.pi, n)
                s[rng.random(n) < 0.03] = 0.0
                s[rng.random(n) < 0.03] = math.pi
            elif name == "Edge Exponent":
                s = rng.uniform(0.0, 200.0, n)
                s[rng.random(n) < 0.15] = 0.0
            elif name == "Exponent":
                if group == "Phong Power Falloff":
                    s = rng.uniform(0.0, 6.0, n)
                    s[rng.random(n) < 0.1] = 0.0
                elif curved:
                    s = rng.uniform(0.0, 20.0, n)
                else:
                    s = rng.uniform(0.0, 200.0, n)
                    s[rng.random(n) < 0.1] = 0.0
            elif name == "Distance" and group.startswith("three.js"):  # the cut-off
                s = rng.uniform(0.5, 10.0, n)
                s[rng.random(n) < 0.4] = 0.0
            elif name == "Distance":
                s = rng.uniform(0.0, 6.0, n)
                s[rng.random(n) < 0.03] = 0.0
            elif name == "Decay":
                s = rng.uniform(0.0, 3.0, n)
                s[rng.random(n) < 0.3] = 2.0
            elif name == "Angle":
                s = rng.uniform(0.05, math.pi / 2.0, n)
            elif name in ("Beam Width", "Cut Off Angle"):  # either may be the larger
                s = rng.uniform(0.0, math.pi / 2.0, n)
            elif name == "Radius":  # negative: no cut-off; 0: only at the light
                s = rng.uniform(-1.0, 8.0, n)
                s[rng.random(n) < 0.1] = 100.0
            elif name == "Penumbra":
                s = rng.uniform(0.0, 1.0, n)
                s[rng.random(n) < 0.3] = 0.0
            elif name == "Shininess":
                s = rng.uniform(0.0, 20.0 if curved else 200.0, n)
                s[rng.random(n) < 0.05] = 0.0
            elif name == "Specular Strength":
                s = rng.uniform(0.0, 1.0, n)
                s[rng.random(n) < 0.2] = 0.0
                s[rng.random(n) < 0.3] = 1.0
            elif name == "Blinn":
                s = rng.uniform(0.0, 1.0, n)
                s[rng.random(n) < 0.2] = 0.0
                s[rng.random(n) < 0.2] = 1.0
            else:  # Factor, strengths
                s = rng.uniform(0.0, 2.0, n)
            x[name] = s
    # geometry-dependent cases ------------------------------------------------
    use_geo = np.zeros(n, dtype=bool)
    if group in GEO_POS_SOCKETS:
        # spot: aim part of the cones at P so that in/out of cone is balanced
        if group in SPOTS:
            aim = rng.random(n) < 0.5
            to_p = P - x["Position"]
            to_p /= np.maximum(np.linalg.norm(to_p, axis=1, keepdims=True), 1e-9)
            jitter = _unit(rng, n) * rng.uniform(0.0, 0.8, (n, 1))
            x["Direction"][aim] = (to_p + jitter)[aim] * rng.uniform(0.3, 2.0, (n, 1))[aim]
        # r = 0: the light sits on the shaded point (flag: Position <- Geometry Position)
        use_geo = degenerate.copy()
        falloff = [s for s in ("Quadratic", "Linear", "Constant") if s in x]
        for s in falloff:
            x[s][degenerate & (rng.random(n) < 0.5)] = 0.0
        allzero = rng.random(n) < 0.04
        for s in falloff:
            x[s][allzero] = 0.0
    if "View Vector" in x and "Light Vector" in x and not curved:
        # many samples near the mirror / half-vector direction, so highlights are exercised
        nrm = np.where(np.linalg.norm(x["Normal"], axis=1, keepdims=True) > 0,
                       x["Normal"], N)
        nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
        ell = x["Light Vector"]
        r = 2.0 * np.sum(ell * nrm, axis=1, keepdims=True) * nrm - ell
        near = (rng.random(n) < 0.5) & (np.linalg.norm(x["View Vector"], axis=1) > 0)
        vv = r + _unit(rng, n) * rng.uniform(0.0, 0.4, (n, 1))
        x["View Vector"][near] = vv[near] * rng.uniform(0.5, 2.0, (n, 1))[near]
    if "Exponent" in x and group != "Phong Power Falloff":
        x["Exponent"][degenerate & (rng.random(n) < 0.3)] = 1000.0
        x["Exponent"][degenerate & (rng.random(n) < 0.3)] = 0.0
    if group == "Phong Power Falloff":
        x["Distance"][degenerate] = 0.0
        x["Exponent"][degenerate & (rng.random(n) < 0.5)] = 0.0
    for name in list(x):
        arr = _f16(x[name])
        if name == "Half Angle":  # keep exact 0 and pi
            arr = np.where(np.isclose(x[name], math.pi), np.float32(math.pi), arr)
        x[name] = arr
    return x, use_geo


# ============================================================== material building

def _input_layout(group, linked):
    """Image layout: list of images, each a list of (socket, channel or None for RGB)."""
    ins, _ = GROUPS[group]
    images, scalars = [], []
    for name, kind in ins:
        if name not in linked:
            continue
        if kind == be.V:
            images.append([(name, None)])
        else:
            scalars.append(name)
    for i in range(0, len(scalars), 3):
        images.append([(s, c) for c, s in enumerate(scalars[i:i + 3])])
    return images


def _make_images(prefix, group, layout, values, use_geo, shape):
    h, w = shape
    imgs = []
    for k, entries in enumerate(layout):
        data = np.zeros((h, w, 3), dtype=np.float32)
        for name, ch in entries:
            v = values[name].reshape(h, w, -1)
            if ch is None:
                data[...] = v
            else:
                data[..., ch] = v[..., 0]
        imgs.append(be.float_image(f"{prefix} {k}", data))
    flag_img = None
    if group in GEO_POS_SOCKETS:
        f = use_geo.reshape(h, w).astype(np.float32)
        data = np.stack([1.0 - f, f, np.zeros_like(f)], axis=-1)
        flag_img = be.float_image(f"{prefix} flags", data)
    return imgs, flag_img


class MatBuilder:
    def __init__(self, name):
        bpy = be.import_bpy()
        self.mat = bpy.data.materials.new(name)
        self.nt = be.compat().new_material_tree(self.mat)
        self.nt.nodes.clear()
        self.out = self.new("ShaderNodeOutputMaterial")
        self.geo = self.new("ShaderNodeNewGeometry")
        uvn = self.new("ShaderNodeUVMap")
        self.uv = uvn.outputs["UV"]

    def new(self, kind):
        return self.nt.nodes.new(kind)

    def link(self, a, b):
        self.nt.links.new(a, b)

    def texture(self, image):
        t = self.new("ShaderNodeTexImage")
        t.image = image
        t.interpolation = "Closest"
        t.extension = "EXTEND"
        self.link(self.uv, t.inputs["Vector"])
        return t.outputs["Color"]

    def separate(self, color):
        s = self.new("ShaderNodeSeparateColor")
        self.link(color, s.inputs[0])
        return s.outputs

    def vmath(self, op, a, b=None, scale=None):
        m = self.new("ShaderNodeVectorMath")
        m.operation = op
        self.link(a, m.inputs[0])
        if b is not None:
            self.link(b, m.inputs[1])
        if scale is not None:
            if isinstance(scale, float):
                m.inputs["Scale"].default_value = scale
            else:
                self.link(scale, m.inputs["Scale"])
        return m.outputs["Vector"]

    def aov(self, name, sock):
        a = self.new("ShaderNodeOutputAOV")
        a.aov_name = name
        self.link(sock, a.inputs["Color"])

    def emission_surface(self, color=(0.5, 0.5, 0.5)):
        e = self.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = (*color, 1.0)
        e.inputs["Strength"].default_value = 1.0
        self.link(e.outputs[0], self.out.inputs["Surface"])


def build_material(name, group, images, flag_img, layout, mode, pack=None, unlinked_zero=()):
    """mode 'cycles': every input/output/geometry as AOVs; 'eevee': one pack into AOV 'eout'."""
    bpy = be.import_bpy()
    b = MatBuilder(name)
    node = b.new("ShaderNodeGroup")
    node.node_tree = bpy.data.node_groups[group]
    sources = {}
    for img, entries in zip(images, layout):
        col = b.texture(img)
        if entries[0][1] is None:
            sources[entries[0][0]] = col
        else:
            chans = b.separate(col)
            for s, c in entries:
                sources[s] = chans[c]
    if group in GEO_POS_SOCKETS and flag_img is not None:
        sock = GEO_POS_SOCKETS[group]
        fl = b.separate(b.texture(flag_img))
        keep = b.vmath("SCALE", sources[sock], scale=fl[0])
        geo = b.vmath("SCALE", b.geo.outputs["Position"], scale=fl[1])
        sources[sock] = b.vmath("ADD", keep, geo)
    for s, src in sources.items():
        b.link(src, node.inputs[s])
    for s in unlinked_zero:
        node.inputs[s].default_value = (0.0, 0.0, 0.0)
    ins, outs = GROUPS[group]
    has_shader = any(k == be.SH for _, k in outs)
    if has_shader:
        b.link(node.outputs["Shader"], b.out.inputs["Surface"])
    else:
        b.emission_surface()
    if mode == "cycles":
        for i, (s, _k) in enumerate(ins):
            if s in sources:
                b.aov(f"in{i:02d}", sources[s])
        for j, (s, k) in enumerate(outs):
            if k != be.SH:
                b.aov(f"out{j}", node.outputs[s])
        b.aov("gP", b.geo.outputs["Position"])
        b.aov("gN", b.geo.outputs["Normal"])
        b.aov("gI", b.geo.outputs["Incoming"])
        val = b.new("ShaderNodeValue")
        val.outputs[0].default_value = 1.0
        b.aov("hit", val.outputs[0])
    else:
        names = EEVEE_PACKS[group][pack] if pack is not None else pack
        if len(names) == 1 and dict(outs)[names[0]] == be.V:
            vec = node.outputs[names[0]]
        else:
            comb = b.new("ShaderNodeCombineXYZ")
            for c, s in enumerate(names):
                b.link(node.outputs[s], comb.inputs[c])
            vec = comb.outputs[0]
        b.aov("eout", b.vmath("SCALE", vec, scale=EE_SCALE))
    return b.mat


def cycles_aovs(scene, max_inputs):
    for i in range(max_inputs):
        be.add_aov(scene, f"in{i:02d}")
    for j in range(6):
        be.add_aov(scene, f"out{j}")
    for g in ("gP", "gN", "gI", "hit"):
        be.add_aov(scene, g)


# ============================================================== reading + reference

def read_inputs(passes, group, ys, xs, linked=None):
    """Inputs (as rendered by Cycles) and geometry at pixel rows ys, cols xs (image-row order)."""
    ins, _ = GROUPS[group]
    vals = {}
    for i, (s, k) in enumerate(ins):
        if linked is not None and s not in linked:
            continue
        a = passes[f"in{i:02d}"][ys, xs].astype(np.float64)
        vals[s] = a[..., :3] if k == be.V else a[..., 0]
    geo = {key: passes[p][ys, xs, :3].astype(np.float64)
           for key, p in (("Position", "gP"), ("Normal", "gN"), ("Incoming", "gI"))}
    return vals, geo


def read_outputs(passes, group, ys, xs):
    _, outs = GROUPS[group]
    res = {}
    for j, (s, k) in enumerate(outs):
        if k == be.SH:
            continue
        a = passes[f"out{j}"][ys, xs].astype(np.float64)
        res[s] = a[..., :3] if k == be.V else a[..., 0]
    return res


def _norm(v):
    return reference.normalize(v)


def near_discontinuity(group, vals, geo):
    """Samples within EPS_DISC of a discontinuity of the group's formula."""
    n_samples = geo["Position"].shape[0]
    bad = np.zeros(n_samples, dtype=bool)
    if "Light Vector" in vals:
        ell = vals["Light Vector"]
        n = reference.resolve_normal(vals.get("Normal", np.zeros_like(ell)), geo["Normal"])
        ln = np.sum(ell * n, axis=1)
        # an exactly zero Light Vector gives exactly zero dot products in every engine
        lit = np.linalg.norm(ell, axis=1) > 0
        if group != "Phong Diffuse":  # max(l.n, 0) is continuous; the specular masks are not
            bad |= lit & (np.abs(ln) < EPS_DISC)
        if group in ("Phong Specular", "Phong Blinn Specular", "Phong Shading"):
            v = reference.resolve_view(vals.get("View Vector", np.zeros_like(ell)), geo["Incoming"])
            r = 2.0 * ln[:, None] * n - ell
            rv = np.sum(r * v, axis=1)
            lv = ell + v
            h = _norm(lv)
            hn = np.sum(h * n, axis=1)
            if group != "Phong Blinn Specular":
                bad |= lit & (np.abs(rv) < EPS_DISC)
            if group != "Phong Specular":
                bad |= lit & ((np.abs(hn) < EPS_DISC) | (np.linalg.norm(lv, axis=1) < EPS_DISC))
        if group == "three.js Phong":  # normalize(ℓ + v); (n·h)^s with s near 0 is a step
            v = reference.resolve_view(vals.get("View Vector", np.zeros_like(ell)), geo["Incoming"])
            lv = ell + v
            hn = np.sum(_norm(lv) * n, axis=1)
            bad |= lit & ((np.abs(hn) < EPS_DISC) | (np.linalg.norm(lv, axis=1) < EPS_DISC))
    if group == "three.js Spot Light":  # penumbra 0: a step at the cone
        ell = _norm(vals["Position"] - geo["Position"])
        cw = -np.sum(ell * _norm(vals["Direction"]), axis=1)
        bad |= np.abs(cw - np.cos(vals["Angle"])) < EPS_DISC
    if group in ("X3D Point Light", "X3D Spot Light"):  # the radius is a step
        d = np.linalg.norm(vals["Position"] - geo["Position"], axis=1)
        bad |= np.abs(d - vals["Radius"]) < EPS_DISC
    if group == "X3D Spot Light":
        ell = _norm(vals["Position"] - geo["Position"])
        cw = -np.sum(ell * _norm(vals["Direction"]), axis=1)
        w = np.arccos(np.clip(cw, -1.0, 1.0))
        # a step at the cut-off when beamWidth >= cutOffAngle; acos is ill-conditioned near
        # the axis (a float32 cosine moves ω by ~sqrt(1e-7)) and the opposite way
        bad |= np.abs(w - vals["Cut Off Angle"]) < EPS_DISC
        bad |= np.abs(w - vals["Beam Width"]) < EPS_DISC
        bad |= np.abs(cw) > 1.0 - 1e-6
    if group == "Phong Spot Light":
        ell = _norm(vals["Position"] - geo["Position"])
        u = _norm(vals["Direction"])
        cw = -np.sum(ell * u, axis=1)
        bad |= np.abs(cw - np.cos(vals["Half Angle"])) < EPS_DISC
    return bad


def _scaled_err(got, ref):
    err = np.abs(got - ref)
    scale = np.maximum(1.0, np.abs(ref))
    if err.ndim == 2:
        return err.max(axis=1), (err / scale).max(axis=1)
    return err, err / scale


# ============================================================== the renders (session scoped)

class Renders:
    pass


def _tile_slices(t):
    col, row = t % COLS, t // COLS
    # image-row order (row 0 = bottom); tile t occupies plane [col, col+1] x [row, row+1]
    return slice(row * TILE, (row + 1) * TILE), slice(col * TILE, (col + 1) * TILE)


@pytest.fixture(scope="session")
def renders(extension, blender_tmp):
    bpy = be.import_bpy()
    be.reset_empty_file()
    be.load_groups()
    missing = [g for g in GROUPS if g not in bpy.data.node_groups]
    assert not missing, f"load_node_groups did not create {missing}"
    rng = np.random.default_rng(20240521)
    R = Renders()
    R.timings = {}
    out = str(blender_tmp)

    # ---------------- flat tiles, orthographic camera
    scene = be.new_scene("PhongFlat", COLS * TILE, ROWS * TILE, "cycles")
    be.add_ortho_camera(scene, (COLS / 2.0, ROWS / 2.0), float(COLS), float(ROWS))
    max_in = max(len(GROUPS[g][0]) for g in GROUPS)
    cycles_aovs(scene, max_in)
    eevee_mats = []
    R.tile_values = []
    jj, ii = np.meshgrid(np.arange(TILE), np.arange(TILE))  # ii: row, jj: col (image-row order)
    for t, (group, pack) in enumerate(TILES):
        col, row = t % COLS, t // COLS
        P = np.stack([col + (jj.ravel() + 0.5) / TILE, row + (ii.ravel() + 0.5) / TILE,
                      np.zeros(TILE * TILE)], axis=1)
        N = np.tile([0.0, 0.0, 1.0], (TILE * TILE, 1))
        vals, use_geo = gen_inputs(group, rng, TILE * TILE, P, N, N)
        linked = [s for s, _ in GROUPS[group][0]]
        layout = _input_layout(group, linked)
        imgs, flag = _make_images(f"T{t}", group, layout, vals, use_geo, (TILE, TILE))
        mat_c = build_material(f"C{t} {group}", group, imgs, flag, layout, "cycles")
        mat_e = build_material(f"E{t} {group}", group, imgs, flag, layout, "eevee", pack)
        obj = be.add_uv_plane(scene, f"tile{t}", float(col), float(row), 1.0, mat_c)
        eevee_mats.append((obj, mat_e))
    t0 = time.perf_counter()
    be.render_exr(scene, os.path.join(out, "flat_cycles.exr"))
    R.timings["cycles flat"] = time.perf_counter() - t0
    R.flat_c = {k: v[::-1] for k, v in be.read_multilayer_exr(os.path.join(out, "flat_cycles.exr")).items()}

    # ---------------- curved: spheres, perspective, Normal / View Vector unlinked
    sc2 = be.new_scene("PhongCurved", CURVED_RES * CURVED_COLS // 2, CURVED_RES, "cycles")
    be.add_persp_camera(sc2, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), lens=50.0)
    cycles_aovs(sc2, max_in)
    eevee_mats2 = []
    for k, group in enumerate(CURVED_GROUPS):
        linked = [s for s, _ in GROUPS[group][0] if s not in ("Normal", "View Vector")]
        layout = _input_layout(group, linked)
        h, w = 32, 64
        nn = h * w
        zeros = np.zeros((nn, 3))
        vals, _ = gen_inputs(group, rng, nn, zeros, zeros + (0, 0, 1), zeros + (0, 0, 1), curved=True)
        # light mostly toward the camera side so that diffuse and highlights show
        ell = _unit(rng, nn)
        ell[:, 2] = np.abs(ell[:, 2]) + 0.3
        vals["Light Vector"] = _f16(ell / np.linalg.norm(ell, axis=1, keepdims=True))
        imgs, flag = _make_images(f"S{k}", group, layout, vals, None, (h, w))
        unl = ("Normal", "View Vector") if group != "Phong Diffuse" else ("Normal",)
        mat_c = build_material(f"SC{k} {group}", group, imgs, flag, layout, "cycles", unlinked_zero=unl)
        pack = len(EEVEE_PACKS[group]) - 1  # Color
        mat_e = build_material(f"SE{k} {group}", group, imgs, flag, layout, "eevee", pack,
                               unlinked_zero=unl)
        loc = (2.2 * (k % CURVED_COLS - (CURVED_COLS - 1) / 2.0), -1.1 + 2.2 * (k // CURVED_COLS),
               0.0)
        obj = be.add_uv_sphere(sc2, f"sphere{k}", loc, 1.0, mat_c)
        eevee_mats2.append((obj, mat_e))
    t0 = time.perf_counter()
    be.render_exr(sc2, os.path.join(out, "curved_cycles.exr"))
    R.timings["cycles curved"] = time.perf_counter() - t0
    R.curved_c = {k: v[::-1] for k, v in be.read_multilayer_exr(os.path.join(out, "curved_cycles.exr")).items()}

    # ---------------- Eevee: same scenes, one output pack per tile in one AOV
    be.switch_to_eevee(scene, eevee_mats)
    t0 = time.perf_counter()
    be.render_exr(scene, os.path.join(out, "flat_eevee.exr"))
    R.timings["eevee flat (compile + render)"] = time.perf_counter() - t0
    R.flat_e = {k: v[::-1] for k, v in be.read_multilayer_exr(os.path.join(out, "flat_eevee.exr")).items()}
    be.switch_to_eevee(sc2, eevee_mats2)
    t0 = time.perf_counter()
    be.render_exr(sc2, os.path.join(out, "curved_eevee.exr"))
    R.timings["eevee curved (compile + render)"] = time.perf_counter() - t0
    R.curved_e = {k: v[::-1] for k, v in be.read_multilayer_exr(os.path.join(out, "curved_eevee.exr")).items()}
    for k, v in R.timings.items():
        report(f"[timing] {k}: {v:.1f} s")
    return R


def _flat_samples(R, group):
    """Pixel index arrays (ys, xs) of every tile of the group, with the tile of each pixel."""
    ys, xs, tiles = [], [], []
    for t, (g, _pack) in enumerate(TILES):
        if g != group:
            continue
        sy, sx = _tile_slices(t)
        yy, xx = np.meshgrid(np.arange(sy.start, sy.stop), np.arange(sx.start, sx.stop), indexing="ij")
        ys.append(yy.ravel())
        xs.append(xx.ravel())
        tiles.append(np.full(yy.size, t))
    return np.concatenate(ys), np.concatenate(xs), np.concatenate(tiles)


def _fmt_case(vals, geo, i):
    parts = [f"{k}={np.round(v[i], 6).tolist()}" for k, v in vals.items()]
    parts += [f"geo.{k}={np.round(v[i], 6).tolist()}" for k, v in geo.items()]
    return ", ".join(parts)


def _compare_cycles(group, vals, geo, got, label, where):
    ref = reference.GROUPS[group](vals, geo)
    bad = near_discontinuity(group, vals, geo)
    n = bad.size
    failures = []
    for name, g in got.items():
        r = ref[name]
        finite = np.isfinite(g).all(axis=-1) if g.ndim == 2 else np.isfinite(g)
        if not finite.all():
            i = int(np.flatnonzero(~finite)[0])
            failures.append(f"{group}.{name}: {int((~finite).sum())} non-finite pixels, e.g. at {where(i)} "
                            f"got {g[i]} ref {r[i]} inputs: {_fmt_case(vals, geo, i)}")
            continue
        abs_err, sc_err = _scaled_err(g, r)
        ok = ~bad
        m_abs = float(abs_err[ok].max()) if ok.any() else 0.0
        m_sc = float(sc_err[ok].max()) if ok.any() else 0.0
        report(f"[cycles {label}] {group} / {name}: n={int(ok.sum())} excluded={int(bad.sum())} "
               f"max|err|={m_abs:.2e} max scaled err={m_sc:.2e}")
        if m_sc > CY_TOL:
            i = int(np.flatnonzero(ok)[np.argmax(sc_err[ok])])
            failures.append(f"{group}.{name} ({label}): scaled error {m_sc:.3e} > {CY_TOL} at {where(i)}: "
                            f"got {np.asarray(g[i]).tolist()} expected {np.asarray(r[i]).tolist()}; "
                            f"inputs: {_fmt_case(vals, geo, i)}")
    assert n - int(bad.sum()) >= 2000, f"{group}: only {n - int(bad.sum())} compared samples"
    assert bad.mean() <= MAX_EXCLUDED_FRACTION, f"{group}: {bad.mean():.2%} samples excluded"
    return failures, ref, bad


@pytest.mark.cycles
@pytest.mark.slow
@pytest.mark.parametrize("group", list(GROUPS))
def test_cycles_flat(renders, group):
    R = renders
    ys, xs, tiles = _flat_samples(R, group)
    vals, geo = read_inputs(R.flat_c, group, ys, xs)
    got = read_outputs(R.flat_c, group, ys, xs)
    where = lambda i: f"tile {tiles[i]} pixel (row {ys[i]}, col {xs[i]})"  # noqa: E731
    failures, ref, bad = _compare_cycles(group, vals, geo, got, "flat", where)
    if group == "Phong Shading":  # the Shader output: Combined == Color (Emission strength 1)
        comb = R.flat_c["Combined"][ys, xs, :3].astype(np.float64)
        abs_err, sc_err = _scaled_err(comb, ref["Color"])
        m = float(sc_err[~bad].max())
        report(f"[cycles flat] {group} / Shader (Combined vs Color): n={int((~bad).sum())} max|err|={m:.2e}")
        if m > CY_TOL:
            failures.append(f"{group}.Shader: Combined differs from reference Color by {m:.3e}")
    assert not failures, "\n".join(failures)


def _curved_case(R, group):
    """Pixels of *group*'s sphere (its image quadrant) and the reference inputs there, with
    Normal / View Vector unlinked at zero, so the reference uses Geometry Normal / Incoming."""
    k = CURVED_GROUPS.index(group)
    hit = R.curved_c["hit"][..., 0] > 0.5
    half = CURVED_RES // 2  # each sphere's square of the picture
    quad = np.zeros_like(hit)
    qy, qx = k // CURVED_COLS, k % CURVED_COLS
    quad[qy * half:(qy + 1) * half, qx * half:(qx + 1) * half] = True
    ys, xs = np.nonzero(hit & quad)
    linked = [s for s, _ in GROUPS[group][0] if s not in ("Normal", "View Vector")]
    vals, geo = read_inputs(R.curved_c, group, ys, xs, linked)
    zeros = np.zeros((ys.size, 3))
    vals["Normal"] = zeros
    if group != "Phong Diffuse":
        vals["View Vector"] = zeros
    where = lambda i: f"curved pixel (row {ys[i]}, col {xs[i]})"  # noqa: E731
    return ys, xs, vals, geo, where


@pytest.mark.cycles
@pytest.mark.slow
@pytest.mark.parametrize("group", CURVED_GROUPS)
def test_cycles_curved_unlinked_normal_view(renders, group):
    R = renders
    ys, xs, vals, geo, where = _curved_case(R, group)
    got = read_outputs(R.curved_c, group, ys, xs)
    incoming_spread = float(np.ptp(geo["Incoming"], axis=0).max())
    assert incoming_spread > 0.1, "perspective Incoming should vary over the sphere"
    failures, ref, bad = _compare_cycles(group, vals, geo, got, "curved", where)
    assert not failures, "\n".join(failures)


def _compare_eevee(group, name, vals, geo, got, label, where, bad):
    ref = reference.GROUPS[group](vals, geo)[name]
    assert not np.isnan(got).any(), f"{group}.{name} ({label}): NaN pixels in Eevee"
    abs_err, sc_err = _scaled_err(got, ref)
    ok = ~bad
    sc = sc_err[ok]
    frac = float((sc <= EE_TOL).mean())
    p995 = float(np.quantile(abs_err[ok], 0.995))
    report(f"[eevee {label}] {group} / {name}: n={int(ok.sum())} excluded={int(bad.sum())} "
           f"max|err|={float(abs_err[ok].max()):.2e} p99.5|err|={p995:.2e} within tol={frac:.4%}")
    msgs = []
    if frac < EE_FRACTION or sc.max() > EE_MAX:
        i = int(np.flatnonzero(ok)[np.argmax(sc)])
        msgs.append(f"{group}.{name} ({label}) Eevee: {frac:.3%} within {EE_TOL}, max scaled {sc.max():.3e} at "
                    f"{where(i)}: got {np.asarray(got[i]).tolist()} expected {np.asarray(ref[i]).tolist()}; "
                    f"inputs: {_fmt_case(vals, geo, i)}")
    return msgs


@pytest.mark.eevee
@pytest.mark.slow
@pytest.mark.parametrize("group", list(GROUPS))
def test_eevee_flat(renders, group):
    R = renders
    failures = []
    _, outs = GROUPS[group]
    kinds = dict(outs)
    for t, (g, pack) in enumerate(TILES):
        if g != group:
            continue
        sy, sx = _tile_slices(t)
        yy, xx = np.meshgrid(np.arange(sy.start, sy.stop), np.arange(sx.start, sx.stop), indexing="ij")
        ys, xs = yy.ravel(), xx.ravel()
        vals, geo = read_inputs(R.flat_c, group, ys, xs)
        bad = near_discontinuity(group, vals, geo)
        enc = R.flat_e["eout"][ys, xs, :3].astype(np.float64) / EE_SCALE
        where = lambda i: f"tile {t} pixel (row {ys[i]}, col {xs[i]})"  # noqa: E731
        names = EEVEE_PACKS[group][pack]
        if len(names) == 1 and kinds[names[0]] == be.V:
            failures += _compare_eevee(group, names[0], vals, geo, enc, "flat", where, bad)
        else:
            for c, name in enumerate(names):
                failures += _compare_eevee(group, name, vals, geo, enc[:, c], "flat", where, bad)
        if group == "Phong Shading":
            comb = R.flat_e["Combined"][ys, xs, :3].astype(np.float64)
            failures += _compare_eevee(group, "Color", vals, geo, comb, "flat Shader->Combined", where, bad)
    assert not failures, "\n".join(failures)


@pytest.mark.eevee
@pytest.mark.slow
@pytest.mark.parametrize("group", CURVED_GROUPS)
def test_eevee_curved_unlinked_normal_view(renders, group):
    R = renders
    ys, xs, vals, geo, where = _curved_case(R, group)
    bad = near_discontinuity(group, vals, geo)
    enc = R.curved_e["eout"][ys, xs, :3].astype(np.float64) / EE_SCALE
    name = EEVEE_PACKS[group][-1][0]
    failures = _compare_eevee(group, name, vals, geo, enc, "curved", where, bad)
    assert not failures, "\n".join(failures)


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
def test_all_pixels_finite(renders):
    R = renders
    for label, passes in (("cycles flat", R.flat_c), ("cycles curved", R.curved_c),
                          ("eevee flat", R.flat_e), ("eevee curved", R.curved_e)):
        for name, arr in passes.items():
            assert np.isfinite(arr).all(), f"{label}: pass {name} has {int((~np.isfinite(arr)).sum())} non-finite values"
