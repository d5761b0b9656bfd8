# SPDX-License-Identifier: GPL-3.0-or-later
"""The group definitions (node_groups/library.py), evaluated on numpy by the expression
builder, agree with the independent reference on random and degenerate inputs.

No Blender here: this catches a wrong formula in seconds; the render tests then check
that Blender's nodes compute what the definitions say.
"""

import numpy as np
import pytest

from phong_nodes.node_groups import library, reference

import seeded

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
    rng = seeded.rng(name)
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
    from phong_nodes.node_groups import expr
    a = expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Normal"))
    b = expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Normal"))
    assert a.key == b.key
    assert a.key != expr.dot(expr.input_("L", expr.VECTOR), expr.geometry("Incoming")).key


def test_fingerprint_changes_with_the_formula():
    shading = library.GROUPS["Phong Shading"]
    assert shading.fingerprint == library.GROUPS["Phong Shading"].fingerprint
    assert len({g.fingerprint for g in library.GROUPS.values()}) == len(library.GROUPS)


def test_colour_is_declared_on_the_socket_not_taken_from_its_name():
    from phong_nodes.node_groups import expr
    g = library.GroupDef("Test", "")
    v = g.vector("V", (0.0, 0.0, 0.0), "a vector")
    c = g.color("C", (1.0, 1.0, 1.0), "a colour")
    assert c.kind == expr.VECTOR, "in formulas a colour is a vector"
    g.output("Color", v, "named like a colour, declared a vector")
    g.output("Tint", c * v, "declared a colour", color=True)
    assert [s.kind for s in g.inputs] == [expr.VECTOR, expr.COLOR]
    assert [s.socket_type for s in g.outputs] == ["NodeSocketVector", "NodeSocketColor"]
    with pytest.raises(TypeError):
        g.output("Length", expr.length(v), color=True)
    colours = {(name, s.name) for name, d in library.GROUPS.items() for s in d.outputs
               if s.kind == expr.COLOR}
    assert ("Phong Shading", "Specular") in colours and ("Phong Point Light", "Light Vector") not in colours


def test_every_operation_gives_the_shape_of_its_declared_kind():
    from phong_nodes.node_groups import expr
    shapes = {expr.FLOAT: (5,), expr.VECTOR: (5, 3), expr.COLOR: (5, 3), expr.SHADER: (5, 3)}
    rng = np.random.default_rng(1)
    for op in expr.OPERATIONS:
        args = [rng.uniform(-2, 2, shapes[kind]) for kind in op.operands]
        with np.errstate(all="ignore"):
            out = op.numpy(*args)
        assert np.shape(out) == shapes[op.kind], f"{op.name} ({', '.join(op.operands)})"
        assert len(op.inputs) == len(op.operands)


def test_a_clamped_math_node_is_one_node_and_clamps():
    """saturate(x) of a float Math operation is that operation with the Clamp option (one
    node); of anything else, min(max(x, 0), 1)."""
    from phong_nodes.node_groups import expr

    a, b = expr.input_("a", expr.FLOAT), expr.input_("b", expr.FLOAT)
    clamped = expr.saturate(a - b)
    assert clamped.op.clamp and clamped.op.operation == "SUBTRACT"
    x = np.array([-2.0, 0.25, 3.0])
    np.testing.assert_array_equal(expr.evaluate(clamped, {"a": x, "b": np.zeros(3)}),
                                  [0.0, 0.25, 1.0])
    v = expr.input_("v", expr.VECTOR)
    other = expr.saturate(expr.dot(v, v))  # a Vector Math node: no Clamp option
    assert not other.op.clamp and other.op.name == "min"
