# SPDX-License-Identifier: GPL-3.0-or-later
"""A small expression builder over shader math nodes.

An :class:`Expr` is a node of an expression DAG with a *kind*: ``"float"`` or
``"vector"`` (colours are vectors: RGB, alpha ignored).  The same DAG can

* be **evaluated on numpy arrays** (:func:`evaluate`) with the semantics of
  Blender's Math / Vector Math nodes (safe division and normalisation), and
* be **written as nodes and links** into a node tree (:func:`build`), one node
  per distinct sub-expression, constants folded into socket values.

Group definitions (``library.py``) are written with Python operators and the
helpers below, so each group reads like the seed formula, e.g.::

    i * maximum(dot(l, n), 0.0) * light_color * object_color

This module never imports ``bpy``: :func:`build` only calls methods on the
node tree it is given.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

FLOAT = "float"
VECTOR = "vector"
SHADER = "shader"


@dataclass(eq=False)
class Expr:
    kind: str
    op: str
    args: tuple = ()
    value: object = None  # constant value, or leaf name

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

    def __repr__(self):  # compact, for debugging
        if self.op in ("const", "input", "geometry"):
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
    """A group input, looked up by socket name."""
    return Expr(kind, "input", value=name)


def geometry(name: str) -> Expr:
    """An output of Geometry node: ``Position``, ``Normal`` or ``Incoming``."""
    return Expr(VECTOR, "geometry", value=name)


# -- operations ----------------------------------------------------------

def _binary(op, a, b) -> Expr:
    a, b = const(a), const(b)
    if a.kind == FLOAT and b.kind == FLOAT:
        return Expr(FLOAT, op, (a, b))
    if op == "mul" and a.kind == FLOAT:  # scalar * vector
        return Expr(VECTOR, "scale", (b, a))
    if op == "mul" and b.kind == FLOAT:
        return Expr(VECTOR, "scale", (a, b))
    if op == "div" and b.kind == FLOAT:
        return Expr(VECTOR, "scale", (a, 1.0 / b if b.op != "const" else const(_safe_inv(b.value))))
    return Expr(VECTOR, op, (_as_vector(a), _as_vector(b)))


def _safe_inv(x):
    return 0.0 if x == 0 else 1.0 / x


def _as_vector(e: Expr) -> Expr:
    if e.kind == VECTOR:
        return e
    if e.op == "const":
        return const((e.value,) * 3)
    raise TypeError("a float expression cannot be used where a vector is expected")


def maximum(a, b) -> Expr:
    return _binary("max", a, b)


def minimum(a, b) -> Expr:
    return _binary("min", a, b)


def power(base, exponent) -> Expr:
    return Expr(FLOAT, "pow", (_float(base), _float(exponent)))


def less_than(a, b) -> Expr:
    """1.0 where a < b, else 0.0."""
    return Expr(FLOAT, "lt", (_float(a), _float(b)))


def at_least(a, b) -> Expr:
    """1.0 where a >= b, else 0.0 (the seeds' non-strict conditions)."""
    return 1.0 - less_than(a, b)


def cos(a) -> Expr:
    return Expr(FLOAT, "cos", (_float(a),))


def dot(a, b) -> Expr:
    return Expr(FLOAT, "dot", (_vector(a), _vector(b)))


def length(a) -> Expr:
    return Expr(FLOAT, "length", (_vector(a),))


def normalize(a) -> Expr:
    """a/|a|; the zero vector stays zero (Blender's safe normalize)."""
    return Expr(VECTOR, "normalize", (_vector(a),))


def select(mask, if_one, if_zero) -> Expr:
    """mask·a + (1-mask)·b for a mask that is exactly 0 or 1."""
    return mask * if_one + (1.0 - mask) * if_zero


def emission(color) -> Expr:
    return Expr(SHADER, "emission", (_vector(color),))


def _float(a) -> Expr:
    a = const(a)
    if a.kind != FLOAT:
        raise TypeError(f"expected a float expression, got {a.kind}")
    return a


def _vector(a) -> Expr:
    return _as_vector(const(a))


# -- numpy evaluation ----------------------------------------------------

def evaluate(expr: Expr, inputs: dict, geometry_values: dict | None = None, _memo=None):
    """Evaluate *expr* on numpy arrays.

    ``inputs`` maps group input names to arrays (vectors ``(..., 3)``, floats
    ``(...)``); ``geometry_values`` maps ``Position``/``Normal``/``Incoming``.
    Computed in float64 with the node semantics (safe divide / normalize,
    Blender's power rules for negative bases).
    """
    memo = {} if _memo is None else _memo
    key = expr.key
    if key in memo:
        return memo[key]
    args = [evaluate(a, inputs, geometry_values, memo) for a in expr.args]
    op = expr.op
    with np.errstate(all="ignore"):
        if op == "const":
            out = np.asarray(expr.value, dtype=np.float64)
        elif op == "input":
            out = np.asarray(inputs[expr.value], dtype=np.float64)
            if expr.kind == VECTOR:
                out = out[..., :3]
        elif op == "geometry":
            out = np.asarray(geometry_values[expr.value], dtype=np.float64)[..., :3]
        elif op == "add":
            out = args[0] + args[1]
        elif op == "sub":
            out = args[0] - args[1]
        elif op == "mul":
            out = args[0] * args[1]
        elif op == "div":
            b = args[1]
            out = np.where(b != 0, args[0] / np.where(b != 0, b, 1.0), 0.0)
        elif op == "scale":
            out = args[0] * np.asarray(args[1])[..., None]
        elif op == "max":
            out = np.maximum(args[0], args[1])
        elif op == "min":
            out = np.minimum(args[0], args[1])
        elif op == "pow":
            out = _blender_pow(args[0], args[1])
        elif op == "lt":
            out = (args[0] < args[1]).astype(np.float64)
        elif op == "cos":
            out = np.cos(args[0])
        elif op == "dot":
            out = np.sum(args[0] * args[1], axis=-1)
        elif op == "length":
            out = np.sqrt(np.sum(args[0] * args[0], axis=-1))
        elif op == "normalize":
            n = np.sqrt(np.sum(args[0] * args[0], axis=-1))[..., None]
            out = np.where(n != 0, args[0] / np.where(n != 0, n, 1.0), 0.0)
        elif op == "emission":
            out = args[0]
        else:  # pragma: no cover - every op above is covered
            raise ValueError(f"unknown op {op}")
    memo[key] = out
    return out


def _blender_pow(a, b):
    """Math node POWER: pow(0, 0) = 1, negative base with fractional exponent gives 0."""
    a, b = np.broadcast_arrays(np.asarray(a, np.float64), np.asarray(b, np.float64))
    frac = b != np.round(b)
    out = np.power(np.abs(a), b)
    out = np.where((a < 0) & frac, 0.0, np.where(a < 0, out * np.where(np.round(b) % 2, -1.0, 1.0), out))
    return out


# -- node building ---------------------------------------------------------

_MATH = {"add": "ADD", "sub": "SUBTRACT", "mul": "MULTIPLY", "div": "DIVIDE",
         "max": "MAXIMUM", "min": "MINIMUM", "pow": "POWER", "lt": "LESS_THAN", "cos": "COSINE"}
_VMATH = {"add": "ADD", "sub": "SUBTRACT", "mul": "MULTIPLY", "div": "DIVIDE",
          "max": "MAXIMUM", "min": "MINIMUM", "scale": "SCALE", "dot": "DOT_PRODUCT",
          "length": "LENGTH", "normalize": "NORMALIZE"}
# Vector Math outputs "Value" for these operations, "Vector" otherwise.
_VMATH_FLOAT_OUT = {"dot", "length"}


@dataclass
class _Builder:
    tree: object
    group_input: object
    memo: dict = field(default_factory=dict)
    depth: dict = field(default_factory=dict)
    geometry_node: object = None

    def socket(self, expr: Expr):
        """The output socket computing *expr* (None for constants)."""
        if expr.op == "const":
            return None
        key = expr.key
        if key in self.memo:
            return self.memo[key]
        if expr.op == "input":
            sock = self.group_input.outputs[expr.value]
            self.depth[key] = 0
        elif expr.op == "geometry":
            if self.geometry_node is None:
                self.geometry_node = self.tree.nodes.new("ShaderNodeNewGeometry")
                self.geometry_node.location = (0, 300)
            sock = self.geometry_node.outputs[expr.value]
            self.depth[key] = 0
        else:
            sock = self._operation(expr)
        self.memo[key] = sock
        return sock

    def _operation(self, expr: Expr):
        nodes, links = self.tree.nodes, self.tree.links
        if expr.op == "emission":
            node = nodes.new("ShaderNodeEmission")
            node.inputs["Strength"].default_value = 1.0
            targets = [node.inputs["Color"]]
            out = node.outputs["Emission"]
        elif expr.kind == FLOAT and expr.op in _MATH:
            node = nodes.new("ShaderNodeMath")
            node.operation = _MATH[expr.op]
            targets = list(node.inputs)[: len(expr.args)]
            out = node.outputs[0]
        else:
            node = nodes.new("ShaderNodeVectorMath")
            node.operation = _VMATH[expr.op]
            if expr.op == "scale":
                targets = [node.inputs[0], node.inputs["Scale"]]
            else:
                targets = list(node.inputs)[: len(expr.args)]
            out = node.outputs["Value" if expr.op in _VMATH_FLOAT_OUT else "Vector"]
        depth = 0
        for arg, target in zip(expr.args, targets):
            src = self.socket(arg)
            if src is None:
                value = arg.value
                if target.type in ("RGBA",):
                    value = (*value, 1.0)
                target.default_value = value
            else:
                links.new(src, target)
                depth = max(depth, self.depth.get(arg.key, 0))
        self.depth[expr.key] = depth + 1
        node.location = (200 * (depth + 1), 0)
        return out


def build(tree, outputs: dict, group_input, group_output) -> None:
    """Write the expressions in *outputs* (output socket name -> Expr) into *tree*."""
    b = _Builder(tree, group_input)
    max_depth = 0
    for name, expr in outputs.items():
        src = b.socket(expr)
        target = group_output.inputs[name]
        if src is None:
            value = expr.value
            target.default_value = (*value, 1.0) if target.type == "RGBA" else value
        else:
            tree.links.new(src, target)
        max_depth = max(max_depth, b.depth.get(expr.key, 0))
    _arrange(tree, b, group_input, group_output, max_depth)


def _arrange(tree, builder, group_input, group_output, max_depth):
    """Columns by depth so the graph reads left to right."""
    columns: dict = {}
    for key, sock in builder.memo.items():
        node = sock.node
        if node in (group_input, builder.geometry_node):
            continue
        col = int(round(node.location[0] / 200))
        columns.setdefault(col, [])
        if node not in columns[col]:
            columns[col].append(node)
    for col, nodes in columns.items():
        for row, node in enumerate(nodes):
            node.location = (col * 220, -row * 180)
    group_input.location = (-300, 0)
    if builder.geometry_node is not None:
        builder.geometry_node.location = (-300, 400)
    group_output.location = ((max_depth + 1) * 220 + 80, 0)


__all__ = [
    "Expr", "FLOAT", "VECTOR", "SHADER", "const", "input_", "geometry", "maximum", "minimum",
    "power", "less_than", "at_least", "cos", "dot", "length", "normalize", "select", "emission",
    "evaluate", "build",
]
