# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison without Blender: the reference picture from synthetic AOV arrays, checked
against values worked out by hand from the formulas (docs/model.md), and the metrics and
verdicts against the tolerances."""

import math

import numpy as np
import pytest

from phong_nodes.core import compare

# The scene as Blender evaluates it (addon/scene/describe.py): a sun and a spot (intensity 0,
# so only its cone edge matters); object 1 is reached by both, object 2 by none.
SCENE = {
    "name": "synthetic", "title": "synthetic",
    "ambient": {"intensity": 0.25, "color": [1.0, 1.0, 1.0]},
    "lights": [
        {"name": "sun", "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 0.4,
         "diffuse": 1.0, "specular": 1.0, "direction": [0, 0, -1]},
        {"name": "spot", "type": "spot", "color": [1.0, 1.0, 1.0], "intensity": 0.0,
         "diffuse": 1.0, "specular": 1.0, "position": [0, 0, 2], "direction": [0, 0, -1],
         "quadratic": 1.0, "linear": 0.0, "constant": 0.0, "half_angle": 45.0,
         "edge_exponent": 0.0},
    ],
    "objects": [{"name": "lit", "lights": [0, 1]}, {"name": "dark", "lights": []}],
}
C1 = np.array([0.5, 0.4, 0.2])   # the object colours the lights groups see
C2 = np.array([0.3, 0.6, 0.9])
KA = np.array([0.2, 0.2, 0.2])   # object 1's own Ambient Object Color


def aovs():
    """A 1 x 4 picture: lit object facing the light, lit object tilted, background, the
    object that no light reaches (irradiant (0.1, 0, 0))."""
    def row(*pixels):
        return np.array([list(p) for p in pixels], dtype=np.float32)[None, ...]

    up, tilted, zero = (0, 0, 1), (0.6, 0, 0.8), (0, 0, 0)
    at_edge = (2.0 * math.tan(math.radians(45.0)), 0.0, 0.0)  # on the spot's cone, ω = 45°
    probes = {
        "params": row((10, 0, 1), (10, 0, 1), zero, (30, 0, 2)),
        "P": row(zero, at_edge, zero, zero),
        "N": row(up, tilted, up, up),
        "I": row(up, up, up, up),
        "normal": row(zero, zero, zero, zero),
        "view": row(zero, zero, zero, zero),
        "color": row(C1, C1, zero, C2),
        "ambient": row(KA, KA, zero, C2),
        "specular": row((1, 1, 1), (1, 1, 1), zero, (1, 1, 1)),
        "irradiant": row(zero, zero, zero, (0.1, 0, 0)),
    }
    return {compare.probe_name(k): v for k, v in probes.items()}


def test_reference_picture_from_probes_matches_the_formulas_by_hand():
    img = compare.reference_image(SCENE, aovs())
    ambient = 0.25 * KA
    # facing the sun (ℓ = n = v): diffuse i·1·C, specular i·1^e·C_spec
    np.testing.assert_allclose(img["Ambient"][0, 0], ambient, atol=1e-7)
    np.testing.assert_allclose(img["Diffuse"][0, 0], 0.4 * C1, atol=1e-7)
    np.testing.assert_allclose(img["Specular"][0, 0], [0.4] * 3, atol=1e-7)
    np.testing.assert_allclose(img["Color"][0, 0], ambient + 0.4 * C1 + 0.4, atol=1e-7)
    # tilted: ℓ·n = 0.8, r = 2(ℓ·n)n - ℓ = (0.96, 0, 0.28), r·v = 0.28
    np.testing.assert_allclose(img["Diffuse"][0, 1], 0.4 * 0.8 * C1, atol=1e-7)
    np.testing.assert_allclose(img["Specular"][0, 1], [0.4 * 0.28 ** 10] * 3, atol=1e-9)
    # the background is black and not an object; the unlit object gets ambient + irradiant
    assert img["object"].tolist() == [[1, 1, 0, 2]]
    np.testing.assert_array_equal(img["Color"][0, 2], [0, 0, 0])
    np.testing.assert_allclose(img["Color"][0, 3], 0.25 * C2 + [0.1, 0, 0], atol=1e-7)
    np.testing.assert_array_equal(img["Diffuse"][0, 3], [0, 0, 0])
    # the pixel on the spot's cone edge is left out of the comparison
    assert img["ambiguous"].tolist() == [[False, True, False, False]]


def test_a_linked_normal_and_view_vector_are_used_where_given():
    """Probes of a material that links Normal (a bump) and View Vector: the reference
    shades with them, not with the geometry's."""
    data = aovs()
    data[compare.probe_name("normal")][0, 0] = (0.0, 0.0, 2.0)  # not normalised: n = up
    data[compare.probe_name("N")][0, 0] = (0.6, 0.0, 0.8)        # the geometry is tilted
    data[compare.probe_name("view")][0, 0] = (0.0, 0.0, 5.0)
    img = compare.reference_image(SCENE, data)
    np.testing.assert_allclose(img["Diffuse"][0, 0], 0.4 * C1, atol=1e-7)
    np.testing.assert_allclose(img["Specular"][0, 0], [0.4] * 3, atol=1e-7)


def test_metrics_and_verdicts_follow_the_tolerances():
    data = SCENE
    ref = compare.reference_image(SCENE, aovs())["Color"]
    good = {"cycles": ref + 5e-5, "eevee": ref + 0.5 / 255}
    metrics, _ref, mask = compare.evaluate(data, good, aovs(), ("cycles", "eevee"))
    assert mask.tolist() == [[True, False, False, True]]
    assert metrics["pixels"]["compared"] == 2 and metrics["pixels"]["ambiguous"] == 1
    assert metrics["pairs"]["cycles-reference"]["max_abs"] == pytest.approx(5e-5, rel=1e-3)
    assert metrics["ok"], metrics["verdict"]
    bad = {"cycles": ref + 2e-4, "eevee": ref + 2.0 / 255}
    metrics, _ref, _mask = compare.evaluate(data, bad, aovs(), ("cycles", "eevee"))
    assert not metrics["verdict"]["cycles"]["ok"] and not metrics["verdict"]["eevee"]["ok"]
    assert compare.verdict_text(metrics["verdict"]) == "cycles 2.00e-04 FAIL, eevee 0.000% FAIL"


def test_a_term_pass_off_the_reference_fails_cycles():
    """The render's own term passes are compared with the reference's terms, and count in
    Cycles' verdict: a right picture with a wrong Specular pass does not pass."""
    ref = compare.reference_image(SCENE, aovs())
    images = {"cycles": ref["Color"].copy()}
    terms = {t: ref[t].copy() for t in compare.TERMS}
    metrics, _ref, _mask = compare.evaluate(SCENE, dict(images), aovs(), ("cycles",), terms)
    assert metrics["ok"] and set(metrics["terms"]) == set(compare.TERMS)
    terms["Specular"][0, 0] += 3e-4
    metrics, _ref, _mask = compare.evaluate(SCENE, dict(images), aovs(), ("cycles",), terms)
    assert metrics["terms"]["Specular"]["max_abs"] == pytest.approx(3e-4, rel=1e-6)
    assert not metrics["ok"] and metrics["verdict"]["cycles"]["value"] == "3.00e-04"


def _padded(height, width):
    """aovs() at the top left of a picture of *height* × *width* whose other pixels are
    background (object number 0): 2 pixels compared (object 1 facing the light, object 2)."""
    out = {}
    for name, row in aovs().items():
        picture = np.zeros((height, width) + row.shape[2:], dtype=row.dtype)
        picture[:1, :4] = row
        out[name] = picture
    return out


def test_a_picture_of_almost_no_phong_surface_fails_and_says_why():
    """The comparison needs Phong surfaces on at least 1% of the pixels: 2 compared of 200
    pass, 2 of 310 (0.65%; with the pixel at the cone edge 3, 0.97%) fail with a message,
    even though Cycles matches the reference exactly."""
    for (height, width), ok in (((10, 20), True), ((10, 31), False)):
        data = _padded(height, width)
        ref = compare.reference_image(SCENE, data)["Color"]
        metrics, _ref, mask = compare.evaluate(SCENE, {"cycles": ref.copy()}, data, ("cycles",))
        assert int(mask.sum()) == 2 and mask.size == height * width
        assert metrics["verdict"]["cycles"]["ok"], "the engine itself matches"
        assert metrics["coverage"]["ok"] is ok and metrics["ok"] is ok
        text = compare.summary_text(metrics)
        if ok:
            assert text == "cycles 0.00e+00 OK" and "message" not in metrics["coverage"]
        else:
            message = metrics["coverage"]["message"]
            assert message.startswith("the camera sees 2 of 310 pixels of Phong surfaces")
            assert "(0.65%, fewer than 1%)" in message and "give it a camera" in message
            assert text == f"FAIL: {message} (on those pixels: cycles 0.00e+00 OK)"
    # nothing at all in view: a picture of background only
    empty = {name: np.zeros_like(a) for name, a in _padded(8, 8).items()}
    metrics, _ref, _mask = compare.evaluate(SCENE, {"cycles": np.zeros((8, 8, 3))}, empty,
                                            ("cycles",))
    assert not metrics["ok"] and metrics["coverage"]["pixels"] == 0
    assert "the camera sees 0 of 64 pixels" in metrics["coverage"]["message"]


def test_phong_surfaces_in_view_that_cannot_be_compared_fail_with_their_own_reason():
    """Object pixels on 3 of 210 pixels (1.4%), of which 1 is at the spot's cone edge: 2
    compared (0.95%) fail, and the message says the surfaces are in view but not comparable,
    not that the camera misses them."""
    data = _padded(10, 21)
    ref = compare.reference_image(SCENE, data)["Color"]
    metrics, _ref, _mask = compare.evaluate(SCENE, {"cycles": ref.copy()}, data, ("cycles",))
    assert metrics["pixels"]["object"] == 3 and not metrics["ok"]
    message = metrics["coverage"]["message"]
    assert message.startswith("the camera sees Phong surfaces on 3 of 210 pixels but only 2 "
                              "can be compared (0.95%, fewer than 1%)")
    assert "see-through" in message and "frame the scene" not in message


def _quad(lift):
    """A unit quad in z = 0 whose corner (1, 1) is lifted by *lift*, as Blender gives it: its
    own normal (Newell's, the corners' average plane) and its two triangles' normals."""
    corners = np.array([[0, 0, 0], [1, 0, 0], [1, 1, lift], [0, 1, 0]], float)
    newell = np.zeros(3)
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        newell += [(a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]),
                   (a[0] - b[0]) * (a[1] + b[1])]
    triangles = [np.cross(corners[1] - corners[0], corners[2] - corners[0]),
                 np.cross(corners[2] - corners[0], corners[3] - corners[0])]
    unit = [t / np.linalg.norm(t) for t in triangles]
    return newell / np.linalg.norm(newell), unit


def test_a_flat_polygon_is_warped_where_its_triangles_turn_from_it_by_the_angle():
    """A quad lifted by 0.01 at one corner turns its triangles by about 0.2° from its own
    normal (under WARP_ANGLE: n·ℓ moves by less than 1/255), one lifted by 0.1 by about 2°:
    warped where flat, not where smooth (the engines interpolate the same corner normals);
    a degenerate triangle (no normal) does not count."""
    polygons, triangles, owners = [], [], []
    for index, lift in enumerate((0.0, 0.005, 0.1, 0.1)):
        normal, (t1, t2) = _quad(lift)
        polygons.append(normal)
        triangles += [t1, t2]
        owners += [index, index]
        turned = math.acos(min(1.0, float(normal @ t1)))
        assert (turned > compare.WARP_ANGLE) == (lift > 0.05), (lift, math.degrees(turned))
    flat = np.array([True, True, True, False])
    assert compare.warped_polygons(np.array(polygons), flat, np.array(triangles),
                                   np.array(owners)) == 1
    assert compare.warped_polygons(np.array(polygons), np.ones(4, bool), np.array(triangles),
                                   np.array(owners)) == 2
    assert compare.warped_polygons(np.array(polygons), np.ones(4, bool),
                                   np.zeros((8, 3)), np.array(owners)) == 0
    assert compare.warped_polygons(np.zeros((0, 3)), np.zeros(0, bool), np.zeros((0, 3)),
                                   np.zeros(0, int)) == 0
