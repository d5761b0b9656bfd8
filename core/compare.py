# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison of renders with the numpy reference: the reference picture from AOV
arrays, the metrics of each pair of pictures, and the verdicts against the tolerances.

Pure numpy (OpenImageIO to read the renders): no ``bpy``.  The Blender side
(``addon/demos/bake.py``) renders and hands the arrays over.

Pixels the reference cannot predict are left out of the metrics, the same for every
engine: the background (no object), objects with a see-through material (Opacity below 1:
the picture blends what is behind them) and pixels within 1e-5 of a discontinuity of the model
(the spot's cone edge cos ω = cos θ; the terminator ℓ·n = 0 where a specular term may
jump).  Their count is in metrics.json.
"""

from __future__ import annotations

import math

import numpy as np

from ..node_groups import models
from ..node_groups import reference as ref

#: Cycles must match the reference within this (max abs error, linear colour).
CYCLES_TOLERANCE = 1e-4
#: Eevee: this share of pixels within 1/255 of the reference (its film is half float).
EEVEE_STEP = 1.0 / 255.0
EEVEE_SHARE = 0.995
#: Pixels this close to a discontinuity of the model are not compared.
AMBIGUOUS = 1e-5

#: three.js (a peer, rendered by a browser): this share of the pixels both cover within
#: 2/255 of Cycles, in display values (its canvas holds 8-bit sRGB).
THREEJS_STEP = 2.0 / 255.0
THREEJS_SHARE = 0.99
#: X_ITE (a peer: an X3D browser, rendered by Chromium): this share of the pixels both cover,
#: away from silhouettes, within 2/255 of Cycles in the X3D display values (its canvas holds
#: the equation's value I itself: :func:`compare_x3d_display`).
X3D_PEER_STEP = 2.0 / 255.0
X3D_PEER_SHARE = 0.99
PEERS = ("threejs", "x_ite")

ENGINES = ("eevee", "cycles")
PAIRS = (("eevee", "reference"), ("cycles", "reference"), ("eevee", "cycles"))
#: What a linear value shows as on screen at most (Standard view transform, 8-bit display).
#: Eevee's light loop (Blender 5.3+, addon/lighting/loop.py) adds the lights where no clamp
#: can follow: its pixel is irradiant + ambient + Σ lights where the model's is min(…, 1).
#: Eevee's picture is compared as shown, min(x, 1): a pixel of 1.3 where the reference is 1
#: is the same on screen, one of 1.0 where the reference is 0.99 is still 0.01 off (and one
#: below 1 is compared as it is).  How many pixels were above 1: metrics["eevee_above_1"].
SHOWN_MAX = 1.0
#: A comparison must see this share of the picture's pixels as Phong surfaces it compares
#: (pixels of objects with Phong materials, not background, see-through or ambiguous), else
#: it compares (almost) nothing and does not pass, whatever the engines' errors: 1%, e.g.
#: 55 of the 85 × 64 pixels of a 4:3 picture 64 px high.  A framed scene with small objects
#: passes easily (the demo scenes at 32 px high: 14.5% to 89.8%); a camera that misses the
#: scene (a file's default view 10 units from a part 0.24 units wide: 1 pixel) does not.
COVERAGE_SHARE = 0.01


#: A flat polygon whose triangles' normals part from its own by more than this (radians:
#: about 0.22°, where n·ℓ can move by 1/255) is warped for the comparison.  Eevee
#: shades a flat polygon with the polygon's one normal, Cycles (and the reference, from
#: Cycles' probes) each of its triangles with the triangle's own: a plain Emission of
#: Geometry ▸ Normal differs between them on such polygons (the warped quads of
#: tests/data/blend/appleseed_linking.blend's Utah teapot: 374 of its 3,408 pixels at 160 px
#: high, 6 once triangulated, bpy 5.3.0), Principled as much as Phong.
WARP_ANGLE = 1.0 / 255.0


def warped_polygons(polygon_normals: np.ndarray, flat: np.ndarray, triangle_normals: np.ndarray,
                    triangle_polygons: np.ndarray, angle: float = WARP_ANGLE) -> int:
    """How many flat polygons (*flat*: one bool per polygon; *polygon_normals* (P, 3)) have
    a triangle (*triangle_normals* (T, 3) of the mesh's triangulation, *triangle_polygons*
    the polygon of each) whose normal parts from the polygon's by more than *angle*.  A
    degenerate triangle (no normal) is never hit by a ray: left out."""
    if not len(triangle_polygons) or not np.any(flat):
        return 0
    triangle_normals = np.asarray(triangle_normals, np.float64)
    owner = np.asarray(triangle_polygons, np.int64)
    length = np.linalg.norm(triangle_normals, axis=1)
    cosine = np.einsum("ij,ij->i", triangle_normals,
                       np.asarray(polygon_normals, np.float64)[owner])
    apart = (np.asarray(flat, bool)[owner] & (length > 0.5)
             & (cosine < np.cos(angle) * length))
    return int(np.unique(owner[apart]).size)


def shown(image: np.ndarray) -> np.ndarray:
    """*image* (linear RGB) as the comparison takes Eevee's picture: min(x, SHOWN_MAX)."""
    return np.minimum(np.asarray(image, np.float64)[..., :3], SHOWN_MAX)


# -- renders ---------------------------------------------------------------------------

def read_exr(path: str) -> dict:
    """{pass name: float32 array (H, W, C)}, row 0 = top; names without the layer."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise RuntimeError(f"cannot read {path}: {oiio.geterror()}")
    out = {}
    order = {"R": 0, "G": 1, "B": 2, "A": 3, "X": 0, "Y": 1, "Z": 2, "V": 0}
    try:
        sub = 0
        while inp.seek_subimage(sub, 0):
            spec = inp.spec()
            pixels = inp.read_image(sub, 0, 0, spec.nchannels, oiio.FLOAT)
            pixels = np.asarray(pixels, dtype=np.float32).reshape(
                spec.height, spec.width, spec.nchannels)
            groups = {}
            for index, name in enumerate(spec.channelnames):
                parts = name.split(".")
                key = parts[-2] if len(parts) >= 2 else name
                groups.setdefault(key, []).append((parts[-1], index))
            for key, chans in groups.items():
                chans.sort(key=lambda c: order.get(c[0], 9))
                out[key] = pixels[..., [i for _c, i in chans]]
            sub += 1
    finally:
        inp.close()
    return out


# -- the reference -------------------------------------------------------------------

#: AOVs the bake adds to every lights group for its Cycles render (the probes): what each
#: pixel's lights group sees.  "params" packs (Exponent, Blinn, object number), "strength"
#: is the Specular Strength (three.js's specularStrength).
PROBE_PREFIX = "phong_probe_"
PROBES = ("P", "N", "I", "normal", "view", "color", "ambient", "specular", "irradiant",
          "params", "strength")
TERMS = ("Irradiant", "Ambient", "Diffuse", "Specular")


def probe_name(probe: str) -> str:
    return PROBE_PREFIX + probe


def reference_image(scene: dict, aovs: dict) -> dict:
    """The reference picture and its terms from the probe AOVs of a render.

    *scene* is the scene as Blender evaluates it (``addon/demos/evaluate.py``): "ambient"
    {intensity, color}, "lights" [{type, color, intensity, diffuse, specular, position,
    direction, quadratic, linear, constant, half_angle (degrees), edge_exponent, falloff
    ("quadratic" or "power": i0/d^k, k = power_k)}] and
    "objects" [{"lights": [indices into lights], "transparent": an Opacity below 1 or an
    opacity map (its pixels are ambiguous)}]: object number k (1-based, the probe's
    third "params" channel) is objects[k - 1].  Per pixel the probes hold what its lights
    group sees: P, N, I (the geometry), the Normal and View Vector inputs (zero: the
    geometry's), Object Color, Ambient Object Color, Specular Color, Irradiant Color,
    Exponent and Blinn.

    Returns {"Color", "Irradiant", "Ambient", "Diffuse", "Specular"}: (H, W, 3) float64,
    "object": (H, W) object number (0 = no Phong material), "ambiguous": (H, W) bool.
    """
    def probe(name, channels=3):
        return aovs[probe_name(name)][..., :channels]

    params = probe("params")
    number = np.rint(params[..., 2]).astype(int)
    h, w = number.shape
    hit = (number >= 1) & (number <= len(scene["objects"]))
    P, N, I = (probe(k)[hit].astype(np.float64) for k in ("P", "N", "I"))
    normal, view = (probe(k)[hit].astype(np.float64) for k in ("normal", "view"))
    color, ambient_color, spec_color, irradiant = (
        probe(k)[hit].astype(np.float64) for k in ("color", "ambient", "specular", "irradiant"))
    exponent, blinn = (params[..., c][hit].astype(np.float64) for c in (0, 1))
    idx = number[hit] - 1
    reach = np.zeros((len(scene["objects"]), max(len(scene["lights"]), 1)), dtype=bool)
    for row, obj in enumerate(scene["objects"]):
        reach[row, obj["lights"]] = True

    amb = scene["ambient"]
    model = models.get(scene.get("model"))
    ambient = model.reference_ambient(amb["intensity"], amb["color"], ambient_color)
    sums = {"Irradiant": np.broadcast_to(irradiant, P.shape).copy(), "Ambient": ambient,
            "Diffuse": np.zeros_like(P), "Specular": np.zeros_like(P)}
    ambiguous = np.zeros(len(P), bool)
    seen = _visibilities(scene, P)
    n = ref.resolve_normal(normal, N)
    px = {"color": color, "ambient_color": ambient_color, "spec_color": spec_color,
          "exponent": exponent, "blinn": blinn, "normal": normal, "view": view, "N": N, "I": I,
          "n": n, "v": ref.resolve_view(view, I),
          "strength": (probe("strength", 1)[hit][..., 0].astype(np.float64)
                       if probe_name("strength") in aovs else None)}
    for k, light in enumerate(scene["lights"]):
        ell, intensity, ambient_i, edge = model.reference_light(light, P, AMBIGUOUS)
        diffuse, specular, ambient_light, unsure = model.reference_terms(
            light, ell, intensity, ambient_i, edge, reach[idx, k], seen[k], px, AMBIGUOUS)
        ambiguous |= unsure
        sums["Diffuse"] += diffuse
        sums["Specular"] += specular
        if ambient_light is not None:
            sums["Ambient"] += ambient_light
    final = np.minimum(sum(sums.values()), 1.0)
    # an object with a material of Opacity below 1 shows what is behind it: not predicted
    see_through = np.array([bool(obj.get("transparent")) for obj in scene["objects"]] or [False])
    ambiguous |= see_through[idx]

    def image(values):
        img = np.zeros((h, w, 3))
        img[hit] = values
        return img

    result = {key: image(val) for key, val in sums.items()}
    result["Color"] = image(final)
    result["object"] = np.where(hit, number, 0)
    amb_img = np.zeros((h, w), bool)
    amb_img[hit] = ambiguous
    edge = np.zeros((h, w), bool)
    result["in_shadow"] = np.zeros((h, w), bool)  # in some light's shadow (the peers show none)
    for values in seen:
        if np.ndim(values) == 0:
            continue
        lit = np.full((h, w), np.nan)
        lit[hit] = values
        edge |= shadow_edge(lit)
        result["in_shadow"] |= lit == 0.0
    result["shadow_edge"] = edge & hit
    result["ambiguous"] = amb_img | result["shadow_edge"]
    return result


def _visibilities(scene: dict, P: np.ndarray) -> list:
    """Per light of *scene*: its visibility at the points *P* (``reference.visibility``
    against the scene's shadow-casting triangles, ``scene["triangles"]``), or 1.0 where it
    casts no shadow or the scene has no triangles."""
    tris = scene.get("triangles")
    out = []
    for light in scene["lights"]:
        if tris is None or not light.get("shadows") or not len(P):
            out.append(1.0)
        else:
            out.append(ref.visibility(P, light, tris))
    return out


def shadow_edge(lit: np.ndarray) -> np.ndarray:
    """The pixels of a light's visibility image *lit* (H, W; NaN where no Phong surface)
    whose visibility differs from a 4-neighbour's: the shadow's boundary, where a pixel's
    centre may fall on either side of the edge in the renderer and the reference alike
    (left out of the metrics, counted as ``pixels["shadow_edge"]``)."""
    edge = np.zeros(lit.shape, bool)
    for axis in (0, 1):
        a = np.take(lit, range(0, lit.shape[axis] - 1), axis=axis)
        b = np.take(lit, range(1, lit.shape[axis]), axis=axis)
        differ = (a != b) & ~np.isnan(a) & ~np.isnan(b)
        lo = [slice(None)] * 2
        hi = [slice(None)] * 2
        lo[axis] = slice(0, lit.shape[axis] - 1)
        hi[axis] = slice(1, lit.shape[axis])
        edge[tuple(lo)] |= differ
        edge[tuple(hi)] |= differ
    return edge


# -- metrics ---------------------------------------------------------------------------

def compare(a: np.ndarray, b: np.ndarray, mask: np.ndarray) -> dict:
    """Metrics of |a - b| (max over RGB) on the pixels of *mask*."""
    diff = np.abs(a[..., :3].astype(np.float64) - b[..., :3].astype(np.float64)).max(axis=-1)
    d = diff[mask]
    if d.size == 0:
        return {"pixels": 0, "max_abs": 0.0, "mean_abs": 0.0, "psnr_db": None,
                "share_over_1_255": 0.0}
    mse = float(np.mean((a[..., :3][mask].astype(np.float64)
                         - b[..., :3][mask].astype(np.float64)) ** 2))
    return {
        "pixels": int(d.size),
        "max_abs": float(d.max()),
        "mean_abs": float(d.mean()),
        "psnr_db": None if mse == 0 else float(10 * math.log10(1.0 / mse)),
        "share_over_1_255": float(np.mean(d > EEVEE_STEP)),
    }


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """Display values of linear colours: clipped to [0, 1], sRGB transfer function (what
    Blender's Standard view transform and three.js's sRGB canvas do)."""
    x = np.clip(np.asarray(linear, np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(display: np.ndarray) -> np.ndarray:
    """Linear colours of display values in [0, 1]."""
    x = np.asarray(display, np.float64)
    return np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def compare_display(peer_rgba: np.ndarray, other: np.ndarray, mask: np.ndarray) -> dict:
    """Metrics of a browser's 8-bit sRGB picture against a linear render, in display values
    (max over RGB of |peer/255 - sRGB(other)|) on the pixels of *mask*."""
    a = peer_rgba[..., :3].astype(np.float64) / 255.0
    b = srgb_encode(other[..., :3])
    diff = np.abs(a - b).max(axis=-1)[mask]
    if diff.size == 0:
        return {"pixels": 0, "max_abs": 0.0, "mean_abs": 0.0, "psnr_db": None,
                "share_over_1_255": 0.0, "share_within_2_255": 0.0, "space": "display"}
    mse = float(np.mean((a[mask] - b[mask]) ** 2))
    return {"pixels": int(diff.size), "max_abs": float(diff.max()),
            "mean_abs": float(diff.mean()),
            "psnr_db": None if mse == 0 else float(10 * math.log10(1.0 / mse)),
            "share_over_1_255": float(np.mean(diff > 1.0 / 255.0 + 1e-9)),
            "share_within_2_255": float(np.mean(diff <= THREEJS_STEP + 1e-9)),
            "space": "display"}


def evaluate_peer(scene: dict, rgba: np.ndarray, images: dict, mask: np.ndarray) -> tuple:
    """three.js's picture (8-bit sRGB RGBA, row 0 = top) against every render: ({pair:
    metrics}, verdict or None, the mask of the pixels compared).  Only pixels both three.js
    and the reference cover are compared.  The verdict counts only for a scene in the
    three.js model (in the seeds' model three.js shows another formula)."""
    both = mask & (rgba[..., 3] > 0)
    pairs = {f"threejs-{name}": compare_display(rgba, images[name], both)
             for name in ("cycles", "eevee", "reference") if name in images}
    if "threejs" not in models.get(scene.get("model")).native or "threejs-cycles" not in pairs:
        return pairs, None, both
    within = pairs["threejs-cycles"]["share_within_2_255"]
    return pairs, {"ok": within >= THREEJS_SHARE and pairs["threejs-cycles"]["pixels"] > 0,
                   "rule": f"≥ {THREEJS_SHARE:.0%} of pixels both cover within 2/255 of Cycles",
                   "value": f"{within:.3%}"}, both


def compare_x3d_display(peer_rgba: np.ndarray, other: np.ndarray, mask: np.ndarray) -> dict:
    """Metrics of an X3D browser's 8-bit picture against a linear render, in the X3D display
    values: an X3D 3 browser (X_ITE with ColorSpace SRGB) writes the lighting equation's
    value I to its canvas as it is, round(255 · min(I, 1)), while Blender's render holds the
    same I before its view transform; so the difference is max over RGB of
    |peer/255 - min(max(render, 0), 1)| on the pixels of *mask*."""
    a = peer_rgba[..., :3].astype(np.float64) / 255.0
    b = np.clip(np.asarray(other[..., :3], np.float64), 0.0, 1.0)
    diff = np.abs(a - b).max(axis=-1)[mask]
    if diff.size == 0:
        return {"pixels": 0, "max_abs": 0.0, "mean_abs": 0.0, "psnr_db": None,
                "share_over_1_255": 0.0, "share_within_2_255": 0.0, "space": "x3d"}
    mse = float(np.mean((a[mask] - b[mask]) ** 2))
    return {"pixels": int(diff.size), "max_abs": float(diff.max()),
            "mean_abs": float(diff.mean()),
            "psnr_db": None if mse == 0 else float(10 * math.log10(1.0 / mse)),
            "share_over_1_255": float(np.mean(diff > 1.0 / 255.0 + 1e-9)),
            "share_within_2_255": float(np.mean(diff <= X3D_PEER_STEP + 1e-9)),
            "space": "x3d"}


def silhouettes(objects: np.ndarray, coverage: np.ndarray) -> np.ndarray:
    """Pixels next to a silhouette: those whose 3 × 3 neighbourhood holds another object
    number (*objects*: the reference's, 0 where nothing is) or a pixel of other *coverage*
    (the peer's).  Both renderers sample the pixel centres, but a centre within a rounding
    error of an edge may fall on either side of it in each; the border of the picture is no
    edge."""
    objects = np.asarray(objects)
    coverage = np.asarray(coverage, bool)
    h, w = objects.shape
    po = np.pad(objects, 1, mode="edge")
    pc = np.pad(coverage, 1, mode="edge")
    edge = np.zeros((h, w), bool)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            if dy == 1 and dx == 1:
                continue
            edge |= po[dy:dy + h, dx:dx + w] != objects
            edge |= pc[dy:dy + h, dx:dx + w] != coverage
    return edge


def evaluate_x3d_peer(scene: dict, rgba: np.ndarray, images: dict, mask: np.ndarray,
                      objects: np.ndarray, peer: str = "x_ite") -> tuple:
    """An X3D browser's picture (8-bit RGBA, row 0 = top, the canvas holding I: see
    :func:`compare_x3d_display`) against every render: ({pair: metrics}, verdict or None,
    the mask of the pixels compared).

    The region judged: the pixels the reference compares (*mask*) away from silhouettes
    (:func:`silhouettes` of the reference's *objects* and the peer's coverage).  The pairs'
    metrics are over the pixels of that region the peer covers; the pair with Cycles also
    gets ``coverage`` (the share of the region the peer covers) and ``agree`` (the share of
    the region the peer covers within 2/255 of Cycles: a pixel the peer leaves empty is a
    disagreement).  The verdict, on ``agree``, counts only for a scene in the X3D model (in
    another model the browser shows another formula); a region without pixels (nothing of
    the scene in view) passes as Cycles' verdict does."""
    covered = rgba[..., 3] > 0
    region = mask & ~silhouettes(objects, covered)
    both = region & covered
    pairs = {f"{peer}-{name}": compare_x3d_display(rgba, images[name], both)
             for name in ("cycles", "eevee", "reference") if name in images}
    key = f"{peer}-cycles"
    if key in pairs:
        diff = np.abs(rgba[..., :3].astype(np.float64) / 255.0
                      - np.clip(np.asarray(images["cycles"][..., :3], np.float64), 0.0, 1.0))
        within = both & (diff.max(axis=-1) <= X3D_PEER_STEP + 1e-9)
        total = int(region.sum())
        pairs[key]["region"] = total
        pairs[key]["coverage"] = float(both.sum() / total) if total else 1.0
        pairs[key]["agree"] = float(within.sum() / total) if total else 1.0
    if "x3d" not in models.get(scene.get("model")).native or key not in pairs:
        return pairs, None, both
    agree = pairs[key]["agree"]
    return pairs, {"ok": agree >= X3D_PEER_SHARE,
                   "rule": f"≥ {X3D_PEER_SHARE:.0%} of the pixels away from silhouettes "
                           "covered and within 2/255 of Cycles",
                   "value": f"{agree:.3%}" if pairs[key]["region"] else "no pixels"}, both


def verdict(pair_metrics: dict, term_metrics: dict | None = None) -> dict:
    """{engine: (ok, text)} against the tolerances.  *term_metrics* ({term: metrics of the
    Cycles term pass against the reference's term}) count in Cycles' verdict."""
    out = {}
    m = pair_metrics.get("cycles-reference")
    if m is not None:
        worst = max([m["max_abs"]] + [t["max_abs"] for t in (term_metrics or {}).values()])
        ok = worst <= CYCLES_TOLERANCE
        out["cycles"] = {"ok": ok, "rule": f"max |Δ| ≤ {CYCLES_TOLERANCE:g}",
                         "value": f"{worst:.2e}"}
    m = pair_metrics.get("eevee-reference")
    if m is not None:
        within = 1.0 - m["share_over_1_255"]
        ok = within >= EEVEE_SHARE
        out["eevee"] = {"ok": ok, "rule": f"≥ {EEVEE_SHARE:.1%} of pixels within 1/255",
                        "value": f"{within:.3%}"}
    return out


def coverage(mask: np.ndarray, surfaces: np.ndarray | None = None) -> dict:
    """The verdict on how much the comparison sees: *mask* the pixels compared, *surfaces*
    the pixels of Phong objects (compared or not).  Fails below :data:`COVERAGE_SHARE` of the
    picture, with a message saying why and what to do."""
    seen, total = int(mask.sum()), int(mask.size)
    share = seen / total if total else 0.0
    out = {"ok": total > 0 and seen >= COVERAGE_SHARE * total, "pixels": seen, "total": total,
           "rule": f"≥ {COVERAGE_SHARE:.0%} of the pixels Phong surfaces compared",
           "value": f"{share:.2%}"}
    if out["ok"]:
        return out
    in_view = seen if surfaces is None else int(surfaces.sum())
    few = f"({share:.2%}, fewer than {COVERAGE_SHARE:.0%}): nothing to compare"
    if in_view >= COVERAGE_SHARE * total:   # in view, but see-through or ambiguous
        out["message"] = (f"the camera sees Phong surfaces on {in_view} of {total} pixels but "
                          f"only {seen} can be compared {few}; the others are see-through "
                          "(Opacity below 1) or at a discontinuity of the model")
    else:
        out["message"] = (f"the camera sees {seen} of {total} pixels of Phong surfaces to "
                          f"compare {few}; frame the scene (View ▸ Frame All, then View ▸ "
                          "Align View ▸ Align Active Camera to View) or give it a camera that "
                          "sees its Phong objects")
    return out


def verdict_text(verdicts: dict, detail: bool = False) -> str:
    """One line for {engine: verdict}: "cycles 2.4e-05 OK, eevee 100.000% OK"; with
    *detail* the rule of each verdict follows its value."""
    parts = []
    for engine, v in verdicts.items():
        mark = "OK" if v["ok"] else "FAIL"
        parts.append(f"{engine} {v['value']} {mark} ({v['rule']})" if detail
                     else f"{engine} {v['value']} {mark}")
    return ", ".join(parts)


def summary_text(metrics: dict, detail: bool = False) -> str:
    """:func:`verdict_text` of *metrics*' verdicts, after why the comparison does not count
    when it sees (almost) nothing (:func:`coverage`)."""
    text = verdict_text(metrics["verdict"], detail)
    seen = metrics.get("coverage", {})
    return text if seen.get("ok", True) else f"FAIL: {seen['message']} (on those pixels: {text})"


def evaluate(scene: dict, images: dict, aovs: dict, engines, terms=None) -> tuple:
    """The reference picture of *scene* (as Blender evaluates it) from the probe *aovs*, and
    the metrics of every pair of *images* ({"cycles": ..., "eevee": ...}) and of each term
    pass in *terms* ({term: Cycles' pass}) against the reference's term; returns (metrics,
    reference, mask).  *images* gains "reference", and its "eevee" becomes the picture as
    shown (:func:`shown`: Eevee's light loop leaves sums above 1), which the pairs compare;
    metrics["eevee_above_1"] counts the compared pixels Eevee rendered above 1;
    metrics["coverage"] (:func:`coverage`) fails a comparison of (almost) no pixels."""
    refimg = reference_image(scene, aovs)
    images["reference"] = refimg["Color"]
    mask = (refimg["object"] > 0) & ~refimg["ambiguous"]
    above = None
    if "eevee" in images:
        peak = np.asarray(images["eevee"], np.float64)[..., :3].max(axis=-1)
        over = mask & (peak > SHOWN_MAX)
        above = {"pixels": int(over.sum()), "max": float(peak[over].max()) if over.any()
                 else None}
        images["eevee"] = shown(images["eevee"])
    present = set(engines) | {"reference"}
    # where Eevee shows no shadows (before 5.3, the X3D model...: scene["eevee_shadows"]
    # false) its picture is compared with the reference without them
    plain = None
    if not scene.get("eevee_shadows", True) and any(l.get("shadows") for l in scene["lights"]):
        plain = reference_image(dict(scene, lights=[dict(light, shadows=False)
                                                    for light in scene["lights"]]), aovs)

    def picture(name, other):
        return plain["Color"] if (name, other) == ("reference", "eevee") and plain else \
            images[name]

    pairs = {f"{a}-{b}": compare(images[a], picture(b, a), mask) for a, b in PAIRS
             if a in present and b in present and a in images and b in images}
    term_metrics = {t: compare(terms[t], refimg[t], mask) for t in TERMS
                    if terms and t in terms}
    verdicts = verdict(pairs, term_metrics)
    seen = coverage(mask, refimg["object"] > 0)
    metrics = {
        "scene": scene["name"],
        "title": scene["title"],
        "engines": list(engines),
        "pixels": {"total": int(mask.size), "object": int((refimg["object"] > 0).sum()),
                   "compared": int(mask.sum()), "ambiguous": int(refimg["ambiguous"].sum()),
                   "shadow_edge": int(refimg["shadow_edge"].sum())},
        "pairs": pairs,
        "terms": term_metrics,
        "tolerances": {"cycles_max_abs": CYCLES_TOLERANCE, "eevee_step": EEVEE_STEP,
                       "eevee_share_within": EEVEE_SHARE},
        "verdict": verdicts,
        "coverage": seen,
        "ok": seen["ok"] and all(v["ok"] for v in verdicts.values()),
        "parameters": {k: v for k, v in scene.items() if k not in ("path", "triangles")},
    }
    if above is not None:
        metrics["eevee_above_1"] = above
    if plain is not None:
        metrics["eevee_shadows"] = False
    return metrics, refimg, mask
