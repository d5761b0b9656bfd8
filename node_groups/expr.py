# SPDX-License-Identifier: GPL-3.0-or-later
"""A small expression builder over shader math nodes.

An :class:`Expr` is a node of an expression DAG with a *kind*: ``"float"``, ``"vector"``
(colours are vectors in formulas: RGB, alpha ignored) or ``"shader"``.  Group definitions
(``library.py``) are written with Python operators and the helpers below, so each group reads
like the model's formula (docs/model.md), e.g.::

    i * maximum(dot(l, n), 0.0) * light_color * object_color

Every operation is declared once, in :data:`OPERATIONS`: its name, its operand and result
kinds, its numpy function and the Blender node that computes it (node type, Math / Vector Math
operation, sockets).  Two readers use that one table:

* :func:`evaluate`, on numpy arrays, with the semantics of Blender's nodes (safe division and
  normalisation, the Math node's power rules);
* the node writer of the add-on (``addon/loader.py``), one node per distinct sub-expression,
  constants folded into socket values.

This module never imports ``bpy``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

#: Kinds of expressions and of sockets.  COLOR is a socket kind only: in formulas a colour is a
#: vector, and a colour socket (RGBA) holds it with alpha 1.
FLOAT = "float"
VECTOR = "vector"
COLOR = "color"
SHADER = "shader"

#: The leaves of the DAG: a constant, a group input (by socket name), a Geometry node output.
LEAVES = ("const", "input", "geometry")


# -- the operation table ---------------------------------------------------------

MATH = "ShaderNodeMath"
VECTOR_MATH = "ShaderNodeVectorMath"
EMISSION = "ShaderNodeEmission"
COMBINE_XYZ = "ShaderNodeCombineXYZ"
#: Each node's operand inputs in order and its default result, by identifier (stable across
#: Blender releases, unlike positions).
_SOCKETS = {MATH: (("Value", "Value_001", "Value_002"), "Value"),
            VECTOR_MATH: (("Vector", "Vector_001", "Vector_002"), "Vector")}


@dataclass(frozen=True, eq=False)
class Op:
    """One operation: what it computes on numpy arrays and which node computes it in Blender.

    ``operands`` are the kinds of the node inputs it reads (a COLOR operand takes a vector
    expression), ``inputs`` the identifiers of those inputs on the node (by default the node's
    first inputs: ``Value``, ``Value_001``, ``Value_002`` on Math, ``Vector``, ``Vector_001``
    on Vector Math), ``output`` the identifier of the node output that carries the result,
    ``settings`` fixed input values.  Sockets are named, never numbered: Blender releases
    insert sockets before existing ones (docs/releases.md).
    """

    name: str
    kind: str
    operands: tuple
    numpy: Callable
    node: str
    operation: str | None = None
    inputs: tuple | None = None
    output: str | None = None
    settings: tuple = ()
    clamp: bool = False  # the Math node's Clamp option: the result clamped to [0, 1]
    properties: tuple = ()  # (name, value) of node properties set before its sockets

    def __post_init__(self):
        first, result = _SOCKETS.get(self.node, ((), None))
        if self.inputs is None:
            object.__setattr__(self, "inputs", first[:len(self.operands)])
        if self.output is None:
            object.__setattr__(self, "output", result)
        if not all(isinstance(key, str) for key in (*self.inputs, self.output)):
            raise ValueError(f"{self.name}: sockets are identifiers, not positions")
        if len(self.inputs) != len(self.operands):
            raise ValueError(f"{self.name}: {len(self.operands)} operands, {len(self.inputs)} inputs")

    def __repr__(self):  # the name, as formulas (and fingerprints) print it
        return self.name


def _safe_divide(a, b):
    """Math / Vector Math DIVIDE: x/0 = 0."""
    return np.where(b != 0, a / np.where(b != 0, b, 1.0), 0.0)


def _blender_pow(a, b):
    """Math node POWER: pow(0, 0) = 1, negative base with fractional exponent gives 0."""
    a, b = np.broadcast_arrays(np.asarray(a, np.float64), np.asarray(b, np.float64))
    frac = b != np.round(b)
    out = np.power(np.abs(a), b)
    out = np.where((a < 0) & frac, 0.0, np.where(a < 0, out * np.where(np.round(b) % 2, -1.0, 1.0), out))
    return out


def _less_than(a, b):
    return (a < b).astype(np.float64)


def _greater_than(a, b):
    return (np.asarray(a) > np.asarray(b)).astype(np.float64)


def _compare(a, b, epsilon):
    """Math COMPARE: 1 where |a - b| ≤ epsilon."""
    return (np.abs(np.asarray(a) - np.asarray(b)) <= np.asarray(epsilon)).astype(np.float64)


def _switch(condition, if_false, if_true):
    """Switch: *if_true* where the condition (a float linked to the boolean input converts as
    x > 0) holds, else *if_false* (vectors: per point)."""
    condition = np.asarray(condition) > 0.0
    if max(np.ndim(if_false), np.ndim(if_true)) > np.ndim(condition):
        condition = condition[..., None]
    return np.where(condition, if_true, if_false)


def _combine(x, y, z):
    x, y, z = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64),
                                  np.asarray(z, np.float64))
    return np.stack([x, y, z], axis=-1)


def _scale(v, s):
    return v * np.asarray(s)[..., None]


def _dot(a, b):
    return np.sum(a * b, axis=-1)


def _length(v):
    return np.sqrt(np.sum(v * v, axis=-1))


def _normalize(v):
    """Vector Math NORMALIZE: the zero vector stays zero."""
    n = _length(v)[..., None]
    return np.where(n != 0, v / np.where(n != 0, n, 1.0), 0.0)


def _acos(x):
    """Math ARCCOSINE: acos of x clamped to [-1, 1] (Blender's safe_acosf)."""
    return np.arccos(np.clip(x, -1.0, 1.0))


def _identity(x):
    return x


def _reflect(i, n):
    """Vector Math REFLECT: i - 2(n̂·i)n̂ with n̂ = n/‖n‖ (the normal is normalized first)."""
    unit = _normalize(n)
    return i - 2.0 * _dot(unit, i)[..., None] * unit


def _faceforward(a, incident, reference):
    """Vector Math FACEFORWARD: *a* where reference·incident < 0, else -*a*."""
    return np.where((_dot(reference, incident) < 0.0)[..., None], a, -a)


def _multiply_add(a, b, c):
    return a * b + c


def _scale_add(v, s, c):
    return v * np.asarray(s)[..., None] + c


def _no_hit(position, direction, length):
    """The Raycast node in numpy: no scene, so nothing is hit (the shadows' reference is
    ``reference.py``'s visibility against the scene's triangles)."""
    shape = np.broadcast_shapes(np.shape(position)[:-1], np.shape(direction)[:-1],
                                np.shape(length))
    return np.zeros(shape)


_FF, _VV = (FLOAT, FLOAT), (VECTOR, VECTOR)

#: Every operation of the expressions; a name may have a float and a vector form (the first
#: whose operands fit is used).
OPERATIONS = (
    Op("add", FLOAT, _FF, np.add, MATH, "ADD"),
    Op("sub", FLOAT, _FF, np.subtract, MATH, "SUBTRACT"),
    Op("mul", FLOAT, _FF, np.multiply, MATH, "MULTIPLY"),
    Op("div", FLOAT, _FF, _safe_divide, MATH, "DIVIDE"),
    Op("max", FLOAT, _FF, np.maximum, MATH, "MAXIMUM"),
    Op("min", FLOAT, _FF, np.minimum, MATH, "MINIMUM"),
    Op("pow", FLOAT, _FF, _blender_pow, MATH, "POWER"),
    Op("lt", FLOAT, _FF, _less_than, MATH, "LESS_THAN"),
    Op("gt", FLOAT, _FF, _greater_than, MATH, "GREATER_THAN"),
    Op("compare", FLOAT, (FLOAT, FLOAT, FLOAT), _compare, MATH, "COMPARE"),
    Op("cos", FLOAT, (FLOAT,), np.cos, MATH, "COSINE"),
    Op("acos", FLOAT, (FLOAT,), _acos, MATH, "ARCCOSINE"),
    Op("madd", FLOAT, (FLOAT, FLOAT, FLOAT), _multiply_add, MATH, "MULTIPLY_ADD"),
    Op("sign", FLOAT, (FLOAT,), np.sign, MATH, "SIGN"),
    Op("add", VECTOR, _VV, np.add, VECTOR_MATH, "ADD", output="Vector"),
    Op("sub", VECTOR, _VV, np.subtract, VECTOR_MATH, "SUBTRACT", output="Vector"),
    Op("mul", VECTOR, _VV, np.multiply, VECTOR_MATH, "MULTIPLY", output="Vector"),
    Op("div", VECTOR, _VV, _safe_divide, VECTOR_MATH, "DIVIDE", output="Vector"),
    Op("max", VECTOR, _VV, np.maximum, VECTOR_MATH, "MAXIMUM", output="Vector"),
    Op("min", VECTOR, _VV, np.minimum, VECTOR_MATH, "MINIMUM", output="Vector"),
    Op("scale", VECTOR, (VECTOR, FLOAT), _scale, VECTOR_MATH, "SCALE", inputs=("Vector", "Scale"),
       output="Vector"),
    Op("dot", FLOAT, _VV, _dot, VECTOR_MATH, "DOT_PRODUCT", output="Value"),
    Op("length", FLOAT, (VECTOR,), _length, VECTOR_MATH, "LENGTH", output="Value"),
    Op("normalize", VECTOR, (VECTOR,), _normalize, VECTOR_MATH, "NORMALIZE"),
    Op("reflect", VECTOR, _VV, _reflect, VECTOR_MATH, "REFLECT", output="Vector"),
    Op("faceforward", VECTOR, (VECTOR, VECTOR, VECTOR), _faceforward, VECTOR_MATH,
       "FACEFORWARD", output="Vector"),
    Op("combine", VECTOR, (FLOAT, FLOAT, FLOAT), _combine, COMBINE_XYZ, inputs=("X", "Y", "Z"),
       output="Vector"),
    Op("emission", SHADER, (COLOR,), _identity, EMISSION, inputs=("Color",), output="Emission",
       settings=(("Strength", 1.0),)),
)

#: The Switch node (float): not in OPERATIONS, whose every operand is a socket of its kind, as
#: its first input is a boolean socket (a float linked to it converts as x > 0).  Blender's
#: inliner drops the branch a constant condition leaves out (a material's Value node,
#: compared with a constant: the branch costs no node), and turns a condition that is not
#: constant into a Mix.
SWITCH = Op("switch", FLOAT, (FLOAT, FLOAT, FLOAT), _switch, "GeometryNodeSwitch",
            inputs=("Switch", "False", "True"), output="Output",
            properties=(("input_type", "FLOAT"),))

#: The Switch node on vectors: the same rules (the first form whose operands fit is used).
SWITCH_VECTOR = Op("switch", VECTOR, (FLOAT, VECTOR, VECTOR), _switch, "GeometryNodeSwitch",
                   inputs=("Switch", "False", "True"), output="Output",
                   properties=(("input_type", "VECTOR"),))

#: The Raycast node (Blender 5.1+): 1 where the ray from Position along Direction (Length in
#: units of Direction) hits a surface, else 0.  Not in OPERATIONS: numpy has no scene (it
#: evaluates as no hit), and only the lights groups' shadow rays use it.
RAYCAST = Op("raycast", FLOAT, (VECTOR, VECTOR, FLOAT), _no_hit, "ShaderNodeRaycast",
             inputs=("Position", "Direction", "Length"), output="Is Hit")

#: v·s + c in one Vector Math MULTIPLY_ADD for a float s: not in OPERATIONS, whose operands
#: are sockets of their kind, as s is linked to a vector input (it reads as (s, s, s)).
SCALE_ADD = Op("scale_add", VECTOR, (VECTOR, FLOAT, VECTOR), _scale_add, VECTOR_MATH,
               "MULTIPLY_ADD", output="Vector")

_BY_NAME: dict = {}
for _op in (*OPERATIONS, SWITCH, SWITCH_VECTOR, RAYCAST, SCALE_ADD):
    _BY_NAME.setdefault(_op.name, []).append(_op)
del _op


# -- expressions -------------------------------------------------------------------

@dataclass(eq=False)
class Expr:
    kind: str
    op: object  # an Op, or the name of a leaf (LEAVES)
    args: tuple = ()
    value: object = None  # constant value, or leaf name

    @property
    def is_leaf(self) -> bool:
        return not isinstance(self.op, Op)

    # -- arithmetic -----------------------------------------------------
    def __add__(self, other):
        return _binary("add", self, other)

    def __radd__(self, other):
        return _binary("add", other, self)

    def __sub__(self, other):
        return _binary("sub", self, other)

    def __rsub__(self, other):
        return _binary("sub", other, self)

    def __mul__(self, other):
        return _binary("mul", self, other)

    def __rmul__(self, other):
        return _binary("mul", other, self)

    def __truediv__(self, other):
        return _binary("div", self, other)

    def __rtruediv__(self, other):
        return _binary("div", other, self)

    def __neg__(self):
        return _binary("mul", self, -1.0)

    @property
    def key(self):
        """Structural identity: equal formulas give one node and one evaluation."""
        k = self.__dict__.get("_key")
        if k is None:
            k = (self.kind, self.op, self.value, tuple(a.key for a in self.args))
            self.__dict__["_key"] = k
        return k

    def __repr__(self):  # compact; also the text of the group fingerprints (library.py)
        if self.is_leaf:
            return f"{self.op}({self.value!r})"
        return f"{self.op}({', '.join(map(repr, self.args))})"


def const(value) -> Expr:
    if isinstance(value, Expr):
        return value
    if isinstance(value, (int, float)):
        return Expr(FLOAT, "const", value=float(value))
    vec = tuple(float(v) for v in value)
    if len(vec) != 3:
        raise ValueError(f"vector constants have 3 components, got {value!r}")
    return Expr(VECTOR, "const", value=vec)


def input_(name: str, kind: str) -> Expr:
    """A group input, looked up by socket name (a COLOR input is a vector in formulas)."""
    return Expr(VECTOR if kind == COLOR else kind, "input", value=name)


def geometry(name: str) -> Expr:
    """An output of Geometry node: ``Position``, ``Normal`` or ``Incoming``."""
    return Expr(VECTOR, "geometry", value=name)


def operation(name: str, *args) -> Expr:
    """The operation *name* of :data:`OPERATIONS` on *args*, in the first form they fit.

    A float constant fits a vector operand (as (c, c, c)); a float expression does not."""
    args = tuple(const(a) for a in args)
    for op in _BY_NAME[name]:
        fitted = _fit(op.operands, args)
        if fitted is not None:
            return Expr(op.kind, op, fitted)
    kinds = ", ".join(a.kind for a in args)
    raise TypeError(f"{name} has no form for ({kinds}): a float expression cannot be used "
                    f"where a vector is expected")


def _fit(operands, args):
    if len(operands) != len(args):
        return None
    fitted = []
    for kind, arg in zip(operands, args):
        want = VECTOR if kind == COLOR else kind
        if arg.kind == want:
            fitted.append(arg)
        elif want == VECTOR and arg.kind == FLOAT and arg.op == "const":
            fitted.append(const((arg.value,) * 3))
        else:
            return None
    return tuple(fitted)


def _binary(name, a, b) -> Expr:
    """Python's operators: a float times (or a vector divided by) a float is a Vector Math SCALE."""
    a, b = const(a), const(b)
    if name == "mul" and a.kind == FLOAT and b.kind == VECTOR:
        return operation("scale", b, a)
    if name == "mul" and a.kind == VECTOR and b.kind == FLOAT:
        return operation("scale", a, b)
    if name == "div" and a.kind == VECTOR and b.kind == FLOAT:
        return operation("scale", a, const(_safe_inv(b.value)) if b.op == "const" else 1.0 / b)
    return operation(name, a, b)


def _safe_inv(x):
    return 0.0 if x == 0 else 1.0 / x


# -- the helpers the formulas are written with ---------------------------------------

def maximum(a, b) -> Expr:
    return _binary("max", a, b)


def minimum(a, b) -> Expr:
    return _binary("min", a, b)


def power(base, exponent) -> Expr:
    return operation("pow", base, exponent)


def less_than(a, b) -> Expr:
    """1.0 where a < b, else 0.0."""
    return operation("lt", a, b)


def greater_than(a, b) -> Expr:
    """1.0 where a > b, else 0.0 (Math GREATER_THAN: one node)."""
    return operation("gt", a, b)


def equal(a, b, epsilon=0.0) -> Expr:
    """1.0 where |a - b| ≤ epsilon, else 0.0 (Math COMPARE)."""
    return operation("compare", a, b, epsilon)


def switch(condition, if_false, if_true) -> Expr:
    """*if_true* where *condition* > 0, else *if_false* (a Switch node: see SWITCH)."""
    return operation("switch", condition, if_false, if_true)


def raycast(origin, direction, length) -> Expr:
    """1 where the ray from *origin* along *direction* (for *length* times its length) hits
    a surface, else 0 (a Raycast node: see RAYCAST)."""
    return operation("raycast", origin, direction, length)


def sign(a) -> Expr:
    """-1, 0 or 1 as *a* is negative, zero or positive (Math SIGN)."""
    return operation("sign", a)


def scale_add(v, s, c) -> Expr:
    """v·s + c for vectors *v*, *c* and a float *s*, in one node (Vector Math MULTIPLY_ADD);
    for a constant *s*, v·s + c (its input is a vector socket)."""
    if const(s).op == "const":
        return const(v) * s + c
    return operation("scale_add", v, s, c)


def combine(x, y, z) -> Expr:
    """The vector (x, y, z) of three floats (Combine XYZ)."""
    return operation("combine", x, y, z)


def at_least(a, b) -> Expr:
    """1.0 where a >= b, else 0.0 (the non-strict conditions, docs/contract.md "Edge cases")."""
    return 1.0 - less_than(a, b)


def cos(a) -> Expr:
    return operation("cos", a)


def acos(a) -> Expr:
    """The angle whose cosine is *a* (clamped to [-1, 1] first), in radians."""
    return operation("acos", a)


def dot(a, b) -> Expr:
    return operation("dot", a, b)


def length(a) -> Expr:
    return operation("length", a)


def normalize(a) -> Expr:
    """a/|a|; the zero vector stays zero (Blender's safe normalize)."""
    return operation("normalize", a)


def multiply_add(a, b, c) -> Expr:
    """a·b + c in one node (Math MULTIPLY_ADD)."""
    return operation("madd", a, b, c)


def reflect_about(i, n) -> Expr:
    """i - 2(n̂·i)n̂, n̂ = n/‖n‖ (Vector Math REFLECT): the mirror image of i about the plane
    of normal n, so that -reflect_about(ℓ, n) = 2(ℓ·n)n - ℓ for a unit n."""
    return operation("reflect", i, n)


def faceforward(a, incident, reference) -> Expr:
    """*a* where reference·incident < 0, else -*a*, in one node (Vector Math FACEFORWARD):
    a vector turned to one side of a surface by the sign of a dot product."""
    return operation("faceforward", a, incident, reference)


_CLAMPED: dict = {}


def _clamped(op: Op) -> Op:
    """*op* with the Math node's Clamp option: its result clamped to [0, 1]."""
    if op.name not in _CLAMPED:
        def numpy(*args, _f=op.numpy):
            return np.clip(_f(*args), 0.0, 1.0)
        _CLAMPED[op.name] = Op(f"{op.name}_clamp", op.kind, op.operands, numpy, op.node,
                               op.operation, op.inputs, op.output, op.settings, clamp=True)
    return _CLAMPED[op.name]


def saturate(x) -> Expr:
    """clamp(x, 0, 1) = min(max(x, 0), 1).  For a float computed by a Math node, the same
    node with its Clamp option (one node instead of three)."""
    x = const(x)
    if x.kind == FLOAT and not x.is_leaf and x.op.node == MATH and not x.op.clamp:
        return Expr(FLOAT, _clamped(x.op), x.args)
    return minimum(maximum(x, 0.0), 1.0)


def select(mask, if_one, if_zero) -> Expr:
    """mask·a + (1-mask)·b for a mask that is exactly 0 or 1."""
    return mask * if_one + (1.0 - mask) * if_zero


def emission(color) -> Expr:
    return operation("emission", color)


# -- numpy evaluation ----------------------------------------------------------------

def _leaf_value(expr: Expr, inputs: dict, geometry_values: dict):
    if expr.op == "const":
        return np.asarray(expr.value, dtype=np.float64)
    if expr.op == "input":
        out = np.asarray(inputs[expr.value], dtype=np.float64)
        return out[..., :3] if expr.kind == VECTOR else out
    return np.asarray(geometry_values[expr.value], dtype=np.float64)[..., :3]


def evaluate(expr: Expr, inputs: dict, geometry_values: dict | None = None, _memo=None):
    """Evaluate *expr* on numpy arrays.

    ``inputs`` maps group input names to arrays (vectors ``(..., 3)``, floats
    ``(...)``); ``geometry_values`` maps ``Position``/``Normal``/``Incoming``.
    Computed in float64 with the node semantics (safe divide / normalize,
    Blender's power rules for negative bases).  A shader evaluates to its colour.
    """
    memo = {} if _memo is None else _memo
    key = expr.key
    if key in memo:
        return memo[key]
    if expr.is_leaf:
        out = _leaf_value(expr, inputs, geometry_values)
    else:
        args = [evaluate(a, inputs, geometry_values, memo) for a in expr.args]
        with np.errstate(all="ignore"):
            out = expr.op.numpy(*args)
    memo[key] = out
    return out


__all__ = [
    "Expr", "Op", "OPERATIONS", "FLOAT", "VECTOR", "COLOR", "SHADER", "LEAVES", "const",
    "input_", "geometry", "operation", "maximum", "minimum", "power", "less_than", "at_least", "cos",
    "greater_than", "combine", "equal", "switch", "SWITCH", "SWITCH_VECTOR", "raycast", "RAYCAST", "sign",
    "scale_add", "SCALE_ADD",
    "acos",
    "dot", "length", "normalize", "select", "emission", "evaluate", "multiply_add",
    "reflect_about", "saturate", "faceforward",
]
