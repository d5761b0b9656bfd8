# SPDX-License-Identifier: GPL-3.0-or-later
"""Images, sheet, heatmaps, plots and index.html of the comparison bake.

numpy + OpenImageIO only (no bpy): PNGs are 8-bit sRGB (the 'Standard' view transform of
the linear pictures); plots are SVG written by hand.
"""

from __future__ import annotations

import html
import json
import math
import os

import numpy as np

from ..node_groups import models
from ..node_groups import reference as ref
from . import compare
from .outputs import write_file

TERMS = ("Irradiant", "Ambient", "Diffuse", "Specular")
#: Heatmap scale: log10 |Δ| from HEAT_LO (black) to HEAT_HI (white).
HEAT_LO, HEAT_HI = 1e-6, 1e-1
MASKED = np.array([0.18, 0.18, 0.22])


# -- images ---------------------------------------------------------------------------

def to_srgb(linear: np.ndarray) -> np.ndarray:
    x = np.clip(linear[..., :3], 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def write_png(path: str, display: np.ndarray) -> None:
    """Write an (H, W, 3) display-referred [0, 1] image as 8-bit PNG."""
    import OpenImageIO as oiio

    data = np.ascontiguousarray(np.clip(np.rint(display * 255.0), 0, 255).astype(np.uint8))
    h, w, c = data.shape
    out = oiio.ImageOutput.create(path)
    if out is None:
        raise RuntimeError(f"cannot write {path}: {oiio.geterror()}")
    out.open(path, oiio.ImageSpec(w, h, c, oiio.UINT8))
    out.write_image(data)
    out.close()


_RAMP = np.array([[0, 0, 0], [0.1, 0.1, 0.6], [0.0, 0.6, 0.7], [0.2, 0.8, 0.2],
                  [0.95, 0.85, 0.1], [0.9, 0.2, 0.1], [1, 1, 1]], dtype=np.float64)


def heat_colors(t: np.ndarray) -> np.ndarray:
    """t in [0, 1] -> RGB along the ramp black-blue-teal-green-yellow-red-white."""
    t = np.clip(t, 0.0, 1.0) * (len(_RAMP) - 1)
    i = np.minimum(np.floor(t).astype(int), len(_RAMP) - 2)
    f = (t - i)[..., None]
    return _RAMP[i] * (1 - f) + _RAMP[i + 1] * f


def heatmap(a: np.ndarray, b: np.ndarray, mask: np.ndarray) -> np.ndarray:
    d = np.abs(a[..., :3].astype(np.float64) - b[..., :3].astype(np.float64)).max(axis=-1)
    t = (np.log10(np.maximum(d, HEAT_LO * 1e-3)) - math.log10(HEAT_LO)) / (
        math.log10(HEAT_HI) - math.log10(HEAT_LO))
    img = heat_colors(t)
    img[~mask] = MASKED
    return img


def heat_legend(width: int, height: int = 14) -> np.ndarray:
    t = np.linspace(0, 1, width)[None, :].repeat(height, 0)
    return heat_colors(t)


# -- text on images (OpenImageIO's built-in font) -----------------------------------------

def _canvas(h, w, value=0.1):
    return np.full((h, w, 3), value, dtype=np.float32)


#: Glyphs the built-in font lacks.
_ASCII = {"≤": "<=", "≥": ">=", "Δ": "d", "…": "...", "⊕": "+", "⊗": "x", "–": "-", "—": "-"}


def _text(img: np.ndarray, x: int, y: int, text: str, size: int = 14, color=(1, 1, 1)):
    """Draw *text* (baseline at y) onto the float image; no-op if text rendering fails."""
    import OpenImageIO as oiio

    if img.shape[0] < 4 or img.shape[1] < 4:
        return img
    for a, b in _ASCII.items():
        text = text.replace(a, b)
    buf = oiio.ImageBuf(np.ascontiguousarray(img, dtype=np.float32))
    if oiio.ImageBufAlgo.render_text(buf, x, y, text, size, "", tuple(color)):
        img[...] = buf.get_pixels(oiio.FLOAT).reshape(img.shape)
    return img


def sheet(tiles: list, title: str, subtitle: str, columns: int) -> np.ndarray:
    """Labelled grid of (label, display image) tiles under a title bar."""
    h, w = tiles[0][1].shape[:2]
    label_h, pad, head = 22, 6, 56
    rows = math.ceil(len(tiles) / columns)
    W = max(columns * (w + pad) + pad, 720)
    H = head + rows * (h + label_h + pad) + pad + 30
    img = _canvas(H, W)
    for i, (label, tile) in enumerate(tiles):
        r, c = divmod(i, columns)
        x = pad + c * (w + pad)
        y = head + r * (h + label_h + pad)
        _text(img[y:y + label_h, x:x + w], 2, 16, label, 14)
        img[y + label_h:y + label_h + h, x:x + w] = tile[..., :3]
    _text(img[:head], pad, 22, title, 18)
    _text(img[:head], pad, 46, subtitle, 13, (0.85, 0.85, 0.85))
    legend_w = min(W - 2 * pad, 300)
    y0 = H - 24
    img[y0:y0 + 14, pad:pad + legend_w] = heat_legend(legend_w)
    _text(img[y0 - 4:H, pad + legend_w + 8:W], 0, 16,
          f"|Δ| heatmaps: log scale {HEAT_LO:g} (black) … {HEAT_HI:g} (white); "
          "1/255 = yellow-red; grey = not compared", 12, (0.85, 0.85, 0.85))
    return img


# -- plots (SVG) ---------------------------------------------------------------------

_PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


def svg_plot(title: str, xlabel: str, ylabel: str, curves: list, x_range, y_range,
             width=440, height=280) -> str:
    """A line plot: curves = [(label, xs, ys)]."""
    left, right, top, bottom = 52, 150, 30, 40
    pw, ph = width - left - right, height - top - bottom
    (x0, x1), (y0, y1) = x_range, y_range

    def sx(x):
        return left + (x - x0) / (x1 - x0) * pw

    def sy(y):
        return top + ph - (min(max(y, y0), y1) - y0) / (y1 - y0) * ph

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
             f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="11">',
             f'<rect width="{width}" height="{height}" fill="white"/>',
             f'<text x="{left}" y="18" font-size="13" font-weight="bold">{html.escape(title)}</text>']
    for i in range(6):
        gx = x0 + (x1 - x0) * i / 5
        gy = y0 + (y1 - y0) * i / 5
        parts.append(f'<line x1="{sx(gx):.1f}" y1="{top}" x2="{sx(gx):.1f}" y2="{top + ph}" '
                     'stroke="#ddd"/>')
        parts.append(f'<line x1="{left}" y1="{sy(gy):.1f}" x2="{left + pw}" y2="{sy(gy):.1f}" '
                     'stroke="#ddd"/>')
        parts.append(f'<text x="{sx(gx):.1f}" y="{top + ph + 14}" text-anchor="middle">'
                     f'{gx:g}</text>')
        parts.append(f'<text x="{left - 4}" y="{sy(gy) + 4:.1f}" text-anchor="end">'
                     f'{gy:.2g}</text>')
    parts.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" '
                 'stroke="#333"/>')
    parts.append(f'<text x="{left + pw / 2}" y="{height - 6}" text-anchor="middle">'
                 f'{html.escape(xlabel)}</text>')
    parts.append(f'<text x="12" y="{top + ph / 2}" text-anchor="middle" '
                 f'transform="rotate(-90 12 {top + ph / 2})">{html.escape(ylabel)}</text>')
    for i, (label, xs, ys) in enumerate(curves):
        color = _PALETTE[i % len(_PALETTE)]
        pts = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs, ys) if np.isfinite(y))
        parts.append(f'<polyline points="{pts}" fill="none" stroke="{color}" '
                     'stroke-width="2"/>')
        ly = top + 12 + 16 * i
        parts.append(f'<line x1="{left + pw + 10}" y1="{ly - 4}" x2="{left + pw + 28}" '
                     f'y2="{ly - 4}" stroke="{color}" stroke-width="2"/>')
        parts.append(f'<text x="{left + pw + 32}" y="{ly}">{html.escape(label)}</text>')
    parts.append("</svg>")
    return "\n".join(parts)


def plots(scene: dict) -> dict:
    """{file name: SVG text} for the scene's lights: falloff curves, cos^e edge curves."""
    if "threejs" in models.get(scene.get("model")).native:   # three.js's lights' curves
        return _threejs_plots(scene)
    out = {}
    points = [l for l in scene["lights"] if l["type"] in ("point", "spot")]
    if points:
        d = np.linspace(0.05, 4.0, 200)
        curves = []
        for light in points:
            if "falloff_exponent" in light:
                y = ref.power_falloff(d, 1.0, light["falloff_exponent"])["Intensity"]
                label = f"1/d^{light['falloff_exponent']:g}"
            else:
                at_d = np.stack([d, np.zeros_like(d), np.zeros_like(d)], axis=-1)
                y = ref.point_light(at_d, 1.0, light["quadratic"], light["linear"],
                                    light["constant"])["Intensity"]
                label = (f"1/({light['quadratic']:g}r²+{light['linear']:g}r"
                         f"+{light['constant']:g})")
            if label not in [c[0] for c in curves]:
                curves.append((label, d, y))
        out["plot_falloff.svg"] = svg_plot("Point-light falloff (i0 = 1)", "distance d",
                                           "intensity", curves, (0, 4), (0, 2))
    spots = [l for l in scene["lights"] if l["type"] == "spot"]
    if spots:
        curves = []
        theta_max = max(l["half_angle"] for l in spots)
        w = np.linspace(0, min(90.0, theta_max * 1.25), 300)
        for light in spots:
            # Points at distance 1 from a spot at the origin pointing down +X, no falloff.
            at_w = np.stack([np.cos(np.radians(w)), np.sin(np.radians(w)), np.zeros_like(w)], -1)
            y = ref.spot_light((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), math.radians(light["half_angle"]),
                               light["edge_exponent"], 1.0, 0.0, 0.0, 1.0,
                               geometry_position=at_w)["Intensity"]
            curves.append((f"e_att = {light['edge_exponent']:g}", w, y))
        out["plot_spot_edge.svg"] = svg_plot(
            f"Spot edge: (cos ω)^e_att for ω ≤ θ = {theta_max:g}°", "angle ω from the axis (°)",
            "factor", curves, (0, float(w[-1])), (0, 1.05))
    return out


def _threejs_plots(scene: dict) -> dict:
    """The three.js model's curves: distance attenuation, spot penumbra (docs/threejs.md)."""
    out = {}
    points = [l for l in scene["lights"] if l["type"] in ("point", "spot")]
    if points:
        reach = max([4.0] + [l["distance"] * 1.1 for l in points])
        d = np.linspace(0.05, reach, 300)
        curves = []
        for light in points:
            y = ref.threejs_distance_attenuation(d, light["distance"], light["decay"])
            label = f"1/d^{light['decay']:g}" + (f", distance {light['distance']:g}"
                                                  if light["distance"] > 0 else "")
            if label not in [c[0] for c in curves]:
                curves.append((label, d, y))
        out["plot_falloff.svg"] = svg_plot("three.js distance attenuation (intensity 1)",
                                           "distance d", "intensity", curves, (0, reach), (0, 2))
    spots = [l for l in scene["lights"] if l["type"] == "spot"]
    if spots:
        curves = []
        top = max(l["half_angle"] for l in spots)
        w = np.linspace(0, min(90.0, top * 1.25), 300)
        for light in spots:
            a = math.radians(light["half_angle"])
            y = ref.threejs_smoothstep(math.cos(a), math.cos(a * (1 - light["penumbra"])),
                                       np.cos(np.radians(w)))
            curves.append((f"penumbra {light['penumbra']:g}", w, y))
        out["plot_spot_edge.svg"] = svg_plot(
            f"three.js spot: smoothstep penumbra, angle ≤ {top:g}°", "angle ω from the axis (°)",
            "factor", curves, (0, float(w[-1])), (0, 1.05))
    return out


# -- one scene ------------------------------------------------------------------------

#: The peers' tiles on the sheet.  X_ITE's canvas holds the X3D equation's I (ColorSpace
#: SRGB), shown here through the same sRGB display as the renders.
PEER_NAMES = {"threejs": "three.js r181 (Chromium)", "x_ite": "X_ITE 15.0.1 (Chromium)"}

def write_scene(folder: str, scene: dict, images: dict, refimg: dict, mask, metrics,
                terms=None, peer_mask=None) -> None:
    """Every image of one scene, and its sheet, into *folder*.  *terms*: {term: the
    render's own term pass}, shown instead of the reference's terms.  *peer_mask*: the
    pixels compared with three.js (images["threejs"], linear), or {peer: its pixels} (also
    "x_ite": images["x_ite"] holds X_ITE's canvas / 255, the X3D equation's I)."""
    peer_masks = peer_mask if isinstance(peer_mask, dict) else {"threejs": peer_mask}
    shown = {}
    for name in ("eevee", "cycles", "reference", "threejs", "x_ite"):
        if name in images:
            shown[name] = to_srgb(images[name])
            write_png(os.path.join(folder, f"{name}.png"), shown[name])
    heat = {}
    for pair in metrics["pairs"]:
        a, b = pair.split("-")
        peer = peer_masks.get(a) if a in PEER_NAMES else None
        heat[pair] = heatmap(images[a], images[b], peer if peer is not None else mask)
        write_png(os.path.join(folder, f"diff_{a}_{b}.png"), heat[pair])
    term_imgs = {}
    for term in TERMS:
        term_imgs[term] = to_srgb(terms[term] if terms and term in terms else refimg[term])
        write_png(os.path.join(folder, f"term_{term.lower()}.png"), term_imgs[term])
    for name, svg in plots(scene).items():
        with open(os.path.join(folder, name), "w", encoding="utf-8") as handle:
            handle.write(svg)

    def caption(pair):
        m = metrics["pairs"][pair]
        if m.get("space") == "display":
            return (f"|{pair.replace('-', ' - ')}| (display)  "
                    f"{m['share_within_2_255']:.1%} ≤ 2/255")
        if m.get("space") == "x3d":   # with Cycles: the share of the region judged
            return (f"|{pair.replace('-', ' - ')}| (X3D display)  "
                    f"{m.get('agree', m['share_within_2_255']):.1%} ≤ 2/255")
        return f"|{pair.replace('-', ' - ')}|  max {m['max_abs']:.1e}"

    names = {"reference": "Reference (numpy)", **PEER_NAMES}
    tiles = [(names.get(n, n.capitalize()), shown[n])
             for n in ("eevee", "cycles", "reference", "threejs", "x_ite") if n in shown]
    tiles += [(caption(p), heat[p]) for p in heat]
    def term_caption(term):
        m = metrics.get("terms", {}).get(term)
        if m is None:
            return f"{term} term (reference)"
        return f"{term} pass (Cycles)  |Δ| max {m['max_abs']:.1e}"

    tiles += [(term_caption(t), term_imgs[t]) for t in TERMS]
    aspect = scene["aspect"]
    columns = 5 if aspect <= 1.2 else 4 if aspect <= 1.6 else 3 if aspect <= 2.2 else 2
    title = f"{scene['name']}: {scene['title']}"
    subtitle = ((scene["source"] + "   " if scene["source"] else "")
                + compare.summary_text(metrics, detail=True))
    write_png(os.path.join(folder, "sheet.png"), sheet(tiles, title, subtitle, columns))


# -- the whole report -------------------------------------------------------------------

def _fmt(x, spec):
    return "–" if x is None else format(x, spec)


def _metrics(out_dir: str, name: str, kind: str = "comparison"):
    """The metrics.json of the scene folder *name*: a dict, None when the folder is not
    finished (no metrics.json), False when the file cannot be read or the folder lacks what
    it names.  *kind* "comparison" (demo, compare: the engine pairs) or "bake" (the .glb)."""
    path = os.path.join(out_dir, name, "metrics.json")
    if name.startswith(".") or not os.path.isfile(path):
        return None
    try:
        with open(path, encoding="utf-8") as handle:
            data = json.load(handle)
    except (OSError, ValueError):
        return False
    if not isinstance(data, dict):
        return False
    if kind == "bake":
        glb = data.get("glb")
        whole = isinstance(glb, str) and os.path.isfile(os.path.join(out_dir, name, glb))
        return data if whole else False
    return data if isinstance(data.get("pairs"), dict) else False


def results(out_dir: str) -> list:
    """The metrics.json of every finished scene folder of *out_dir*, by folder name."""
    found = (_metrics(out_dir, name) for name in sorted(os.listdir(out_dir)))
    return [m for m in found if m]


# -- completeness of a run --------------------------------------------------------------

#: Written by every run (each shard the same) into its output folder: the scene folders
#: the whole run makes, so a check can name those that are missing.
RUN_FILE = "run.json"


class RunError(Exception):
    """A folder that cannot be checked (one line: the folder or file and why)."""


def write_run(out_dir: str, folders, command: str) -> str:
    """Record in *out_dir* the scene folders that the whole run (all shards) makes;
    *command*: demo, compare or bake."""
    data = {"command": command, "scenes": list(folders)}
    return write_file(os.path.join(out_dir, RUN_FILE), json.dumps(data, indent=1) + "\n")


def check_run(out_dir: str) -> dict:
    """The state of the run in *out_dir*: ``expected`` (from run.json), ``finished`` (scene
    folders with their metrics), ``missing`` (no finished folder: never run, killed, or its
    bake failed), ``failed`` (an engine does not match, a bake's glTF check failed, or
    metrics.json unreadable), ``kind`` ("bake" for a run of ``bake``, else "comparison").
    RunError when *out_dir* or its run.json cannot be read."""
    path = os.path.join(out_dir, RUN_FILE)
    if not os.path.isdir(out_dir):
        raise RunError(f"{out_dir}: no such folder")
    try:
        with open(path, encoding="utf-8") as handle:
            data = json.load(handle)
    except FileNotFoundError:
        raise RunError(f"{path}: missing: {out_dir} is not the output folder of a run of "
                       "demo, compare or bake (each writes it when it starts)") from None
    except (OSError, ValueError) as error:
        raise RunError(f"{path}: unreadable ({error})") from None
    names = data.get("scenes") if isinstance(data, dict) else None
    if not isinstance(names, list) or not all(isinstance(n, str) and n for n in names):
        raise RunError(f"{path}: scenes: expected a list of scene folder names")
    kind = "bake" if data.get("command") == "bake" else "comparison"
    state = {"expected": names, "finished": [], "missing": [], "failed": [], "kind": kind}
    for name in names:
        metrics = _metrics(out_dir, name, kind)
        if metrics is None:
            state["missing"].append(name)
        elif metrics is False or not metrics.get("ok"):
            state["failed"].append(name)
        else:
            state["finished"].append(name)
    return state


def run_text(state: dict) -> str:
    """One line for a check_run state."""
    total, done = len(state["expected"]), len(state["finished"])
    bake = state.get("kind") == "bake"
    if not state["missing"] and not state["failed"]:
        return f"complete: {done} of {total} scene(s), " + (
            "every one baked and exported" if bake else "every engine matches the reference")
    parts = [f"INCOMPLETE: {done} of {total} scene(s) "
             + ("baked and exported" if bake else "finished and matching")]
    if state["missing"]:
        parts.append(f"missing {', '.join(state['missing'])}")
    if state["failed"]:
        parts.append(f"failed {', '.join(state['failed'])}")
    return "; ".join(parts)


def _rows(results: list) -> str:
    rows = []
    for m in results:
        for pair, p in m["pairs"].items():
            rows.append(
                f"<tr class='{'ok' if m['ok'] else 'bad'}'><td><a href='#{m['scene']}'>"
                f"{html.escape(m['scene'])}</a></td><td>{pair}</td>"
                f"<td>{p['max_abs']:.2e}</td><td>{p['mean_abs']:.2e}</td>"
                f"<td>{_fmt(p['psnr_db'], '.1f')}</td><td>{p['share_over_1_255']:.3%}</td>"
                f"<td>{p['pixels']}</td></tr>")
    return "".join(rows)


def _section(out_dir: str, m: dict) -> str:
    s = m["parameters"]
    verdicts = compare.summary_text(m, detail=True)
    notes = "".join(f"<p>{html.escape(note)}</p>" for note in m.get("notes", []))
    scene_dir = m["scene"]
    files = sorted(os.listdir(os.path.join(out_dir, scene_dir)))
    plots_html = "".join(f"<img src='{scene_dir}/{f}' alt='{f}'>" for f in files
                         if f.startswith("plot_") and f.endswith(".svg"))
    names = s.get("light_names", [])
    objects = "".join(
        f"<li><b>{html.escape(o['name'])}</b>: lights "
        f"{html.escape(', '.join(names[k] for k in o['lights']) or 'none')}; materials "
        f"{html.escape(', '.join(o['materials']))}</li>" for o in s["objects"])
    terms = "".join(f"<li>{t} pass (Cycles) − reference: max |Δ| {v['max_abs']:.2e}</li>"
                    for t, v in m.get("terms", {}).items())
    timing = ", ".join(f"{k[:-2]} {v:.1f} s" for k, v in m.get("timings", {}).items())
    return f"""
<section id="{scene_dir}">
<h2>{html.escape(s['title'])} <small>({scene_dir})</small></h2>
<p><i>{html.escape(s['source'])}</i> — {html.escape(s['description'])}</p>
<p class="{'ok' if m['ok'] else 'bad'}">{html.escape(verdicts)}</p>
{notes}
<a href="{scene_dir}/sheet.png"><img class="sheet" src="{scene_dir}/sheet.png" alt="sheet"></a>
<div class="plots">{plots_html}</div>
<ul>{terms}</ul>
<ul>{objects}</ul>
<p>{m['resolution'][0]}×{m['resolution'][1]} px; {m['pixels']['compared']} pixels compared,
{m['pixels']['ambiguous']} at a discontinuity of the model left out; {timing}.</p>
<details><summary>Parameters</summary><pre>{html.escape(json.dumps(s, indent=1, ensure_ascii=False))}</pre></details>
</section>"""


def write_index(out_dir: str) -> str:
    """index.html over every finished scene folder of *out_dir* (shards merge)."""
    found = results(out_dir)
    sections = "".join(_section(out_dir, m) for m in found)
    try:
        state = check_run(out_dir)
    except RunError:
        state = None
    ok = all(m["ok"] for m in found)
    blind = [m["scene"] for m in found if not m.get("coverage", {}).get("ok", True)]
    headline = ("every engine matches the reference" if ok else
                f"the camera of {html.escape(', '.join(blind))} sees (almost) no Phong "
                "surface: not compared" if blind else "some engine does NOT match the reference")
    whole = state is not None and not state["missing"] and not state["failed"]
    run_line = "" if state is None else (f"<p class='{'ok' if whole else 'bad'}'>Run: "
                                         f"{html.escape(run_text(state))}.</p>")
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Phong Nodes: Eevee, Cycles and the formulas</title>
<style>
body {{ font-family: sans-serif; max-width: 1400px; margin: 1em auto; padding: 0 1em; }}
table {{ border-collapse: collapse; }} td, th {{ border: 1px solid #ccc; padding: 2px 8px; text-align: right; }}
td:first-child, td:nth-child(2) {{ text-align: left; }}
.ok {{ color: #176117; }} .bad {{ color: #b00; font-weight: bold; }}
img.sheet {{ max-width: 100%; }} .plots img {{ margin: 4px; border: 1px solid #ddd; }}
</style></head><body>
<h1>Phong Nodes: Eevee, Cycles and the numpy reference</h1>
<p class="{'ok' if ok else 'bad'}">{len(found)} scene(s): {headline}
(Cycles: max |Δ| ≤ 1e-4; Eevee: ≥ 99.5% of pixels within 1/255).</p>
{run_line}
<p>Each picture is rendered with one sample at the pixel centres; the reference evaluates the seed formulas
(node_groups/reference.py) for the scene's lights as Blender evaluates them (world matrices, colours, Phong settings,
Light Linking, the World's ambient) on what each pixel's lights group sees, written by Cycles as AOVs (position, normal,
incoming direction, the material's inputs).  The term images are Cycles' own term passes, each compared with the reference's term.
Background pixels and pixels within 1e-5 of a discontinuity of the model (spot cone edge, terminator) are not compared.</p>
<table><tr><th>scene</th><th>pair</th><th>max |Δ|</th><th>mean |Δ|</th><th>PSNR dB</th><th>&gt; 1/255</th><th>pixels</th></tr>
{_rows(found)}</table>
{sections}
</body></html>
"""
    return write_file(os.path.join(out_dir, "index.html"), page)
