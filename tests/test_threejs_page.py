# SPDX-License-Identifier: GPL-3.0-or-later
"""The three.js peer renderer without Blender: the page of ``core/threejs.py`` rendered by
headless Chromium (``core/browser.py``), its pixels checked against values worked out here by
hand from three.js's formulas (MeshLambertMaterial / MeshPhongMaterial, physical light units,
sRGB output).

The browser tests skip without Chromium or three.js (``bash tools/phong.sh setup`` installs
three.js with npm), except under CI (``CI`` set), where they fail: CI must run them.
"""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from phong_nodes.core import browser, threejs

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
W, H = 256, 128
NEAR, FAR = 0.1, 100.0

# An orthographic camera at z = 5 looking down -z: it sees x in [-2, 2] and y in [-1, 1]
# (64 pixels per unit).  Matrices column-major, as THREE.Matrix4.fromArray takes them.
ORTHO = {
    "type": "orthographic",
    "matrix_world": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1],
    "projection": [2 / 4, 0, 0, 0, 0, 2 / 2, 0, 0, 0, 0, -2 / (FAR - NEAR), 0,
                   0, 0, -(FAR + NEAR) / (FAR - NEAR), 1],
}
# A perspective camera at z = 5, tan(half vertical fov) = 0.5, aspect 2.
PERSPECTIVE = {
    "type": "perspective",
    "matrix_world": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1],
    "projection": [1, 0, 0, 0, 0, 2, 0, 0, 0, 0, (FAR + NEAR) / (NEAR - FAR), -1,
                   0, 0, 2 * FAR * NEAR / (NEAR - FAR), 0],
}
C = (0.5, 0.25, 0.1)    # the Lambert colour of the brief
C2 = (0.2, 0.3, 0.4)


# --- formulas, by hand -------------------------------------------------------------------

def srgb_byte(linear):
    """Piecewise sRGB OETF of linear values, as 0..255 floats (clamped)."""
    out = []
    for x in linear:
        x = min(max(x, 0.0), 1.0)
        v = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
        out.append(255.0 * v)
    return out


def blinn_phong_along_normal(f0, shininess):
    """three's BRDF_BlinnPhong with light, view and normal all alike (dotVH = dotNH = 1)."""
    f = 2.0 ** ((-5.55473 * 1.0 - 6.98316) * 1.0)
    fresnel = [s * (1.0 - f) + f for s in f0]
    d = (shininess / 2.0 + 1.0) / math.pi
    return [x * 0.25 * d for x in fresnel]


def smoothstep(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def at(row, col):
    """World (x, y) of the centre of pixel (row, col) on the plane z = 0 under ORTHO."""
    return -2.0 + (col + 0.5) * 4.0 / W, 1.0 - (row + 0.5) * 2.0 / H


def col_of(x):
    return int((x + 2.0) / 4.0 * W)


def quad(x0, x1, y0, y1):
    """Two triangles in the plane z = 0 facing +z."""
    a, b, c, d = (x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)
    return {"positions": [*a, *b, *c, *a, *c, *d], "normals": [0, 0, 1] * 6}


def scene(title, camera, lights, materials, meshes, ambient=((0, 0, 0), 0.0)):
    return {"format": "phong-nodes-threejs", "version": 1, "title": title,
            "width": W, "height": H, "camera": camera,
            "ambient": {"color": list(ambient[0]), "intensity": ambient[1]},
            "lights": lights, "materials": materials, "meshes": meshes}


def sun(name, color, intensity):
    return {"name": name, "type": "directional", "color": list(color), "intensity": intensity,
            "position": [0, 0, 1], "target": [0, 0, 0]}


def lambert(name, color, emissive=(0, 0, 0)):
    return {"name": name, "type": "lambert", "color": list(color), "emissive": list(emissive)}


def phong(name, color, specular, shininess, emissive=(0, 0, 0), strength=1.0):
    return {"name": name, "type": "phong", "color": list(color), "emissive": list(emissive),
            "specular": list(specular), "shininess": shininess, "specular_strength": strength}


def mesh(name, material, lights, geometry):
    return {"name": name, "material": material, "lights": lights, **geometry}


def assert_pixel(result, row, col, linear, what):
    got = result.rgba[row, col]
    want = srgb_byte(linear)
    assert got[3] == 255, f"{what}: pixel ({row}, {col}) not covered: {got}"
    assert np.all(np.abs(got[:3].astype(float) - want) <= 1.0), (
        f"{what}: pixel ({row}, {col}) is {got[:3]}, expected {np.round(want, 2)} "
        f"(linear {np.round(linear, 4)})")


def assert_background(result, row, col):
    assert tuple(result.rgba[row, col]) == (0, 0, 0, 0), (row, col, result.rgba[row, col])


# --- the browser ---------------------------------------------------------------------------

def _missing(message):
    if os.environ.get("CI"):
        pytest.fail(f"CI runs the three.js peer tests: {message}")
    pytest.skip(message)


@pytest.fixture(scope="module")
def peer():
    problem = threejs.unavailable()
    if problem is not None:
        _missing(problem)


@pytest.fixture(scope="module")
def render(peer, tmp_path_factory):
    folder = tmp_path_factory.mktemp("threejs")
    cache = {}

    def run(name, page):
        if name not in cache:
            path = str(folder / f"{name}.html")
            threejs.write_page(path, page)
            cache[name] = browser.render_page(path, timeout=120)
        return cache[name]
    return run


def directional_page():
    """Left: Lambert C lit by light 0 (white, 2) only.  Right: Phong lit by light 1 only."""
    return scene("directional", ORTHO,
                 [sun("white", (1, 1, 1), 2.0), sun("warm", (1, 0.9, 0.8), 1.0)],
                 [lambert("lambert", C), phong("phong", C2, (0.1, 0.1, 0.1), 8.0)],
                 [mesh("left", 0, [0], quad(-1.9, -0.1, -0.9, 0.9)),
                  mesh("right", 1, [1], quad(0.1, 1.9, -0.9, 0.9))])


def test_page_loads_without_errors(render):
    """A perspective camera: the quad [-1, 1] x [-0.5, 0.5] lands where the projection puts it
    (x: NDC ±0.2, columns 102.4 .. 153.6; y: NDC ±0.2, rows 51.2 .. 76.8)."""
    page = scene("perspective", PERSPECTIVE, [sun("white", (1, 1, 1), 2.0)],
                 [lambert("lambert", C)], [mesh("quad", 0, [0], quad(-1, 1, -0.5, 0.5))])
    result = render("perspective", page)
    assert result.errors == []
    assert result.title == "phong: done"
    assert result.rgba.shape == (H, W, 4) and result.rgba.dtype == np.uint8
    assert 0 < result.seconds < 120
    lit = [2 * c / math.pi for c in C]
    for row, col in [(64, 128), (64, 104), (64, 152), (53, 128), (75, 128), (52, 103)]:
        assert_pixel(result, row, col, lit, "perspective")
    for row, col in [(64, 101), (64, 155), (50, 128), (78, 128), (0, 0), (127, 255)]:
        assert_background(result, row, col)


def test_script_error_is_reported(render):
    """An unknown light type makes the page throw: no pixels, and the error says why."""
    page = directional_page()
    page["lights"][1]["type"] = "area"
    with pytest.raises(browser.BrowserError) as caught:
        render("bad-light", page)
    assert caught.value.title == "phong: error"
    assert caught.value.errors, "the page's error was not captured"
    assert any('unknown type \\"area\\"' in e or 'unknown type "area"' in e
               for e in caught.value.errors), caught.value.errors
    assert "area" in str(caught.value)


def test_lambert_and_phong_under_directional_lights(render):
    """(a) Lambert 2·C/π; (b) Phong with light and view along the normal: diffuse plus
    irradiance·F·0.25·D; (g) alpha; (h) each quad lit by its own light only."""
    result = render("directional", directional_page())
    assert result.errors == [] and result.title == "phong: done"
    lambert_value = [2 * c / math.pi for c in C]
    irradiance = (1.0, 0.9, 0.8)
    specular = blinn_phong_along_normal((0.1, 0.1, 0.1), 8.0)
    phong_value = [e * (c / math.pi + s) for e, c, s in zip(irradiance, C2, specular)]
    for row in (10, 64, 117):
        for x in (-1.8, -1.0, -0.2):
            assert_pixel(result, row, col_of(x), lambert_value, "lambert")
        # Off-centre pixels too: under an orthographic camera the view is along -z everywhere.
        for x in (0.2, 1.0, 1.8):
            assert_pixel(result, row, col_of(x), phong_value, "phong")
    for row, col in [(64, 127), (64, 128), (0, 10), (127, 200), (64, 0), (64, 255)]:
        assert_background(result, row, col)
    covered = result.rgba[..., 3]
    assert set(np.unique(covered)) == {0, 255}


def test_point_and_spot_lights(render):
    """(c) A point light 2 above the left quad's centre, decay 2, cutoff 3:
    1/d² · (1 − (d/3)⁴)² · cosθ.  (d) A spot 1 above the right quad's centre, half angle
    0.5, penumbra 0.5: smoothstep(cos 0.5, cos 0.25, cos ω) / d² · cosθ."""
    point = {"name": "point", "type": "point", "color": [1, 1, 1], "intensity": 10.0,
             "position": [-1, 0, 2], "distance": 3.0, "decay": 2.0}
    spot = {"name": "spot", "type": "spot", "color": [1, 1, 1], "intensity": 3.0,
            "position": [1, 0, 1], "target": [1, 0, 0], "distance": 0.0, "decay": 2.0,
            "angle": 0.5, "penumbra": 0.5}
    page = scene("point and spot", ORTHO, [point, spot], [lambert("lambert", C)],
                 [mesh("left", 0, [0], quad(-1.95, -0.05, -0.95, 0.95)),
                  mesh("right", 0, [1], quad(0.05, 1.95, -0.95, 0.95))])
    result = render("point-spot", page)
    assert result.errors == [] and result.title == "phong: done"

    def lit(light, row, col, height):
        x, y = at(row, col)
        dx, dy = x - light["position"][0], y - light["position"][1]
        d = math.sqrt(dx * dx + dy * dy + height * height)
        cos_theta = height / d       # the normal is +z
        falloff = 1.0 / max(d ** light["decay"], 0.01)
        if light["distance"] > 0:
            falloff *= min(max(1.0 - (d / light["distance"]) ** 4, 0.0), 1.0) ** 2
        if light["type"] == "spot":  # the spot points straight down: cos ω = cos θ
            falloff *= smoothstep(math.cos(light["angle"]),
                                  math.cos(light["angle"] * (1 - light["penumbra"])), cos_theta)
        return [light["intensity"] * falloff * cos_theta * c / math.pi for c in C]

    # Centre pixel of the left quad, then away from it (where the cutoff bites harder).
    for row, x in [(64, -1.0), (64, -1.5), (64, -1.9), (10, -1.0), (120, -0.3)]:
        col = col_of(x)
        assert_pixel(result, row, col, lit(point, row, col, 2.0), f"point at x={x}")
    # The spot: inside the inner cone (r < tan 0.25 = 0.255), in the penumbra, outside
    # (r > tan 0.5 = 0.546: black but covered).
    spot_values = []
    for x in (1.0, 1.2, 1.3, 1.35, 1.4, 1.45, 1.5, 1.7, 0.6):
        col = col_of(x)
        want = lit(spot, 64, col, 1.0)
        spot_values.append(want[0])
        assert_pixel(result, 64, col, want, f"spot at x={x}")
    assert spot_values[0] > spot_values[3] > spot_values[5] > 0 and spot_values[-2] == 0
    # (h) Each quad sees only its own light: at x = 0.3 the right quad is outside the spot's
    # cone (black), while the point light (d = 2.39 < its cutoff 3) would light it if it leaked.
    col = col_of(0.3)
    assert_pixel(result, 64, col, lit(spot, 64, col, 1.0), "right quad without the point light")
    assert_background(result, 64, 128)


def test_ambient_emissive_and_specular_strength(render):
    """(e) Ambient only: ambient·intensity·C/π.  (f) Emissive adds as is, with a Phong whose
    specular_strength 0.5 halves its highlight (a float specularMap)."""
    ambient = ((1.0, 0.8, 0.6), 1.5)
    emissive = (0.05, 0.1, 0.15)
    page = scene("ambient", ORTHO, [sun("white", (1, 1, 1), 1.0)],
                 [lambert("lambert", C),
                  phong("phong", C2, (0.2, 0.2, 0.2), 20.0, emissive=emissive, strength=0.5)],
                 [mesh("left", 0, [], quad(-1.9, -0.1, -0.9, 0.9)),
                  mesh("right", 1, [0], quad(0.1, 1.9, -0.9, 0.9))], ambient=ambient)
    result = render("ambient", page)
    assert result.errors == [] and result.title == "phong: done"
    amb = [a * ambient[1] for a in ambient[0]]
    left = [a * c / math.pi for a, c in zip(amb, C)]
    specular = blinn_phong_along_normal((0.2, 0.2, 0.2), 20.0)
    right = [a * c / math.pi + c / math.pi + 0.5 * s + e
             for a, c, s, e in zip(amb, C2, specular, emissive)]
    for row in (20, 64, 100):
        for x in (-1.5, -0.5):
            assert_pixel(result, row, col_of(x), left, "ambient")
        for x in (0.5, 1.5):
            assert_pixel(result, row, col_of(x), right, "phong + emissive + strength 0.5")
    assert_background(result, 64, 128)


def _shadow_page(occluder_lights, cast=True):
    """A Lambert floor x in [-1.9, -0.1] at z = 0 and a quad x in [0, 0.5], y in [-0.5, 0.5]
    at z = 1 (seen by *occluder_lights*), under a sun from +x+z at 45 degrees and an ambient
    light: the quad's shadow on z = 0 (p + t·(1, 0, 1) meets z = 1 at t = 1) is x in
    [-1, -0.5], y in [-0.5, 0.5]."""
    raised = quad(0.0, 0.5, -0.5, 0.5)
    raised["positions"] = [v if i % 3 != 2 else 1.0 for i, v in enumerate(raised["positions"])]
    light = dict(sun("slanted", (1, 1, 1), 2.0), position=[1, 0, 1])
    page = scene("shadows", ORTHO, [light], [lambert("floor", C)],
                 [mesh("floor", 0, [0], quad(-1.9, -0.1, -0.9, 0.9)),
                  mesh("occluder", 0, occluder_lights, raised)],
                 ambient=((1.0, 1.0, 1.0), 0.5))
    return threejs.with_shadows(page, [True], [False, cast])


def test_shadow_maps_where_the_page_asks_for_them(render):
    """``with_shadows``: the floor is ambient only, 0.5·C/π, inside the occluder's shadow
    (worked out by hand above), and ambient plus the sun, (0.5 + 2·cos 45°)·C/π, away from
    it; the same with the occluder in another light set (drawn into the floor's shadow map
    only); no shadow from an occluder that does not cast, nor without ``shadows``."""
    shade = [0.5 * c / math.pi for c in C]
    lit = [(0.5 + 2.0 * math.cos(math.pi / 4.0)) * c / math.pi for c in C]
    # rows of y = 0.25, 0, -0.25 and y = 0.75 (lit); columns of x = -0.9 .. -0.6 (shadow)
    inside = [(row, col_of(x)) for row in (48, 64, 80) for x in (-0.9, -0.75, -0.6)]
    outside = [(row, col_of(x)) for row in (64,) for x in (-1.6, -1.3, -0.3)] + \
              [(16, col_of(-0.75)), (112, col_of(-0.75))]
    for name, lights in (("shadows", [0]), ("shadows-sets", [])):
        page = _shadow_page(lights)
        assert page["shadows"] is True and page["lights"][0]["cast_shadow"] is True
        result = render(name, page)
        assert result.errors == [] and result.title == "phong: done"
        for row, col in inside:
            assert_pixel(result, row, col, shade, f"{name}: in the shadow")
        for row, col in outside:
            assert_pixel(result, row, col, lit, f"{name}: lit")
    for name, page in (("shadows-none", _shadow_page([0], cast=False)),
                       ("shadows-off", dict(_shadow_page([0]), shadows=False))):
        result = render(name, page)
        for row, col in inside + outside:
            assert_pixel(result, row, col, lit, f"{name}: lit")


def test_with_shadows_frames_the_scene():
    """A directional light moves to 2 radii from the bounds' centre along its direction, its
    orthographic shadow camera covers the bounding sphere; a point light's near and far
    planes hold the sphere; nothing changes without a casting light."""
    page = scene("frame", ORTHO,
                 [sun("sun", (1, 1, 1), 1.0),
                  {"name": "bulb", "type": "point", "color": [1, 1, 1], "intensity": 1.0,
                   "position": [0, 0, 10], "distance": 0, "decay": 2}],
                 [lambert("m", C)], [mesh("box", 0, [0, 1], quad(-3, 3, -4, 4))])
    assert threejs.with_shadows(page, [False, False], [True]) == page
    out = threejs.with_shadows(page, [True, True], [True])
    radius = 5.0   # the quad's half diagonal: sqrt(3² + 4²)
    sun_light, bulb = out["lights"]
    assert sun_light["position"] == pytest.approx([0, 0, 2 * radius])
    assert sun_light["target"] == [0, 0, 0]
    assert sun_light["shadow"]["extent"] >= radius
    assert sun_light["shadow"]["near"] <= radius <= 3 * radius <= sun_light["shadow"]["far"]
    assert bulb["shadow"]["near"] <= 10 - radius and bulb["shadow"]["far"] >= 10 + radius
    assert bulb["position"] == [0, 0, 10]
    assert out["meshes"][0]["cast_shadow"] and out["meshes"][0]["receive_shadow"]


def test_script_tag_in_names(render, tmp_path):
    """A '</script>' in the title or a name neither closes the scene's tag nor shows as HTML."""
    page = directional_page()
    page["title"] = "a </script><script>document.title='hacked'</script> <!-- title"
    page["materials"][0]["name"] = "</script><b>bold</b>"
    result = render("script-tag", page)
    assert result.errors == [] and result.title == "phong: done"
    assert_pixel(result, 64, col_of(-1.0), [2 * c / math.pi for c in C], "lambert")


# --- pure ------------------------------------------------------------------------------------

@pytest.fixture
def fake_three(tmp_path, monkeypatch):
    """A stand-in three.js install (the page is only written, not rendered)."""
    build = tmp_path / "three" / "node_modules" / "three" / "build"
    build.mkdir(parents=True)
    (build / "three.cjs").write_text("module.exports = {};\n")
    (build.parent / "LICENSE").write_text("The MIT License\n")
    monkeypatch.setenv("PHONG_THREE_DIR", str(tmp_path / "three"))
    return build / "three.cjs"


def test_three_dir(monkeypatch, tmp_path):
    monkeypatch.delenv("PHONG_THREE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert threejs.three_dir() == str(tmp_path / "phong-nodes" / "three-0.181.0")
    monkeypatch.setenv("XDG_CACHE_HOME", "")
    assert threejs.three_dir() == os.path.expanduser("~/.cache/phong-nodes/three-0.181.0")
    monkeypatch.setenv("PHONG_THREE_DIR", str(tmp_path / "elsewhere"))
    assert threejs.three_dir() == str(tmp_path / "elsewhere")
    with pytest.raises(threejs.ThreeMissing, match="tools/phong.sh setup"):
        threejs.three_module()


def test_write_page_and_read_scene(fake_three, tmp_path):
    page = directional_page()
    page["title"] = "</script><script>alert(1)</script> & <!-- x"
    page["materials"][1]["name"] = "</SCRIPT> </script>"
    page["meshes"][0]["positions"] = np.asarray(page["meshes"][0]["positions"], dtype=np.float32)
    out = tmp_path / "out"
    path = out / "scene.html"
    threejs.write_page(str(path), page)
    assert sorted(os.listdir(out)) == ["scene.html", "three.LICENSE", "three.cjs"]
    back = threejs.read_scene(str(path))
    expected = json.loads(json.dumps({**page, "meshes": [
        {**page["meshes"][0], "positions": page["meshes"][0]["positions"].tolist()},
        page["meshes"][1]]}))
    assert back == expected
    text = path.read_text()
    start = text.index('<script type="application/json" id="phong-scene">')
    embedded = text[start:text.index("</script>", start)]
    assert "</" not in embedded.split(">", 1)[1] and "<!--" not in embedded
    assert text.count("</script>") == 6         # the page's own six scripts, no more
    assert "&lt;/script&gt;" in text            # the visible title, escaped
    # The three.js copy is left alone when identical and replaced when not.
    stamp = os.stat(out / "three.cjs").st_mtime_ns
    os.utime(out / "three.cjs", ns=(stamp - 10**9, stamp - 10**9))
    threejs.write_page(str(path), page)
    assert os.stat(out / "three.cjs").st_mtime_ns == stamp - 10**9
    fake_three.write_text("module.exports = {changed: true};\n")
    threejs.write_page(str(path), page)
    assert (out / "three.cjs").read_text() == fake_three.read_text()
    assert sorted(os.listdir(out)) == ["scene.html", "three.LICENSE", "three.cjs"]
    with pytest.raises(ValueError):
        threejs.write_page(str(path), {**page, "width": float("nan")})
    assert sorted(os.listdir(out)) == ["scene.html", "three.LICENSE", "three.cjs"]
    assert threejs.read_scene(str(path)) == expected


def test_browser_log_and_dom_parsing():
    log = "\n".join([
        "/usr/bin/chromium: 9: [: 25276502016: unexpected operator",
        "[1:2:1123/134510.890596:ERROR:dbus/bus.cc:405] Failed to connect to the bus",
        "[1:3:1123/134510.9:ERROR:gpu/command_buffer/service/gl_utils.cc:431] "
        "[GroupMarkerNotSet(crbug.com/242999)!:A0B0]GL ERROR :GL_INVALID_OPERATION",
        "[1:3:1123/134510.9:ERROR:ui/gl/gl_surface_egl.cc:1] eglCreateContext failed "
        "with error EGL_BAD_MATCH",
        '[1:1:1123/134511.397264:INFO:CONSOLE:1] "hello", source: file:///x.html (1)',
        '[1:1:1123/134511.397264:ERROR:CONSOLE:7] "boom", source: file:///x.html (7)',
        '[1:1:1123/134511.397264:ERROR:CONSOLE(8)] "old", source: file:///x.html (8)',
    ])
    assert browser.console_errors(log) == [
        'console: "boom", source: file:///x.html (7)',
        'console: "old", source: file:///x.html (8)']
    pixels = np.arange(2 * 3 * 4, dtype=np.uint8).reshape(2, 3, 4)
    import base64
    dom = ('<html><head><title>phong: done</title></head><body>'
           '<pre id="phong-errors">a &lt;b&gt;\nsecond</pre>'
           f'<pre id="phong-pixels" data-width="3" data-height="2">'
           f'{base64.b64encode(pixels.tobytes()).decode()}</pre></body></html>')
    title, errors, rgba = browser.parse_dom(dom)
    assert title == "phong: done" and errors == ["a <b>", "second"]
    assert np.array_equal(rgba, pixels)
    assert browser.parse_dom(dom.replace('data-width="3"', 'data-width="0"'))[2] is None


def _check_system():
    from phong_nodes.cli import system  # noqa: PLC0415

    return system


def test_browser_packages(monkeypatch, tmp_path):
    check = _check_system()
    assert check.BROWSERS == browser.BROWSERS
    monkeypatch.setenv("PATH", str(tmp_path))   # nothing on PATH
    monkeypatch.delenv("PHONG_CHROMIUM", raising=False)
    assert check.browser_packages() == ["chromium", "nodejs", "npm"]
    assert "sudo apt-get install -y chromium nodejs npm" in check.browser_hint()
    assert browser.find_browser() is None
    assert "sudo apt-get install -y chromium nodejs npm" in browser.missing_message()
    with pytest.raises(browser.BrowserError, match="apt-get install"):
        browser.render_page(str(tmp_path / "none.html"))
    for name in ("chromium", "npm"):
        tool = tmp_path / name
        tool.write_text("#!/bin/sh\n")
        tool.chmod(0o755)
    assert check.browser_packages() == [] and check.browser_hint() is None
    assert browser.find_browser() == str(tmp_path / "chromium")
    monkeypatch.setenv("PHONG_CHROMIUM", "no-such-browser")
    assert check.browser_packages() == ["chromium"] and browser.find_browser() is None
    assert "apt-get install -y chromium &&" in browser.missing_message()


def test_three_is_pinned():
    folder = os.path.join(ROOT, "tools", "threejs")
    with open(os.path.join(folder, "package.json")) as stream:
        package = json.load(stream)
    with open(os.path.join(folder, "package-lock.json")) as stream:
        lock = json.load(stream)
    assert package["dependencies"] == {"three": threejs.THREE_VERSION}
    assert lock["packages"]["node_modules/three"]["version"] == threejs.THREE_VERSION
    assert lock["packages"]["node_modules/three"]["integrity"].startswith("sha512-")
    assert not os.path.exists(os.path.join(folder, "node_modules"))
    with open(os.path.join(ROOT, "tools", "phong.sh")) as stream:
        script = stream.read()
    function = script[script.index("ensure_three() {"):]
    function = function[:function.index("}")]
    assert f" three {threejs.THREE_VERSION} PHONG_THREE_DIR build/{threejs.SCRIPT_NAME}\n" \
        in function


# --- pages that finish after the load event (the glTF check's GLTFLoader page) ------------

_LATE_PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>phong: loading</title></head><body>
<pre id="phong-errors"></pre>
<pre id="phong-pixels" data-width="0" data-height="0"></pre>
<script>
@LATE@
</script></body></html>
"""
# Two pixels, (10, 20, 30, 255) and (40, 50, 60, 128), written 1.5 s of real time after the
# load event: nothing is drawn synchronously.
_FINISH_LATE = """
const t0 = performance.now();
setTimeout(() => {
  const pixels = document.getElementById("phong-pixels");
  pixels.setAttribute("data-width", "2");
  pixels.setAttribute("data-height", "1");
  pixels.textContent = btoa(String.fromCharCode(10, 20, 30, 255, 40, 50, 60, 128));
  document.title = "phong: done";
}, 1500);
"""
_NEVER_FINISH = """
document.getElementById("phong-errors").textContent = "texture 3 could not be decoded";
"""


def _late_page(tmp_path, script):
    path = tmp_path / "late.html"
    path.write_text(_LATE_PAGE.replace("@LATE@", script))
    return str(path)


def test_a_page_that_finishes_after_the_load_event_is_read_when_it_says_so(tmp_path):
    if browser.find_browser() is None:
        _missing(browser.missing_message())
    result = browser.render_page(_late_page(tmp_path, _FINISH_LATE), timeout=60,
                                 until_done=True)
    assert result.title == "phong: done" and result.errors == []
    assert result.rgba.tolist() == [[[10, 20, 30, 255], [40, 50, 60, 128]]]
    assert result.seconds >= 1.5


def test_a_page_that_never_finishes_names_its_title_and_errors(tmp_path):
    if browser.find_browser() is None:
        _missing(browser.missing_message())
    with pytest.raises(browser.BrowserError) as caught:
        browser.render_page(_late_page(tmp_path, _NEVER_FINISH), timeout=8, until_done=True)
    message = str(caught.value)
    assert "did not finish" in message and "'phong: loading'" in message
    assert "texture 3 could not be decoded" in message
    assert caught.value.title == "phong: loading"
