# SPDX-License-Identifier: GPL-3.0-or-later
"""The group definitions (node_groups/library.py), evaluated on numpy by the expression
builder, agree with the independent reference on random and degenerate inputs.

No Blender here: this catches a wrong formula in seconds; the render tests then check
that Blender's nodes compute what the definitions say.
"""

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from node_groups import library, reference  # noqa: E402

N = 4000
VECTOR_INPUTS = {"Light Vector", "Normal", "View Vector", "Position", "Direction"}


def random_inputs(group, rng):
    values = {}
    for sock in group.inputs:
        if sock.socket_type == "NodeSocketColor":
            values[sock.name] = rng.uniform(-0.2, 1.5, (N, 3))
        elif sock.socket_type == "NodeSocketVector":
            v = rng.normal(size=(N, 3)) * rng.choice([0.0, 1.0, 3.0], size=(N, 1), p=[.1, .6, .3])
            if sock.name == "Light Vector":  # the light groups give unit vectors (or zero)
                norm = np.linalg.norm(v, axis=1, keepdims=True)
                v = np.where(norm > 0, v / np.where(norm > 0, norm, 1), 0)
            values[sock.name] = v
        else:
            low, high = {"Half Angle": (0, np.pi), "Blinn": (-0.2, 1.2), "Exponent": (-1, 200),
                         "Edge Exponent": (-1, 40)}.get(sock.name, (-0.5, 4.0))
            x = rng.uniform(low, high, N)
            x[rng.random(N) < 0.05] = 0.0  # zeros: r = 0, α = β = γ = 0, exponent 0
            values[sock.name] = x
    return values


def random_geometry(rng):
    def unit(v):
        return v / np.linalg.norm(v, axis=1, keepdims=True)
    return {"Position": rng.uniform(-4, 4, (N, 3)), "Normal": unit(rng.normal(size=(N, 3))),
            "Incoming": unit(rng.normal(size=(N, 3)))}


@pytest.mark.parametrize("name", library.NAMES)
def test_definition_matches_reference(name):
    rng = np.random.default_rng(abs(hash(name)) % 2**32)
    group = library.GROUPS[name]
    inputs, geometry = random_inputs(group, rng), random_geometry(rng)
    got = group.evaluate(inputs, geometry)
    want = reference.GROUPS[name](inputs, geometry)
    assert set(got) == set(want), "same outputs as SPEC"
    for output, expected in want.items():
        value = np.broadcast_to(got[output], np.shape(expected))
        finite = np.isfinite(expected)
        assert finite.mean() > 0.99
        np.testing.assert_allclose(value[finite], expected[finite], rtol=1e-9, atol=1e-9,
                                   err_msg=f"{name} ▸ {output}")


@pytest.mark.parametrize("name", library.NAMES)
def test_sockets_follow_spec_names_and_reference_defaults(name):
    group = library.GROUPS[name]
    assert [s.name for s in group.inputs] == list(reference.INPUTS[name])
    for sock in group.inputs:
        want = np.asarray(reference.DEFAULTS[name][sock.name], dtype=float)
        got = np.atleast_1d(np.asarray(sock.default, dtype=float))[: want.size]
        np.testing.assert_allclose(got, want, err_msg=f"default of {name} ▸ {sock.name}")
        assert sock.description, f"{name} ▸ {sock.name} has a tooltip"


def test_structurally_equal_subexpressions_are_shared():
    from node_groups import expr
    a = expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Normal"))
    b = expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Normal"))
    assert a.key == b.key
    assert a.key != expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Incoming")).key


def test_fingerprint_changes_with_the_formula():
    shading = library.GROUPS["Phong Shading"]
    assert shading.fingerprint == library.GROUPS["Phong Shading"].fingerprint
    assert len({g.fingerprint for g in library.GROUPS.values()}) == len(library.GROUPS)
