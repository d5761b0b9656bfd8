# SPDX-License-Identifier: GPL-3.0-or-later
"""The X_ITE peer renderer without Blender: hand-written X3D / VRML97 files rendered by X_ITE in
headless Chromium (``core/x_ite.py``), every covered pixel checked against the standard's
lighting equation (ISO/IEC 19775-1 §17.2.2.4) computed here with the independent numpy
restatement of ``node_groups/reference.py`` (``x3d_*``) or by hand, within 2/255.

X_ITE is run with ``ColorSpace SRGB``: its canvas holds round(255 · min(I, 1)), the equation's
value itself (the X3D 3 rule), so the expectations are 255 · I.  The browser tests skip without
Chromium or X_ITE (``bash tools/phong.sh setup`` installs X_ITE with npm), except under CI
(``CI`` set), where they fail: CI must run them.
"""

from __future__ import annotations

import gzip
import json
import math
import os

import numpy as np
import pytest

from phong_nodes.core import browser, x_ite
from phong_nodes.node_groups import reference as ref

W, H = 256, 128
#: 2/255 in bytes: the peer's tolerance (core.compare.X3D_PEER_STEP).
TOLERANCE = 2.0
EYE = np.array([0.0, 0.0, 5.0])
#: An OrthoViewpoint at z = 5 looking down -z that sees x in [-2, 2], y in [-1, 1]: 64 pixels
#: per unit, pixel (row, col) centred on x = -2 + (col + 0.5)/64, y = 1 - (row + 0.5)/64.
ORTHO = '<OrthoViewpoint position="0 0 5" fieldOfView="-2 -1 2 1"/>'


# --- files --------------------------------------------------------------------------------

def x3d(*nodes, headlight=False, viewpoint=ORTHO, version="3.3"):
    """An X3D XML file of *nodes* (strings) with a NavigationInfo and the viewpoint."""
    body = "\n".join(nodes)
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<X3D profile="Immersive" version="{version}">\n<Scene>\n'
            f'<NavigationInfo headlight="{"true" if headlight else "false"}" type=\'"NONE"\'/>\n'
            f'{viewpoint}\n{body}\n</Scene>\n</X3D>\n')


def material(diffuse=(0.8, 0.8, 0.8), ambient=0.2, specular=(0, 0, 0), shininess=0.2,
             emissive=(0, 0, 0)):
    return (f'<Material diffuseColor="{_v(diffuse)}" ambientIntensity="{ambient}" '
            f'specularColor="{_v(specular)}" shininess="{shininess}" '
            f'emissiveColor="{_v(emissive)}"/>')


def quad(x0, x1, y0, y1, mat, z=0.0):
    """A quad in the plane z facing +z, with its normal given."""
    points = f"{x0} {y0} {z} {x1} {y0} {z} {x1} {y1} {z} {x0} {y1} {z}"
    return (f'<Shape><Appearance>{mat}</Appearance>'
            f'<IndexedFaceSet solid="false" coordIndex="0 1 2 3 -1" normalPerVertex="false" '
            f'normalIndex="0 -1"><Coordinate point="{points}"/><Normal vector="0 0 1"/>'
            f'</IndexedFaceSet></Shape>')


def _v(values):
    return " ".join(repr(float(x)) for x in values)


def directional(direction, intensity=1.0, ambient=0.0, color=(1, 1, 1), on=True):
    return (f'<DirectionalLight direction="{_v(direction)}" intensity="{intensity}" '
            f'ambientIntensity="{ambient}" color="{_v(color)}" on="{str(on).lower()}" '
            f'global="true"/>')


def point(location, intensity=1.0, ambient=0.0, attenuation=(1, 0, 0), radius=100.0,
          color=(1, 1, 1)):
    return (f'<PointLight location="{_v(location)}" intensity="{intensity}" '
            f'ambientIntensity="{ambient}" attenuation="{_v(attenuation)}" radius="{radius}" '
            f'color="{_v(color)}"/>')


def spot(location, direction, beam, cut, intensity=1.0, ambient=0.0, attenuation=(1, 0, 0),
         radius=100.0, color=(1, 1, 1)):
    return (f'<SpotLight location="{_v(location)}" direction="{_v(direction)}" '
            f'beamWidth="{beam}" cutOffAngle="{cut}" intensity="{intensity}" '
            f'ambientIntensity="{ambient}" attenuation="{_v(attenuation)}" radius="{radius}" '
            f'color="{_v(color)}"/>')


# --- the equation, with reference.py -------------------------------------------------------

def ortho_points():
    """World positions (H, W, 3) of the pixel centres on z = 0 under ORTHO."""
    cols, rows = np.meshgrid(np.arange(W), np.arange(H))
    return np.stack([-2.0 + (cols + 0.5) / 64.0, 1.0 - (rows + 0.5) / 64.0,
                     np.zeros((H, W))], axis=-1)


def equation(P, lights, diffuse, ambient_intensity, specular=(0, 0, 0), shininess=0.0,
             emissive=(0, 0, 0), eye=EYE):
    """The standard's I at the points P (..., 3) of a surface facing +z: lights are
    (kind, parameters) pairs for reference.x3d_*_light; V points to the viewer's position."""
    P = np.asarray(P, float)
    n = np.broadcast_to([0.0, 0.0, 1.0], P.shape)
    v = ref.normalize(eye - P)
    od, os_ = np.asarray(diffuse, float), np.asarray(specular, float)
    total = np.broadcast_to(np.asarray(emissive, float), P.shape).copy()
    for kind, params in lights:
        params = dict(params)
        color = params.pop("color", (1.0, 1.0, 1.0))
        function = {"directional": ref.x3d_directional_light, "point": ref.x3d_point_light,
                    "spot": ref.x3d_spot_light}[kind]
        out = function(**params, geometry_position=P)
        terms = ref.x3d_light_terms(out["Light Vector"], out["Intensity"], out["Ambient"],
                                    color, 128.0 * shininess, n, v)
        total += (terms["Diffuse Light"] * od + terms["Specular Light"] * os_
                  + terms["Ambient Light"] * ambient_intensity * od)
    return np.minimum(total, 1.0)


def assert_close(rgba, expected, where, what, tolerance=TOLERANCE):
    """Every pixel of *where* covered and within *tolerance* bytes of 255·expected."""
    assert (rgba[where][:, 3] == 255).all(), f"{what}: pixels not covered"
    diff = np.abs(rgba[..., :3].astype(float) - 255.0 * expected)[where].max(axis=-1)
    worst = np.unravel_index(np.argmax(np.where(where, np.abs(
        rgba[..., :3].astype(float) - 255.0 * expected).max(axis=-1), -1)), where.shape)
    assert diff.max() <= tolerance, (
        f"{what}: {np.mean(diff > tolerance):.2%} of {diff.size} pixels off by more than "
        f"{tolerance}/255, worst {diff.max():.2f} at {worst}: {rgba[worst]} against "
        f"{np.round(255 * expected[worst], 2)}")
    return float(diff.max())


# --- the browser ---------------------------------------------------------------------------

def _missing(message):
    if os.environ.get("CI"):
        pytest.fail(f"CI runs the X_ITE peer tests: {message}")
    pytest.skip(message)


@pytest.fixture(scope="module")
def peer():
    problem = x_ite.unavailable()
    if problem is not None:
        _missing(problem)


@pytest.fixture(scope="module")
def render(peer, tmp_path_factory):
    folder = tmp_path_factory.mktemp("x_ite")

    def run(name, text, width=W, height=H, suffix=".x3d", color_space="SRGB", packed=False):
        path = folder / f"{name}{suffix}"
        data = text.encode("utf-8")
        path.write_bytes(gzip.compress(data) if packed else data)
        result = x_ite.render_file(str(path), width, height, color_space=color_space,
                                   timeout=120)
        assert result.title == "phong: done" and result.errors == [], result.errors
        assert result.rgba.shape == (height, width, 4) and result.rgba.dtype == np.uint8
        return result.rgba
    return run


# --- tests ----------------------------------------------------------------------------------

def test_unavailable_names_what_to_install(monkeypatch, tmp_path):
    """Without X_ITE the peer says to run setup; without Chromium it names the package."""
    monkeypatch.setenv("PHONG_X_ITE_DIR", str(tmp_path / "nothing"))
    if browser.find_browser() is not None:
        problem = x_ite.unavailable()
        assert problem is not None and "X_ITE 15.0.1" in problem
        assert "setup" in problem or "npm" in problem
    with pytest.raises(x_ite.XIteMissing, match="tools/phong.sh setup"):
        x_ite.x_ite_script()
    monkeypatch.setenv("PHONG_CHROMIUM", str(tmp_path / "no-such-chromium"))
    problem = x_ite.unavailable()
    assert problem is not None and "chromium" in problem and "apt-get install" in problem


def test_the_pinned_version_is_one():
    """package.json, its lockfile, tools/phong.sh and core/x_ite.py name the same X_ITE."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, "tools", "x_ite", "package.json"), encoding="utf-8") as f:
        package = json.load(f)
    with open(os.path.join(root, "tools", "x_ite", "package-lock.json"), encoding="utf-8") as f:
        lock = json.load(f)
    with open(os.path.join(root, "tools", "phong.sh"), encoding="utf-8") as f:
        script = f.read()
    assert package["dependencies"] == {"x_ite": x_ite.X_ITE_VERSION}
    assert lock["packages"]["node_modules/x_ite"]["version"] == x_ite.X_ITE_VERSION
    assert lock["packages"]["node_modules/x_ite"]["integrity"].startswith("sha512-")
    function = script[script.index("ensure_x_ite() {"):]
    function = function[:function.index("}")]
    assert f" x_ite {x_ite.X_ITE_VERSION} PHONG_X_ITE_DIR dist/{x_ite.SCRIPT_NAME}\n" in function
    assert x_ite.x_ite_dir().endswith(f"x_ite-{x_ite.X_ITE_VERSION}") or \
        os.environ.get("PHONG_X_ITE_DIR")


def test_page_embeds_the_file_safely():
    """The file's text survives ``</script>`` and the options reach the page."""
    text = x3d('<WorldInfo title="a </script><script>alert(1)</script> b"/>')
    page = x_ite.page_html(text, 32, 16, script_url="x_ite.min.js")
    start = page.index('<script type="application/json" id="phong-x3d">')
    inner = page[page.index(">", start) + 1:page.index("</script>", start)]
    assert json.loads(inner) == text
    assert '"Shading":"PHONG"' in page and '"ColorSpace":"SRGB"' in page
    assert '"Multisampling":0' in page and 'antialiased="false"' in page
    with pytest.raises(ValueError):
        x_ite.page_html(text, 0, 16, script_url="x")
    with pytest.raises(ValueError):
        x_ite.page_html(text, 16, 16, color_space="P3", script_url="x")


def test_directional_light_diffuse_and_per_light_ambient(render):
    """A DirectionalLight at 36.87° from the normal (N·L = 0.8) with its own ambientIntensity:
    I = IL ⊗ (Ia·ambientIntensity·O_d + I·O_d·0.8) on every pixel of the quad, hand-computed;
    a second light that is off adds nothing; the background is transparent."""
    od = (0.5, 0.25, 0.1)
    rgba = render("directional", x3d(
        directional((0, -0.6, -0.8), intensity=0.8, ambient=0.3, color=(1.0, 0.9, 0.8)),
        directional((0, 0, -1), intensity=1.0, ambient=1.0, on=False),
        quad(-1.5, 1.5, -0.75, 0.75, material(od, ambient=0.5))))
    covered = rgba[..., 3] == 255
    assert covered.sum() == 192 * 96 and set(np.unique(rgba[..., 3])) == {0, 255}
    assert covered[16:112, 32:224].all() and not covered[15, 100] and not covered[64, 31]
    il = np.array([1.0, 0.9, 0.8])
    expected = il * (0.3 * 0.5 * np.array(od) + 0.8 * np.array(od) * 0.8)
    assert_close(rgba, np.broadcast_to(expected, (H, W, 3)), covered, "directional")
    assert (rgba[~covered] == 0).all()


def test_point_light_attenuation_radius_and_specular(render):
    """A PointLight with attenuation (0.5, 0.4, 0.3) (the clamp max(…, 1) bites near it),
    ambientIntensity 0.2 and radius 1.2 over a quad with a Blinn highlight (shininess 0.25:
    exponent 32, V toward the viewer's position): every pixel against reference.py's
    x3d_point_light and x3d_light_terms; beyond the radius only the emissive colour."""
    light = {"location": (0.3, -0.2, 0.6), "intensity": 1.0, "ambient": 0.2,
             "attenuation": (0.5, 0.4, 0.3), "radius": 1.2, "color": (1.0, 0.95, 0.9)}
    mat = dict(diffuse=(0.6, 0.5, 0.3), ambient=0.4, specular=(0.5, 0.5, 0.5), shininess=0.25,
               emissive=(0.05, 0.02, 0.0))
    rgba = render("point", x3d(point(**light), quad(-1.9, 1.9, -0.95, 0.95, material(**mat))))
    P = ortho_points()
    params = {"position": light["location"], "intensity": 1.0, "ambient_intensity": 0.2,
              "constant": 0.5, "linear": 0.4, "quadratic": 0.3, "radius": 1.2,
              "color": light["color"]}
    expected = equation(P, [("point", params)], mat["diffuse"], mat["ambient"],
                        mat["specular"], mat["shininess"], mat["emissive"])
    d = np.linalg.norm(P - np.array(light["location"]), axis=-1)
    quad_mask = (np.abs(P[..., 0]) < 1.9 - 0.02) & (np.abs(P[..., 1]) < 0.95 - 0.02)
    away_from_edge = np.abs(d - 1.2) > 2.0 / 64.0   # the radius cuts the light: a hard edge
    worst = assert_close(rgba, expected, quad_mask & away_from_edge, "point light")
    assert worst <= TOLERANCE
    outside = quad_mask & (d > 1.2 + 2.0 / 64.0)
    assert outside.sum() > 1000
    emissive = 255.0 * np.array(mat["emissive"])
    assert np.abs(rgba[outside][:, :3] - emissive).max() <= 1.0
    near = quad_mask & (d < 0.8)
    assert (rgba[near][:, 0] > 120).all(), "the light is missing inside its radius"
    attenuation = 0.5 + 0.4 * d + 0.3 * d * d
    assert (quad_mask & (attenuation < 1.0)).sum() > 100, "the clamp max(…, 1) is not tested"


def test_spot_light_linear_ramp_and_hard_cone(render):
    """Left: an X3D SpotLight ramp, beamWidth 0.25 to cutOffAngle 0.6, straight down from 1.2
    above; right: beamWidth ≥ cutOffAngle (0.5), a hard edge.  Every pixel against
    reference.py's x3d_spot_light (the hard edge ±1.5 px left out), and the ramp checked by hand
    at three radii."""
    left = {"location": (-1.0, 0.0, 1.2), "direction": (0, 0, -1), "beam": 0.25, "cut": 0.6,
            "intensity": 0.9, "ambient": 0.1}
    right = {"location": (1.0, 0.0, 1.2), "direction": (0, 0, -1), "beam": 0.7, "cut": 0.5,
             "intensity": 0.9, "ambient": 0.1}
    od = (0.9, 0.8, 0.7)
    text = x3d(spot(**left), spot(**right),
               quad(-1.95, 1.95, -0.95, 0.95, material(od, ambient=0.5)))
    rgba = render("spot", text)
    P = ortho_points()

    def params(light):
        return {"position": light["location"], "direction": light["direction"],
                "beam_width": light["beam"], "cut_off_angle": light["cut"],
                "intensity": light["intensity"], "ambient_intensity": light["ambient"]}
    expected = equation(P, [("spot", params(left)), ("spot", params(right))], od, 0.5)
    quad_mask = (np.abs(P[..., 0]) < 1.93) & (np.abs(P[..., 1]) < 0.93)
    r_right = np.hypot(P[..., 0] - 1.0, P[..., 1])
    edge = np.abs(r_right - 1.2 * math.tan(0.5)) < 1.5 / 64.0
    assert_close(rgba, expected, quad_mask & ~edge, "spot lights")
    # By hand along the row through the left light: ω = atan(r / 1.2).
    row = 63  # y = 1/128, practically on the axis
    for r in (0.1, 0.5, 0.65, 0.8):
        col = int(round((-1.0 + r + 2.0) * 64 - 0.5))
        x, y = -2.0 + (col + 0.5) / 64.0, 1.0 - (row + 0.5) / 64.0
        rr = math.hypot(x + 1.0, y)
        omega = math.atan2(rr, 1.2)
        ramp = 1.0 if omega <= 0.25 else 0.0 if omega >= 0.6 else (omega - 0.6) / (0.25 - 0.6)
        d = math.hypot(rr, 1.2)
        value = ramp * (0.1 * 0.5 + 0.9 * 1.2 / d) * od[0]
        assert abs(rgba[row, col, 0] - 255 * value) <= TOLERANCE, (r, rgba[row, col], value)
    # The hard cone: lit just inside, dark just outside.
    inside, outside = 1.2 * math.tan(0.5) - 3 / 64, 1.2 * math.tan(0.5) + 3 / 64
    assert rgba[row, int((1.0 + inside + 2.0) * 64), 0] > 100
    assert rgba[row, int((1.0 + outside + 2.0) * 64), 0] <= 1


def test_headlight_and_perspective_field_of_view(render):
    """A perspective Viewpoint (fieldOfView 0.6: the angle of the picture's smaller side) and
    the headlight (a white DirectionalLight along the view, intensity 1, no ambient), on a
    quad with a highlight: every pixel of the equation, the quad's edges where the projection
    puts them, and nothing lit with the headlight off."""
    fov = 0.6
    viewpoint = f'<Viewpoint position="0 0 5" fieldOfView="{fov}"/>'
    mat = dict(diffuse=(0.4, 0.3, 0.2), ambient=0.3, specular=(0.6, 0.6, 0.6), shininess=0.1)
    shape = quad(-2.0, 2.0, -1.0, 1.0, material(**mat))
    rgba = render("headlight", x3d(shape, headlight=True, viewpoint=viewpoint))
    t = math.tan(fov / 2)
    cols, rows = np.meshgrid(np.arange(W), np.arange(H))
    x_ndc, y_ndc = 2 * (cols + 0.5) / W - 1, 1 - 2 * (rows + 0.5) / H
    ray = np.stack([x_ndc * t * W / H, y_ndc * t, -np.ones((H, W))], axis=-1)
    P = EYE + 5.0 * ray                      # where each pixel's ray meets z = 0
    inside = (np.abs(P[..., 0]) < 2.0) & (np.abs(P[..., 1]) < 1.0)
    margin = (np.abs(P[..., 0]) < 2.0 - 0.05) & (np.abs(P[..., 1]) < 1.0 - 0.05)
    outside = (np.abs(P[..., 0]) > 2.0 + 0.05) | (np.abs(P[..., 1]) > 1.0 + 0.05)
    covered = rgba[..., 3] == 255
    assert covered[margin].all() and not covered[outside].any()
    assert abs(int(covered.sum()) - int(inside.sum())) <= 2 * (W + H) // 8
    headlight = {"direction": (0, 0, -1), "intensity": 1.0, "ambient_intensity": 0.0}
    expected = equation(P, [("directional", headlight)], mat["diffuse"], mat["ambient"],
                        mat["specular"], mat["shininess"])
    assert_close(rgba, expected, margin, "headlight")
    assert rgba[64, 128, 0] > rgba[margin][:, 0].min() + 20, "no highlight at the centre"
    dark = render("headlight-off", x3d(shape, headlight=False, viewpoint=viewpoint))
    assert (dark[..., 3] == rgba[..., 3]).all() and (dark[..., :3] == 0).all()


def test_portrait_picture_takes_the_field_of_view_across(render):
    """In a picture taller than wide the fieldOfView is the horizontal angle."""
    fov = 0.8
    viewpoint = f'<Viewpoint position="0 0 5" fieldOfView="{fov}"/>'
    rgba = render("portrait", x3d(quad(-1.0, 1.0, -1.0, 1.0, material(emissive=(1, 1, 1))),
                                  viewpoint=viewpoint), width=64, height=128)
    half = 5.0 * math.tan(fov / 2)          # half width seen at z = 0
    cols = np.flatnonzero(rgba[64, :, 3] == 255)
    rows = np.flatnonzero(rgba[:, 32, 3] == 255)
    expected = 64 * 1.0 / half              # pixels across the quad, both ways
    assert abs(len(cols) - expected) <= 1.0 and abs(len(rows) - expected) <= 1.0
    assert (rgba[rgba[..., 3] == 255][:, :3] == 255).all()


def test_vrml97_and_gzip_give_the_same_picture(render):
    """The directional scene as VRML97 (gzipped) and as ClassicVRML gives X3D XML's pixels."""
    od = (0.5, 0.25, 0.1)
    xml = x3d(directional((0, -0.6, -0.8), intensity=0.8),
              quad(-1.5, 1.5, -0.75, 0.75, material(od, ambient=0.0)))
    vrml = """#VRML V2.0 utf8
NavigationInfo { headlight FALSE type "NONE" }
Viewpoint { position 0 0 5 fieldOfView 0.6 }
DirectionalLight { direction 0 -0.6 -0.8 intensity 0.8 }
Shape {
  appearance Appearance { material Material { diffuseColor 0.5 0.25 0.1 ambientIntensity 0 } }
  geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ -1.5 -0.75 0, 1.5 -0.75 0,
    1.5 0.75 0, -1.5 0.75 0 ] } coordIndex [ 0 1 2 3 -1 ] }
}
"""
    packed = render("vrml97", vrml, suffix=".wrz", packed=True)
    classic = render("classic", vrml.replace("#VRML V2.0 utf8", "#X3D V3.3 utf8\nPROFILE Immersive"),
                     suffix=".x3dv")
    xml_perspective = render("xml-perspective", xml.replace(
        ORTHO, '<Viewpoint position="0 0 5" fieldOfView="0.6"/>'))
    assert (packed == xml_perspective).all() and (classic == xml_perspective).all()
    covered = packed[..., 3] == 255
    assert covered.sum() > 1000
    assert (np.abs(packed[covered][:, :3] - 255 * 0.64 * np.array(od)) <= 1).all()


def test_linear_color_space_writes_a_2_2_power(render):
    """ColorSpace LINEAR (not the comparison's) writes 255·I^(1/2.2): a 2.2 power, not the sRGB
    curve; SRGB writes 255·I.  I = 0.8·0.5·(0.5, 0.25, 0.1)·... here (0.4, 0.2, 0.08)."""
    text = x3d(directional((0, 0, -1), intensity=0.8),
               quad(-1.5, 1.5, -0.75, 0.75, material((0.5, 0.25, 0.1), ambient=0.0)))
    value = np.array([0.4, 0.2, 0.08])
    srgb = render("srgb", text)
    linear = render("linear", text, color_space="LINEAR")
    assert (np.abs(srgb[64, 128, :3] - 255 * value) <= 1).all()
    assert (np.abs(linear[64, 128, :3] - 255 * value ** (1 / 2.2)) <= 1).all()
    curve = 255 * np.where(value <= 0.0031308, 12.92 * value,
                           1.055 * value ** (1 / 2.4) - 0.055)
    assert np.abs(linear[64, 128, :3] - curve).max() >= 1.5, "indistinguishable from sRGB"


def test_a_broken_file_is_reported(peer, tmp_path):
    """A file X_ITE cannot parse leaves no pixels, and the error says so."""
    path = tmp_path / "broken.x3d"
    path.write_text('<?xml version="1.0"?><X3D><Scene><Shape><Appearance></Scene>')
    with pytest.raises(browser.BrowserError) as caught:
        x_ite.render_file(str(path), 16, 16, timeout=60)
    assert caught.value.title == "phong: error" and caught.value.errors


def test_the_files_background_is_not_drawn(render):
    """A file's own Background (red sky) is not drawn: the peer's alpha is the coverage."""
    rgba = render("background", x3d('<Background skyColor="1 0 0"/>',
                                    quad(-1.0, 1.0, -0.5, 0.5, material(emissive=(0, 1, 0)))))
    covered = rgba[..., 3] == 255
    assert covered.sum() == 128 * 64 and (rgba[~covered] == 0).all()
    assert (rgba[covered][:, :3] == (0, 255, 0)).all()


def test_x_ite_drops_a_light_of_intensity_zero_with_its_ambient(render):
    """A deviation of X_ITE 15.0.1 from the standard, kept here so that it is known: a light of
    intensity 0 is switched off whole (``X3DLightNode.set_on__``: on and intensity > 0), so its
    ambientIntensity adds nothing, where the equation gives Ia·IL·O_a.  A tiny intensity
    brings the ambient back."""
    od = (0.5, 0.5, 0.5)
    shape = quad(-1.0, 1.0, -0.5, 0.5, material(od, ambient=1.0))
    zero = render("intensity-0", x3d(directional((0, 0, -1), intensity=0.0, ambient=0.6), shape))
    tiny = render("intensity-tiny", x3d(directional((0, 0, -1), intensity=1e-20, ambient=0.6),
                                        shape))
    covered = zero[..., 3] == 255
    assert covered.sum() == 128 * 64
    assert (zero[covered][:, :3] == 0).all()                     # the standard: 0.6·0.5 = 0.3
    assert (np.abs(tiny[covered][:, :3] - 255 * 0.3) <= 1).all()
