# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison without Blender: the reference picture from synthetic AOV arrays, checked
against values worked out by hand from the formulas (docs/model.md), and the metrics and
verdicts against the tolerances."""

import math

import numpy as np
import pytest

from phong_nodes.core import compare, scenes

SCENE = scenes.parse({
    "title": "synthetic",
    "camera": {"location": [0, 0, 5]},
    "ambient": {"intensity": 0.25, "color": [1.0, 1.0, 1.0]},
    "lights": [
        {"name": "sun", "type": "directional", "direction": [0, 0, -1], "intensity": 0.4},
        {"name": "spot", "type": "spot", "position": [0, 0, 2], "direction": [0, 0, -1],
         "half_angle": 45.0, "intensity": 0.0},
    ],
    "objects": [
        {"name": "lit", "material": {"exponent": 10, "specular_color": [1.0, 1.0, 1.0]}},
        {"name": "dark", "lights": [], "material": {"irradiant": [0.1, 0.0, 0.0]}},
    ],
})
C1 = np.array([0.5, 0.4, 0.2])   # the object colours that Cycles writes as an AOV
C2 = np.array([0.3, 0.6, 0.9])


def aovs():
    """A 1 x 4 picture: lit object facing the light, lit object tilted, background, the
    object that no light reaches."""
    def row(*pixels):
        return np.array([list(p) for p in pixels], dtype=np.float32)[None, ...]

    up, tilted = (0, 0, 1), (0.6, 0, 0.8)
    at_edge = (2.0 * math.tan(math.radians(45.0)), 0.0, 0.0)  # on the spot's cone, ω = 45°
    return {
        "phong_index": row((1, 1, 1), (1, 1, 1), (0, 0, 0), (2, 2, 2)),
        "phong_P": row((0, 0, 0), at_edge, (0, 0, 0), (0, 0, 0)),
        "phong_N": row(up, tilted, up, up),
        "phong_I": row(up, up, up, up),
        "phong_color": row(C1, C1, (0, 0, 0), C2),
    }


def test_reference_picture_from_aovs_matches_the_formulas_by_hand():
    img = compare.reference_image(SCENE, aovs())
    ambient = 0.25 * C1
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


def test_metrics_and_verdicts_follow_the_tolerances():
    data = dict(SCENE, name="synthetic")
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
