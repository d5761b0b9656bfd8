# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene of the Phong material tests and its helpers (shared by test_materials and
test_lighting): one Point (with a Limit Location constraint), one Sun (parented to a rotated
Empty) and one Spot light over a plane and a sphere; probe AOVs, renders, the numpy
reference of the material recipe and checks of the lights group's drivers."""

from __future__ import annotations

import math
import time

import numpy as np

import blender_env as be
from blender_env import report

CY_TOL = 1e-4
SIZE = 32
TERMS = ("Irradiant", "Ambient", "Diffuse", "Specular")
AOVS = (("P", "COLOR"), ("N", "COLOR"), ("I", "COLOR"), ("id", "VALUE"))
PLANE, SPHERE = "Phong Material", "Phong Old Principled"
SPHERE_COLOR = (0.2, 0.5, 0.8, 1.0)


def _ref():
    from phong_nodes.node_groups import reference  # noqa: PLC0415

    return reference


# -- scene ----------------------------------------------------------------------

def _light(bpy, scene, name, kind, location, rotation=(0.0, 0.0, 0.0)):
    data = bpy.data.lights.new(name, kind)
    data.use_shadow = False  # these scenes test the model without shadows (issue 43)
    data.phong.intensity = 1.0  # the seeds' i0 of its own, not its watts' (tests may set it)
    obj = bpy.data.objects.new(name, data)
    scene.collection.objects.link(obj)
    obj.location = location
    obj.rotation_euler = rotation
    return obj


def _add_probe_aovs(bpy, material, ident):
    """AOV outputs P / N / I (Geometry) and id (a constant) in *material*."""
    tree = material.node_tree
    geo = tree.nodes.new("ShaderNodeNewGeometry")
    geo.location = (500.0, -500.0)
    for index, (aov_name, socket) in enumerate((("P", "Position"), ("N", "Normal"),
                                                ("I", "Incoming"))):
        aov = tree.nodes.new("ShaderNodeOutputAOV")
        aov.aov_name = aov_name
        aov.location = (800.0, -400.0 - 120.0 * index)
        tree.links.new(geo.outputs[socket], aov.inputs["Color"])
    value = tree.nodes.new("ShaderNodeValue")
    value.outputs[0].default_value = float(ident)
    aov = tree.nodes.new("ShaderNodeOutputAOV")
    aov.aov_name = "id"
    aov.location = (800.0, -800.0)
    tree.links.new(value.outputs[0], aov.inputs["Value"])


def build_scene(bpy, kind="cycles"):
    scene = be.new_scene("Phong lights", SIZE, SIZE, kind)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.08
    scene.world.phong.ambient_color = (1.0, 0.9, 0.8)
    for name, aov_kind in AOVS:
        be.add_aov(scene, name, aov_kind)
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    be.add_ortho_camera(scene, (0.0, 0.0), 4.0, 4.0)

    plane = be.add_quad(scene, "Plane", -3, -3, 3, 3)
    # The sphere had a Principled material: its base colour becomes the Object Color.
    old = bpy.data.materials.new("Old Principled")
    be.compat().new_material_tree(old)
    old.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = SPHERE_COLOR
    sphere = be.add_uv_sphere(scene, "Sphere", (0.3, 0.2, 0.6), 1.1, old, segments=32, rings=16)

    point = _light(bpy, scene, "Point", "POINT", (1.2, -0.9, 2.6))
    limit = point.constraints.new("LIMIT_LOCATION")  # world z becomes 1.8
    limit.use_max_z, limit.max_z = True, 1.8
    point.data.color = (1.0, 0.8, 0.6)
    point.data.phong.intensity = 1.2
    point.data.phong.quadratic, point.data.phong.linear, point.data.phong.constant = 0.6, 0.2, 0.1

    pivot = bpy.data.objects.new("Pivot", None)
    scene.collection.objects.link(pivot)
    pivot.location = (2.0, 1.0, 3.0)
    pivot.rotation_euler = (0.5, -0.3, 0.8)
    sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 1.0), (-0.3, 0.2, 0.1))
    sun.parent = pivot
    sun.data.color = (0.6, 0.7, 1.0)
    sun.data.phong.intensity = 0.35
    sun.data.phong.specular = 0.6

    spot = _light(bpy, scene, "Spot", "SPOT", (-1.4, 0.8, 3.0), (0.35, -0.25, 0.4))
    spot.data.color = (1.0, 1.0, 0.5)
    spot.data.spot_size = math.radians(70.0)
    spot.data.phong.intensity = 3.0
    spot.data.phong.edge_exponent = 2.0
    spot.data.phong.diffuse = 0.9

    for obj in scene.objects:
        obj.select_set(obj in (plane, sphere))
    bpy.context.view_layer.objects.active = sphere
    return scene, plane, sphere, (point, sun, spot)


def _finish_materials(bpy, plane, sphere):
    """Test probes, and non-default controls on the sphere."""
    _add_probe_aovs(bpy, plane.active_material, 1)
    _add_probe_aovs(bpy, sphere.active_material, 2)
    tree = sphere.active_material.node_tree
    tree.nodes["phong_exponent"].outputs[0].default_value = 18.0
    tree.nodes["phong_blinn"].outputs[0].default_value = 0.3
    tree.nodes["phong_specular_color"].outputs[0].default_value = (0.9, 0.8, 1.0, 1.0)
    tree.nodes["phong_irradiant_color"].outputs[0].default_value = (0.02, 0.0, 0.03, 1.0)


def linked_controls(material):
    """A Phong material's controls as its lights group reads them: the colour of the node linked
    to each colour input, and the values of the exponent and Blinn nodes (the importers' tests
    compare them with the file's values)."""
    nodes = material.node_tree.nodes
    lights = nodes["phong_lights"]

    def colour(name):
        return tuple(lights.inputs[name].links[0].from_node.outputs[0].default_value)[:3]

    return {"Object Color": colour("Object Color"),
            "Ambient Object Color": colour("Ambient Object Color"),
            "Specular Color": colour("Specular Color"),
            "Irradiant Color": colour("Irradiant Color"),
            "Exponent": nodes["phong_exponent"].outputs[0].default_value,
            "Blinn": nodes["phong_blinn"].outputs[0].default_value}


# -- reference ------------------------------------------------------------------

def _controls(material, ambient=True):
    """The material's controls as :func:`reference_color` and :func:`phong_shading` read
    them, its "Ambient Object Color" included unless not *ambient* (the reference's own
    Phong Shading group has none)."""
    nodes = material.node_tree.nodes
    col = lambda n: np.array(nodes[n].outputs[0].default_value[:3], dtype=np.float64)  # noqa: E731
    out = {"Object Color": col("phong_object_color"),
           "Specular Color": col("phong_specular_color"),
           "Irradiant Color": col("phong_irradiant_color"),
           "Exponent": float(nodes["phong_exponent"].outputs[0].default_value),
           "Blinn": float(nodes["phong_blinn"].outputs[0].default_value)}
    if ambient:
        out["Ambient Object Color"] = _ambient_object_color(material, out["Object Color"])
    return out


def _ambient_object_color(material, object_color):
    """The colour the material states for its Ambient Object Color, read from its nodes: an
    RGB node's colour; Object Color × scale + offset where a Vector Math Multiply Add of
    the Object Color's feed does it (a converted Principled material: its values are
    checked against Cycles in test_principled_ambient.py); else the Object Color."""
    socket = material.node_tree.nodes["phong_lights"].inputs["Ambient Object Color"]
    if not socket.is_linked:
        return object_color
    node = socket.links[0].from_node
    if node.bl_idname == "ShaderNodeRGB":
        return np.array(node.outputs[0].default_value[:3], dtype=np.float64)
    if node.bl_idname == "ShaderNodeVectorMath" and node.operation == "MULTIPLY_ADD":
        scale, offset = (np.array(node.inputs[i].default_value[:3], dtype=np.float64)
                         for i in (1, 2))
        return object_color * scale + offset
    return object_color


def phong_shading(inputs, geo):
    """The reference's Phong Shading of *inputs* (``_controls(material, ambient=True)`` and
    the light's), its ambient light seeing their "Ambient Object Color"."""
    shading = dict(inputs)
    shading.pop("Ambient Object Color", None)
    out = _ref().GROUPS["Phong Shading"](shading, geo)
    return _own_ambient(out, inputs, shading.get("Ambient Intensity", 0.1),
                        shading.get("Ambient Color", np.ones(3)))


def _own_ambient(out, controls, ambient_intensity, ambient_color):
    """*out* of a Phong Shading whose ambient light sees the material's Ambient Object Color
    (the reference's Phong Shading has the seeds' Ka = Kd): its Ambient term and Color
    (the sum of the terms, at most 1) made again."""
    ka = controls.get("Ambient Object Color")
    if ka is None:
        return out
    out = dict(out)
    out["Ambient"] = ambient_intensity * np.asarray(ambient_color, dtype=np.float64) * ka \
        * np.ones_like(out["Ambient"])
    out["Color"] = np.minimum(sum(out[t] for t in TERMS), 1.0)
    return out


#: i0 per watt (per unit of a sun's strength) of a light that takes it from its Power: what
#: Blender's own light gives a diffuse surface, measured in Cycles (docs/model.md).
POWER_I0 = {"POINT": 1.0 / (4.0 * math.pi ** 2), "SPOT": 1.0 / (4.0 * math.pi ** 2),
            "SUN": 1.0 / math.pi, "AREA": 1.0 / math.pi ** 2}


def intensity(light):
    """The light's i0: its Phong Intensity, or from its Power where it follows it."""
    if not light.phong.from_power:
        return light.phong.intensity
    return light.energy * 2.0 ** getattr(light, "exposure", 0.0) * POWER_I0[light.type]


def light_inputs(obj):
    """The light-model group's inputs from the light itself (matrix_world, data, settings);
    an Area light is a spot of half angle 90° and edge exponent 1."""
    light = obj.data
    kind = "SPOT" if light.type == "AREA" else light.type
    mw = np.array(obj.matrix_world, dtype=np.float64)
    s = light.phong
    inputs = {"Intensity": intensity(light)}
    if kind in ("POINT", "SPOT"):
        inputs.update({"Position": mw[:3, 3], "Quadratic": s.quadratic, "Linear": s.linear,
                       "Constant": s.constant})
        if s.falloff == "POWER":  # i0/d^k: the group without falloff (see _power)
            inputs.update({"Quadratic": 0.0, "Linear": 0.0, "Constant": 1.0})
    if kind in ("SUN", "SPOT"):
        inputs["Direction"] = -mw[:3, 2]
    if light.type == "SPOT":
        inputs.update({"Half Angle": light.spot_size / 2.0, "Edge Exponent": s.edge_exponent})
    elif light.type == "AREA":
        inputs.update({"Half Angle": math.pi / 2.0, "Edge Exponent": 1.0})
    return inputs


GROUP = {"POINT": "Phong Point Light", "SUN": "Phong Directional Light",
         "SPOT": "Phong Spot Light", "AREA": "Phong Spot Light"}


def reference_color(world, lights, controls, P, N, I, terms=None):
    """Summed Phong colour: one Phong Shading per light, ambient/irradiant on the first;
    *terms* (a dict) receives the sum of each term."""
    ref = _ref()
    geo = {"Position": P, "Normal": N, "Incoming": I}
    near_edge = np.zeros(P.shape[:-1], dtype=bool)
    total = None
    if terms is not None:
        terms.update({t: np.zeros(P.shape) for t in TERMS})
    for index, obj in enumerate(lights):
        out = dict(ref.GROUPS[GROUP[obj.data.type]](light_inputs(obj), geo))
        if obj.data.type in ("POINT", "SPOT", "AREA") and obj.data.phong.falloff == "POWER":
            out["Intensity"] = ref.power_falloff(out["Distance"], out["Intensity"],
                                                 obj.data.phong.power_k)["Intensity"]
        if obj.data.type == "SPOT":
            cos_t = math.cos(obj.data.spot_size / 2.0)
            near_edge |= np.abs(out["Cos Angle"] - cos_t) < 1e-5
        first = index == 0
        shading = {**controls,
                   "Light Vector": out["Light Vector"], "Light Intensity": out["Intensity"],
                   "Light Color": np.array(obj.data.color, dtype=np.float64),
                   "Diffuse Strength": obj.data.phong.diffuse,
                   "Specular Strength": obj.data.phong.specular,
                   "Ambient Intensity": world.phong.ambient_intensity if first else 0.0,
                   "Ambient Color": np.array(world.phong.ambient_color, dtype=np.float64)}
        if not first:
            shading["Irradiant Color"] = np.zeros(3)
        shading.pop("Ambient Object Color", None)
        out = ref.GROUPS["Phong Shading"](shading, geo)
        out = _own_ambient(out, controls, shading["Ambient Intensity"], shading["Ambient Color"])
        color = out["Color"]
        if terms is not None:
            for t in TERMS:
                terms[t] = terms[t] + out[t]
        total = color if total is None else ref.GROUPS["Phong Color Add"]({"A": total, "B": color})["Color"]
    if total is None:  # no light: one Phong Shading with Light Intensity 0
        shading = {**controls, "Light Intensity": 0.0,
                   "Ambient Intensity": world.phong.ambient_intensity,
                   "Ambient Color": np.array(world.phong.ambient_color, dtype=np.float64)}
        shading.pop("Ambient Object Color", None)
        out = _own_ambient(ref.GROUPS["Phong Shading"](shading, geo), controls,
                           shading["Ambient Intensity"], shading["Ambient Color"])
        total = out["Color"]
        if terms is not None:
            terms.update({t: out[t] for t in TERMS})
    return total, near_edge


def render(bpy, scene, path):
    t0 = time.perf_counter()
    be.render_exr(scene, path)
    seconds = time.perf_counter() - t0
    passes = {k: v[::-1] for k, v in be.read_multilayer_exr(path).items()}  # row 0 = bottom
    return passes, seconds


def compare(bpy, scene, passes, lights, label, tol=CY_TOL, objects=None):
    """Every probed pixel against the reference: "Phong Color", Combined and each term pass.
    *objects*: {id: (material, lights reaching it)}; default the plane (1) and sphere (2)."""
    world = scene.world
    if objects is None:
        objects = {1: (bpy.data.objects["Plane"].active_material, lights),
                   2: (bpy.data.objects["Sphere"].active_material, lights)}
    ident = np.rint(passes["id"][..., 0]).astype(int)
    got = {"Color": passes["Phong Color"][..., :3].astype(np.float64),
           "Combined": passes["Combined"][..., :3].astype(np.float64)}
    got.update({t: passes[f"Phong {t}"][..., :3].astype(np.float64) for t in TERMS})
    expected = {k: np.zeros_like(got["Color"]) for k in got}
    edge = np.zeros(ident.shape, dtype=bool)
    P, N, I = (passes[k][..., :3].astype(np.float64) for k in ("P", "N", "I"))
    for key, (mat, reach) in objects.items():
        m = ident == key
        terms = {}
        exp, near = reference_color(world, reach, _controls(mat, ambient=True), P[m], N[m], I[m],
                                    terms)
        expected["Color"][m] = expected["Combined"][m] = exp
        for t in TERMS:
            expected[t][m] = terms[t]
        edge[m] = near
    assert set(np.unique(ident)) >= set(objects), "every object is in the picture"
    ok = ~edge & np.isin(ident, list(objects))
    errors = {k: float(np.abs(got[k] - expected[k])[ok].max()) for k in got}
    report(f"[materials {label}] pixels={int(ok.sum())} near spot edge excluded={int(edge.sum())} "
           + " ".join(f"max|{k}-ref|={v:.2e}" for k, v in errors.items())
           + f" mean colour={expected['Color'][ok].mean():.3f}")
    assert edge.sum() <= 3, "only a few pixels lie within 1e-5 of the spot cone edge"
    assert expected["Color"].max() > 0.2 and expected["Color"].std() > 0.02, "lit, not flat"
    for k, err in errors.items():
        assert err <= tol, f"{label}: {k} differs from the reference by {err:.3e}"
    return max(errors.values())


def lights_tree(material):
    """The lights group a Phong material uses."""
    return material.node_tree.nodes["phong_lights"].node_tree


def be_drivers(tree):
    anim = tree.animation_data
    return list(anim.drivers) if anim is not None else []


def _assert_drivers_ok(tree):
    fcurves = be_drivers(tree)
    assert fcurves, "the lights group has drivers"
    for fc in fcurves:
        d = fc.driver
        assert d.is_valid, f"{tree.name}: invalid driver {fc.data_path}[{fc.array_index}]"
        assert d.type != "SCRIPTED" or d.is_simple_expression, (
            f"{tree.name}: {fc.data_path} needs Python: {d.expression!r}")
        for var in d.variables:
            for target in var.targets[:1]:
                path = target.data_path if var.type == "SINGLE_PROP" else ""
                assert "phong." not in path, f"driver reads add-on data {path!r}"
    return len(fcurves)


def _drivers_in_file(bpy):
    trees = [m.node_tree for m in bpy.data.materials if m.node_tree] + list(bpy.data.node_groups)
    return sum(len(be_drivers(t)) for t in trees)


def input_value(socket, world=None):
    """The value a light group's input gets: its (driven) default value, or the World custom
    property an Attribute node of type View Layer reads into it (issue 30)."""
    if socket.is_linked:
        node = socket.links[0].from_node
        assert node.bl_idname == "ShaderNodeAttribute" and node.attribute_type == "VIEW_LAYER"
        import bpy  # noqa: PLC0415  (tests import this module before bpy)

        world = world or bpy.context.scene.world
        if socket.links[0].from_socket.name == "Alpha":  # a light's i0, the copy's fourth
            return float(world[node.attribute_name][3])
        return np.array(list(world[node.attribute_name])[:3])
    value = socket.default_value
    return np.array(value) if hasattr(value, "__len__") else float(value)


def _assert_light_inputs(tree, lights):
    for obj in lights:
        node = tree.nodes[f"light:{obj.name}"]
        mw = np.array(obj.matrix_world)
        if "Position" in node.inputs:
            np.testing.assert_allclose(input_value(node.inputs["Position"]), mw[:3, 3], atol=1e-6)
        if "Direction" in node.inputs:
            direction = input_value(node.inputs["Direction"])
            np.testing.assert_allclose(direction / np.linalg.norm(direction),
                                       -mw[:3, 2] / np.linalg.norm(mw[:3, 2]), atol=1e-6)
        if "Reversed Axis" in node.inputs:  # a lights group's light: the unit +Z axis
            np.testing.assert_allclose(input_value(node.inputs["Reversed Axis"]),
                                       mw[:3, 2] / np.linalg.norm(mw[:3, 2]), atol=1e-6)

