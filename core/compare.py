# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison of renders with the numpy reference: the reference picture from AOV
arrays, the metrics of each pair of pictures, and the verdicts against the tolerances.

Pure numpy (OpenImageIO to read the renders): no ``bpy``.  The Blender side
(``addon/demos/bake.py``) renders and hands the arrays over.

Pixels the reference cannot predict are left out of the metrics, the same for every
engine: the background (no object) and pixels within 1e-5 of a discontinuity of the model
(the spot's cone edge cos ω = cos θ; the terminator ℓ·n = 0 where a specular term may
jump).  Their count is in metrics.json.
"""

from __future__ import annotations

import math

import numpy as np

from ..node_groups import reference as ref

#: Cycles must match the reference within this (max abs error, linear colour).
CYCLES_TOLERANCE = 1e-4
#: Eevee: this share of pixels within 1/255 of the reference (its film is half float).
EEVEE_STEP = 1.0 / 255.0
EEVEE_SHARE = 0.995
#: Pixels this close to a discontinuity of the model are not compared.
AMBIGUOUS = 1e-5

ENGINES = ("eevee", "cycles")
PAIRS = (("eevee", "reference"), ("cycles", "reference"), ("eevee", "cycles"))


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

def light_at(light, P):
    """(ℓ, intensity, ambiguous) of one light at the points P (N, 3)."""
    kind = light["type"]
    if kind == "directional":
        out = ref.directional_light(light["direction"], light["intensity"], geometry_position=P)
        return out["Light Vector"], out["Intensity"], np.zeros(len(P), bool)
    if kind == "point":
        out = ref.point_light(light["position"], light["intensity"], light["quadratic"],
                              light["linear"], light["constant"], geometry_position=P)
        intensity = out["Intensity"]
        if "falloff_exponent" in light:
            intensity = ref.power_falloff(out["Distance"], light["intensity"],
                                          light["falloff_exponent"])["Intensity"]
        return out["Light Vector"], intensity, np.zeros(len(P), bool)
    theta = math.radians(light["half_angle"])
    out = ref.spot_light(light["position"], light["direction"], theta, light["edge_exponent"],
                         light["intensity"], light["quadratic"], light["linear"],
                         light["constant"], geometry_position=P)
    edge = np.abs(out["Cos Angle"] - math.cos(theta)) < AMBIGUOUS
    return out["Light Vector"], out["Intensity"], edge


def reference_image(scene: dict, aovs: dict) -> dict:
    """The reference picture and its terms from Cycles' AOVs.

    Returns {"Color", "Irradiant", "Ambient", "Diffuse", "Specular"}: (H, W, 3) float64,
    "object": (H, W) object index (0 = background), "ambiguous": (H, W) bool.
    """
    index = np.rint(aovs["phong_index"][..., 0]).astype(int)
    h, w = index.shape
    hit = (index >= 1) & (index <= len(scene["objects"]))
    P = aovs["phong_P"][..., :3][hit].astype(np.float64)
    N = aovs["phong_N"][..., :3][hit].astype(np.float64)
    I = aovs["phong_I"][..., :3][hit].astype(np.float64)
    color = aovs["phong_color"][..., :3][hit].astype(np.float64)
    idx = index[hit] - 1
    objects = scene["objects"]

    def per_object(fn):
        table = np.array([fn(o) for o in objects], dtype=np.float64)
        return table[idx]

    spec_color = per_object(lambda o: o["material"]["specular_color"])
    exponent = per_object(lambda o: o["material"]["exponent"])
    blinn = per_object(lambda o: o["material"]["blinn"])
    irradiant = per_object(lambda o: o["material"]["irradiant"] if "irradiant" in o["terms"]
                           else [0.0, 0.0, 0.0])
    ambient = per_object(lambda o: scene["ambient"]["intensity"] if "ambient" in o["terms"]
                         else 0.0)
    ambiguous = np.zeros(len(P), bool)
    sums = {k: np.zeros((len(P), 3)) for k in ("Irradiant", "Ambient", "Diffuse", "Specular")}
    lights = scene["lights"] or [None]
    final = None
    for k, light in enumerate(lights):
        if light is None:
            ell, intensity, edge = np.zeros_like(P), np.zeros(len(P)), np.zeros(len(P), bool)
            light_color, dif, spe = (1.0, 1.0, 1.0), 0.0, 0.0
        else:
            ell, intensity, edge = light_at(light, P)
            light_color = light["color"]
            dif = per_object(lambda o, l=light: l["diffuse"] if l["name"] in o["lights"]
                             and "diffuse" in o["terms"] else 0.0)
            spe = per_object(lambda o, l=light: l["specular"] if l["name"] in o["lights"]
                             and "specular" in o["terms"] else 0.0)
            ambiguous |= edge & (np.asarray(dif) + np.asarray(spe) > 0)
            ln = ref.dot(ell, ref.normalize(N))
            ambiguous |= (np.abs(ln) < AMBIGUOUS) & (np.asarray(spe) > 0)
        out = ref.phong_shading(
            light_vector=ell, light_intensity=intensity, light_color=light_color,
            object_color=color, irradiant_color=irradiant if k == 0 else (0.0, 0.0, 0.0),
            ambient_intensity=ambient if k == 0 else 0.0,
            ambient_color=scene["ambient"]["color"], diffuse_strength=dif,
            specular_strength=spe, specular_color=spec_color, exponent=exponent, blinn=blinn,
            geometry_normal=N, incoming=I)
        for key in sums:
            sums[key] += out[key]
        final = out["Color"] if final is None else ref.color_add(final, out["Color"])["Color"]

    def image(values, channels=3):
        img = np.zeros((h, w, channels))
        img[hit] = values
        return img

    result = {key: image(val) for key, val in sums.items()}
    result["Color"] = image(final)
    result["object"] = np.where(hit, index, 0)
    amb = np.zeros((h, w), bool)
    amb[hit] = ambiguous
    result["ambiguous"] = amb
    return result


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


def verdict(pair_metrics: dict) -> dict:
    """{engine: (ok, text)} against the tolerances."""
    out = {}
    m = pair_metrics.get("cycles-reference")
    if m is not None:
        ok = m["max_abs"] <= CYCLES_TOLERANCE
        out["cycles"] = {"ok": ok, "rule": f"max |Δ| ≤ {CYCLES_TOLERANCE:g}",
                         "value": f"{m['max_abs']:.2e}"}
    m = pair_metrics.get("eevee-reference")
    if m is not None:
        within = 1.0 - m["share_over_1_255"]
        ok = within >= EEVEE_SHARE
        out["eevee"] = {"ok": ok, "rule": f"≥ {EEVEE_SHARE:.1%} of pixels within 1/255",
                        "value": f"{within:.3%}"}
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


def evaluate(data: dict, images: dict, aovs: dict, engines) -> tuple:
    """The reference picture of the scene *data* from Cycles' *aovs*, and the metrics of
    every pair of *images* ({"cycles": ..., "eevee": ...}); returns (metrics, reference,
    mask).  *images* gains "reference"."""
    refimg = reference_image(data, aovs)
    images["reference"] = refimg["Color"]
    mask = (refimg["object"] > 0) & ~refimg["ambiguous"]
    present = set(engines) | {"reference"}
    pairs = {f"{a}-{b}": compare(images[a], images[b], mask) for a, b in PAIRS
             if a in present and b in present and a in images and b in images}
    verdicts = verdict(pairs)
    metrics = {
        "scene": data["name"],
        "title": data["title"],
        "engines": list(engines),
        "pixels": {"total": int(mask.size), "object": int((refimg["object"] > 0).sum()),
                   "compared": int(mask.sum()), "ambiguous": int(refimg["ambiguous"].sum())},
        "pairs": pairs,
        "tolerances": {"cycles_max_abs": CYCLES_TOLERANCE, "eevee_step": EEVEE_STEP,
                       "eevee_share_within": EEVEE_SHARE},
        "verdict": verdicts,
        "ok": all(v["ok"] for v in verdicts.values()),
        "parameters": {k: v for k, v in data.items() if k != "path"},
    }
    return metrics, refimg, mask
