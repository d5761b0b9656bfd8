# SPDX-License-Identifier: GPL-3.0-or-later
"""The whole lighting model of a material as one expression, for Per Vertex and Per Face
shading (docs/shading_modes.md).

Per Pixel materials compute the model in the shader, with the scene's lights group
(``addon/lighting/rig.py``): group nodes of the library (``library.py``) wired together.  Per
Vertex and Per Face materials compute the same model once per vertex or per face, in a
Geometry Nodes modifier; this module composes that model from the library's own group
expressions (so both modes compute exactly what the groups compute), as one expression DAG
whose leaves are named inputs:

* the material's controls: ``Object Color``, ``Specular Color``, ``Exponent``, ``Blinn``,
  ``Irradiant Color``, ``Ambient Object Color``, ``Specular Strength``;
* the ambient light: ``Ambient Intensity``, ``Ambient Color``;
* per light *k* (0, 1, ...): ``light<k>:<input of its light group>`` (``Position``,
  ``Direction``, ``Intensity``, ``Quadratic`` ... ``Half Angle``, ``Edge Exponent``; three.js:
  ``Distance``, ``Decay``, ``Angle``, ``Penumbra``), ``light<k>:Color`` and, in the seeds'
  model, ``light<k>:Diffuse`` / ``light<k>:Specular`` (the light's strengths);
* the geometry: ``P`` (the world position), ``N`` (the world normal, not yet normalized) and
  ``Camera`` (the camera's world position): the groups' Geometry ▸ Position / Normal /
  Incoming become P, normalize(N) and normalize(Camera - P).

The composition is what the lights group (rig.py) computes, written as docs/contract.md
("Several lights") defines it: the ambient, then per light its light group and a Phong
Shading (ambient off, the irradiant on the first only), added with Phong Color Add; in the
three.js model the three.js groups and the irradiant (emissive) added as is.
Constants are folded and trivial operations (x·1, x+0) dropped, so the written nodes are
only those that compute something.

No ``bpy`` here.
"""

from __future__ import annotations

import numpy as np

from .expr import FLOAT, SHADER, VECTOR, Expr, evaluate, input_, minimum, normalize
from . import models
from .library import BLACK, GROUPS, WHITE, ZERO, clamp_add, definition

#: The values of ``material["phong_shading"]`` (docs/contract.md), the default first.
MODES = ("PIXEL", "VERTEX", "FACE")
#: The lighting models (``models.py``, the one table of them), the default first.
MODELS = models.NAMES

#: The material's controls: name -> kind (a colour is a vector in formulas).
CONTROLS = {"Object Color": VECTOR, "Specular Color": VECTOR, "Exponent": FLOAT,
            "Blinn": FLOAT, "Irradiant Color": VECTOR, "Ambient Object Color": VECTOR,
            "Specular Strength": FLOAT}
AMBIENT = {"Ambient Intensity": FLOAT, "Ambient Color": VECTOR}
GEOMETRY = {"P": VECTOR, "N": VECTOR, "Camera": VECTOR}


def light_input(index: int, name: str) -> str:
    """The leaf name of input *name* of light *index*."""
    return f"light{index}:{name}"


def _input(name, kind):
    return input_(name, kind)


# -- substitution with folding ----------------------------------------------------------

def _is_const(e: Expr, value=None) -> bool:
    if e.op != "const":
        return False
    if value is None:
        return True
    return bool(np.all(np.asarray(e.value, dtype=np.float64) == value))


def _const_of(kind, value) -> Expr:
    array = np.asarray(value, dtype=np.float64)
    if kind == FLOAT:
        return Expr(FLOAT, "const", value=float(array))
    return Expr(VECTOR, "const", value=tuple(float(v) for v in np.broadcast_to(array, (3,))))


def _simplify(e: Expr) -> Expr:
    """*e* with constant operands folded and x·1, x+0, x-0, x·0 dropped."""
    if e.is_leaf or e.kind == SHADER:
        return e
    args = e.args
    if all(_is_const(a) for a in args):
        with np.errstate(all="ignore"):
            return _const_of(e.kind, evaluate(e, {}, {}))
    name = e.op.name
    if name in ("mul", "scale"):
        a, b = args
        if _is_const(b, 1.0) and a.kind == e.kind:
            return a
        if _is_const(a, 1.0) and b.kind == e.kind:
            return b
        if _is_const(a, 0.0) or _is_const(b, 0.0):
            return _const_of(e.kind, 0.0)
    if name == "add":
        a, b = args
        if _is_const(b, 0.0):
            return a
        if _is_const(a, 0.0):
            return b
    if name == "sub" and _is_const(args[1], 0.0):
        return args[0]
    return e


def substitute(expr: Expr, inputs: dict, geometry_values: dict | None = None,
               _memo: dict | None = None) -> Expr:
    """*expr* with its group inputs replaced by the expressions *inputs* (name -> Expr or
    constant) and its Geometry outputs by *geometry_values*; constants folded."""
    memo = {} if _memo is None else _memo
    key = expr.key
    if key in memo:
        return memo[key]
    if expr.op == "input" and expr.value in inputs:
        value = inputs[expr.value]
        out = value if isinstance(value, Expr) else _const_of(expr.kind, value)
    elif expr.op == "geometry" and geometry_values and expr.value in geometry_values:
        out = geometry_values[expr.value]
    elif expr.is_leaf:
        out = expr
    else:
        args = tuple(substitute(a, inputs, geometry_values, memo) for a in expr.args)
        out = _simplify(Expr(expr.kind, expr.op, args))
    memo[key] = out
    return out


def _group(name: str, output: str, inputs: dict, geometry_values: dict) -> Expr:
    """Output *output* of the library group *name* (or a lights-group part) with *inputs*
    (defaults for the rest)."""
    group = definition(name)
    values = {s.name: s.default for s in group.inputs}
    values.update(inputs)
    values = {k: (v[:3] if isinstance(v, tuple) and len(v) == 4 else v) for k, v in values.items()}
    return substitute(group.expressions[output], values, geometry_values)


# -- the model ---------------------------------------------------------------------------

def world_geometry() -> dict:
    """The groups' Geometry outputs in terms of the leaves P, N and Camera."""
    p = _input("P", VECTOR)
    return {"Position": p, "Normal": normalize(_input("N", VECTOR)),
            "Incoming": normalize(_input("Camera", VECTOR) - p)}


def light_group_inputs(index: int, group_name: str) -> dict:
    """Every input of the light group *group_name* as the leaf of light *index*."""
    return {s.name: _input(light_input(index, s.name), s.kind) for s in GROUPS[group_name].inputs}


def model_color(light_types, model: str = models.DEFAULT, power=()) -> Expr:
    """The clamped colour of the whole model for lights of *light_types* (``POINT``,
    ``SUN``, ``SPOT``, in the order of the lights group), one vector expression, composed as
    the model's ``composition`` (``models.COMPOSITIONS``) says.  The lights whose indices
    are in *power* fall off as i0/d^k (a model that reads the falloff, as the rig builds
    them: the light group without falloff, then a Phong Power Falloff of its Distance, k the
    leaf ``light<k>:Power K``)."""
    if model not in models.MODELS:
        raise ValueError(f"unknown lighting model {model!r}: expected one of "
                         f"{tuple(models.MODELS)}")
    spec = models.MODELS[model]
    geo = world_geometry()
    controls = {name: _input(name, kind) for name, kind in {**CONTROLS, **AMBIENT}.items()}
    return COMPOSE[spec.composition](spec, light_types, geo, controls, power)


def _summed_color(spec, light_types, geo, controls, power) -> Expr:
    """The compositions "phong" and "chain": the ambient, then per light its light group and
    a Phong Shading (ambient off, the irradiant on the first only), or a three.js Phong (the
    irradiant, three.js's emissive, added as is), added with Phong Color Add."""
    chain = spec.composition == "chain"
    normal_view = {"Normal": ZERO, "View Vector": ZERO}
    if chain:
        color = _group("three.js Ambient", "Color", {
            "Intensity": controls["Ambient Intensity"], "Light Color": controls["Ambient Color"],
            "Diffuse Color": controls["Ambient Object Color"]}, geo)
        parts = [controls["Irradiant Color"]]
    else:
        color = _group("Phong Ambient", "Color", {
            "Intensity": controls["Ambient Intensity"], "Light Color": controls["Ambient Color"],
            "Object Color": controls["Ambient Object Color"]}, geo)
        parts = []
    for index, light_type in enumerate(light_types):
        group_name = spec.light_groups[light_type]
        light = light_group_inputs(index, group_name)
        is_power = spec.power_falloff and index in power and light_type in ("POINT", "SPOT")
        if is_power:  # no falloff in the light group: α = β = 0, γ = 1
            light.update({"Quadratic": 0.0, "Linear": 0.0, "Constant": 1.0})
        vector = _group(group_name, "Light Vector", light, geo)
        intensity = _group(group_name, "Intensity", light, geo)
        if is_power:
            intensity = _group("Phong Power Falloff", "Intensity", {
                "Intensity": intensity, "Distance": _group(group_name, "Distance", light, geo),
                "Exponent": _input(light_input(index, "Power K"), FLOAT)}, geo)
        light_color = _input(light_input(index, "Color"), VECTOR)
        if chain:
            parts.append(_group("three.js Phong", "Color", {
                "Light Vector": vector, "Intensity": intensity, "Light Color": light_color,
                "Diffuse Color": controls["Object Color"],
                "Specular Color": controls["Specular Color"], "Shininess": controls["Exponent"],
                "Specular Strength": controls["Specular Strength"], **normal_view}, geo))
            continue
        parts.append(_group("Phong Shading", "Color", {
            "Light Vector": vector, "Light Intensity": intensity, "Light Color": light_color,
            "Object Color": controls["Object Color"],
            "Irradiant Color": controls["Irradiant Color"] if index == 0 else BLACK,
            "Ambient Intensity": 0.0, "Ambient Color": WHITE,
            "Diffuse Strength": _input(light_input(index, "Diffuse"), FLOAT),
            "Specular Strength": _input(light_input(index, "Specular"), FLOAT),
            "Specular Color": controls["Specular Color"], "Exponent": controls["Exponent"],
            "Blinn": controls["Blinn"], **normal_view}, geo))
    if not chain and not light_types:  # no light: the irradiant alone
        parts.append(_group("Phong Shading", "Color", {
            "Light Intensity": 0.0, "Object Color": controls["Object Color"],
            "Irradiant Color": controls["Irradiant Color"], "Ambient Intensity": 0.0,
            **normal_view}, geo))
    memo: dict = {}
    for part in parts:
        color = substitute(clamp_add(color, part), {}, None, memo)
    return color


def _light_ambient_color(spec, light_types, geo, controls, _power=()) -> Expr:
    """The composition "phong_light_ambient" (the X3D / VRML97 model) as rig.py builds it:
    per light an X3D light group and an X3D Light Terms (the unit normal and view vector of
    the point); the sums times the material's colours, the World's ambient light added, min(…, 1)."""
    unit = {"Normal": geo["Normal"], "View Vector": geo["Incoming"]}
    ambient = _group("Phong Ambient", "Color", {
        "Intensity": controls["Ambient Intensity"], "Light Color": controls["Ambient Color"],
        "Object Color": controls["Ambient Object Color"]}, geo)
    sums = {"Diffuse Light": None, "Specular Light": None, "Ambient Light": None}
    for index, light_type in enumerate(light_types):
        group_name = spec.light_groups[light_type]
        light = light_group_inputs(index, group_name)
        terms = {"Light Vector": _group(group_name, "Light Vector", light, geo),
                 "Intensity": _group(group_name, "Intensity", light, geo),
                 "Ambient": _group(group_name, "Ambient", light, geo),
                 "Light Color": _input(light_input(index, "Color"), VECTOR),
                 "Exponent": controls["Exponent"], **unit}
        for output in sums:
            part = _group("X3D Light Terms", output, terms, geo)
            sums[output] = part if sums[output] is None else sums[output] + part
    color = controls["Irradiant Color"] + ambient
    for output, material_color in (("Ambient Light", "Ambient Object Color"),
                                   ("Diffuse Light", "Object Color"),
                                   ("Specular Light", "Specular Color")):
        if sums[output] is not None:
            color = color + sums[output] * controls[material_color]
    return substitute(minimum(color, 1.0), {}, None, {})


#: composition (``models.COMPOSITIONS``) -> function(model, light types, geometry, controls,
#: power) -> the colour expression.
COMPOSE = {"phong": _summed_color, "chain": _summed_color,
           "phong_light_ambient": _light_ambient_color}


def leaves(expression: Expr) -> set:
    """The names of the input leaves *expression* reads."""
    found, seen, todo = set(), set(), [expression]
    while todo:
        e = todo.pop()
        if id(e) in seen:
            continue
        seen.add(id(e))
        if e.op == "input":
            found.add(e.value)
        todo.extend(e.args)
    return found


def count_operations(expression: Expr) -> int:
    """How many distinct operations (nodes) *expression* needs."""
    keys, todo = set(), [expression]
    while todo:
        e = todo.pop()
        if e.is_leaf or e.key in keys:
            continue
        keys.add(e.key)
        todo.extend(e.args)
    return len(keys)


__all__ = ["MODES", "MODELS", "CONTROLS", "AMBIENT", "GEOMETRY", "light_input",
           "substitute", "world_geometry", "model_color", "leaves", "count_operations"]
