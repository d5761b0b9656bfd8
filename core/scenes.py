# SPDX-License-Identifier: GPL-3.0-or-later
"""Demo scenes as data: read ``scenes/*.toml`` and validate them.

Pure python (``tomllib``, no ``bpy``), so the validation unit-tests in milliseconds and
the CLI can refuse a bad file before it imports Blender or creates any output.

``load(path)`` returns a plain dict with every default filled in (JSON-serialisable: the
report prints it as the scene's parameters).  Every error is a :class:`SceneError` whose
message names the file, the key (``lights[1].type``) and what was expected.

Schema (units: Blender world space, Z up; angles in degrees; colours are either
``"#RRGGBB"`` (sRGB, converted to scene-linear) or ``[r, g, b]`` (scene-linear, >= 0)):

    title = "..."                 # required
    model = "seeds"               # a lighting model of node_groups/models.py: "seeds",
                                  # "threejs" (three.js r181's MeshPhongMaterial /
                                  # MeshLambertMaterial and its lights, docs/threejs.md) or
                                  # "x3d" (X3D / VRML97's lighting equation, docs/x3d.md)
    source = "seed 000 §3.1"      # where the figure comes from (optional)
    description = "..."           # optional
    aspect = 2.0                  # width / height of the picture (default 1)
    [camera]                      # required
    type = "perspective"          # or "orthographic"
    location = [x, y, z]          # required
    look_at = [0, 0, 0]
    lens = 50.0                   # mm, perspective
    ortho_scale = 10.0            # orthographic: width of the view
    [ambient]                     # optional: intensity 0 (none), colour white
    intensity = 0.1
    color = "#FFFFFF"
    [[lights]]                    # any number, also none (black without ambient)
    name = "key"                  # unique; default "light<i>"
    type = "point"                # "point", "directional" or "spot"
    color = "#FFFFFF"; intensity = 1.0; diffuse = 1.0; specular = 1.0
    shadows = false               # casts shadows (Blender's Cast Shadow; the seeds' none)
    position = [x, y, z]          # point, spot (required)
    direction = [x, y, z]         # directional, spot: the way the rays travel (required)
    quadratic = 1.0; linear = 0.0; constant = 0.0     # point, spot: i0/(αr²+βr+γ)
    falloff_exponent = 2          # point only, optional: i0/d^k instead, 0 <= k <= 16 (k = 0,
                                  # 1, 2: the light's γ, β or α = 1, the others 0; any other k:
                                  # the light's power falloff, phong_falloff POWER)
    half_angle = 30.0             # spot, degrees, in (0, 90]
    edge_exponent = 0.0           # spot, >= 0
    # model = "threejs": lights take three.js's settings instead (three.js defaults):
    #   intensity = 1.0; distance = 0.0 (point, spot: cut-off, 0 = none); decay = 2.0
    #   (point, spot); half_angle = 60.0 (spot: three.js's angle); penumbra = 0.0 (spot, [0, 1])
    # model = "x3d": lights take X3D's fields instead (X3D's defaults): intensity = 1.0;
    #   ambient = 0.0 (ambientIntensity, [0, 1]); constant = 1.0, linear = 0.0, quadratic = 0.0
    #   (point, spot: attenuation 1/max(a0 + a1·d + a2·d², 1)); radius = 100.0 (point, spot);
    #   half_angle = 90.0 (spot: cutOffAngle, degrees); beam_width = 45.0 (spot: beamWidth,
    #   degrees; held in radians in the parsed scene, as Blender's light holds it)
    [[objects]]                   # at least one
    name = "ball"                 # unique, required
    shape = "sphere"              # or "plane" (square, normal +Z before rotation)
    location = [0, 0, 0]; rotation = [0, 0, 0] (degrees); size = 1.0 (radius / half side)
    segments = 64                 # sphere: segments around (rings: half as many), 3 to 256
    bake = "vertex"               # optional: shown baked (Bake Phong Lighting, view camera):
                                  # "vertex" (Gouraud shading) or "image"; not compared
    label = "..."                 # caption in the report (default: the name)
    lights = ["key"]              # lights that shine on this object (default: all)
    shadows = true                # casts shadows (false: Ray Visibility ▸ Shadow and, 5.3+,
                                  # Ray Cast off; Blender 5.2's Cycles cannot leave it out)
    terms = ["irradiant", "ambient", "diffuse", "specular"]   # terms shown (default: all)
    [objects.material]
    color = "#CCCCCC"; specular_color = "#FFFFFF"; exponent = 30.0; blinn = 0.0
    irradiant = [0, 0, 0]
    texture = { type = "checker", color2 = "#333333", scale = 4.0 }   # optional
    shading = "pixel"             # or "vertex" (Gouraud), "face" (flat), live
                                  # (docs/shading_modes.md); not compared
    # model = "threejs": type = "phong" or "lambert"; color (default "#FFFFFF"),
    # specular_color ("#111111"), exponent (shininess, 30), irradiant (emissive); no blinn
    # model = "x3d": color (diffuseColor, default [0.8, 0.8, 0.8]), ambient_intensity (0.2,
    # [0, 1]: the ambient lights see ambient_intensity × color), specular_color ([0, 0, 0]),
    # exponent (128 × shininess, 25.6), irradiant (emissiveColor); no blinn (X3D's highlight
    # is the half-vector one)

The models' names come from the lighting models' table (``node_groups/models.py``); each has
its readers of lights and materials here (``LIGHT_READERS``, ``MATERIAL_READERS``).  Every
parsed material has ``ambient_color``: the colour the ambient light sees (the object colour,
or ambient_intensity × it in X3D).
"""

from __future__ import annotations

import math
import os
import re
import tomllib

from ..node_groups import models
from ..node_groups.library import FALLOFF_DEFAULTS, X3D_BEAM_WIDTH, X3D_RADIUS

#: The scenes shipped with the extension.
SCENES_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scenes")

LIGHT_TYPES = ("point", "directional", "spot")
SHAPES = ("sphere", "plane")
CAMERA_TYPES = ("perspective", "orthographic")
TERMS = ("irradiant", "ambient", "diffuse", "specular")
TEXTURES = ("checker",)
#: falloff_exponent k -> (quadratic α, linear β, constant γ): i0/d^k = i0/(αd² + βd + γ).
FALLOFF_EXPONENTS = {0.0: (0.0, 0.0, 1.0), 1.0: (0.0, 1.0, 0.0), 2.0: (1.0, 0.0, 0.0)}
#: The largest falloff_exponent (the Phong Power Falloff group's Exponent input goes to 16).
MAX_FALLOFF_EXPONENT = 16.0
NAME_RE = re.compile(r"^[a-z0-9_]+$")
#: The lighting models of a scene file (``model = ...``): the lighting models' table's.
MODELS = models.NAMES
THREEJS_MATERIALS = ("phong", "lambert")


class SceneError(ValueError):
    """A scene file that cannot be used; the message names file, key and expectation."""


# -- colours ---------------------------------------------------------------------

def srgb_to_linear(c: float) -> float:
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def hex_to_linear(text: str) -> tuple:
    return tuple(srgb_to_linear(int(text[i:i + 2], 16) / 255.0) for i in (1, 3, 5))


# -- the checker ----------------------------------------------------------------------

class _Checker:
    """Typed access to a TOML table; every failure names file and key."""

    def __init__(self, path: str):
        self.path = path

    def fail(self, key: str, expected: str, got=None, show_got=True):
        got_text = f", got {_show(got)}" if show_got else ""
        raise SceneError(f"{self.path}: {key}: expected {expected}{got_text}")

    def table(self, parent: dict, key: str, where: str, required=True) -> dict:
        if key not in parent:
            if required:
                self.fail(_join(where, key), "a table (missing)", show_got=False)
            return {}
        value = parent[key]
        if not isinstance(value, dict):
            self.fail(_join(where, key), "a table", value)
        return value

    def unknown(self, table: dict, allowed, where: str):
        extra = sorted(set(table) - set(allowed))
        if extra:
            raise SceneError(f"{self.path}: {_join(where, extra[0])}: unknown key; expected one of "
                             f"{', '.join(sorted(allowed))}")

    def string(self, table, key, where, default=None, choices=None, pattern=None):
        if key not in table:
            if default is None:
                self.fail(_join(where, key), "a string (missing)", show_got=False)
            return default
        value = table[key]
        if not isinstance(value, str):
            self.fail(_join(where, key), "a string", value)
        if choices is not None and value not in choices:
            self.fail(_join(where, key), "one of " + ", ".join(repr(c) for c in choices), value)
        if pattern is not None and not pattern.match(value):
            self.fail(_join(where, key), f"a name matching {pattern.pattern}", value)
        return value

    def boolean(self, table, key, where, default=False) -> bool:
        if key not in table:
            return default
        value = table[key]
        if not isinstance(value, bool):
            self.fail(_join(where, key), "true or false", value)
        return value

    def number(self, table, key, where, default=None, minimum=None, maximum=None,
               exclusive_min=False):
        if key not in table:
            if default is None:
                self.fail(_join(where, key), "a number (missing)", show_got=False)
            return float(default)
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(_join(where, key), "a finite number", value)
        value = float(value)
        if minimum is not None and (value <= minimum if exclusive_min else value < minimum):
            op = ">" if exclusive_min else ">="
            bound = f"a number {op} {_fmt(minimum)}"
            if maximum is not None:
                bound += f" and <= {_fmt(maximum)}"
            self.fail(_join(where, key), bound, value)
        if maximum is not None and value > maximum:
            self.fail(_join(where, key), f"a number <= {_fmt(maximum)}", value)
        return value

    def vector(self, table, key, where, default=None, nonzero=False):
        if key not in table:
            if default is None:
                self.fail(_join(where, key), "a list of 3 numbers [x, y, z] (missing)",
                          show_got=False)
            return list(default)
        value = table[key]
        if (not isinstance(value, list) or len(value) != 3
                or any(isinstance(v, bool) or not isinstance(v, (int, float))
                       or not math.isfinite(v) for v in value)):
            self.fail(_join(where, key), "a list of 3 numbers [x, y, z]", value)
        if nonzero and all(v == 0 for v in value):
            self.fail(_join(where, key), "a non-zero vector", value)
        return [float(v) for v in value]

    def color(self, table, key, where, default):
        if key not in table:
            return list(hex_to_linear(default)) if isinstance(default, str) else list(default)
        value = table[key]
        if isinstance(value, str):
            if not re.match(r"^#[0-9A-Fa-f]{6}$", value):
                self.fail(_join(where, key), 'a colour "#RRGGBB" (sRGB) or [r, g, b] (linear)',
                          value)
            return list(hex_to_linear(value))
        if (not isinstance(value, list) or len(value) != 3
                or any(isinstance(v, bool) or not isinstance(v, (int, float))
                       or not math.isfinite(v) or v < 0 for v in value)):
            self.fail(_join(where, key),
                      'a colour "#RRGGBB" (sRGB) or [r, g, b] (linear, numbers >= 0)', value)
        return [float(v) for v in value]

    def names(self, table, key, where, choices, default):
        if key not in table:
            return list(default)
        value = table[key]
        if not isinstance(value, list) or any(not isinstance(v, str) for v in value):
            self.fail(_join(where, key), "a list of strings", value)
        for index, item in enumerate(value):
            if item not in choices:
                self.fail(f"{_join(where, key)}[{index}]",
                          "one of " + ", ".join(repr(c) for c in choices), item)
        return list(value)

    def array_of_tables(self, table, key, where, required=True):
        if key not in table:
            if required:
                self.fail(_join(where, key), f"an array of tables [[{key}]] (missing)",
                          show_got=False)
            return []
        value = table[key]
        if not isinstance(value, list) or any(not isinstance(v, dict) for v in value):
            self.fail(_join(where, key), f"an array of tables [[{key}]]", value)
        return value


def _join(where: str, key) -> str:
    return f"{where}.{key}" if where else str(key)


def _fmt(x: float) -> str:
    return f"{x:g}"


def _show(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


# -- the schema -------------------------------------------------------------------

TOP_KEYS = ("title", "model", "source", "description", "aspect", "camera", "ambient", "lights",
            "objects")
CAMERA_KEYS = ("type", "location", "look_at", "lens", "ortho_scale")
AMBIENT_KEYS = ("intensity", "color")
LIGHT_KEYS = {
    "point": ("name", "type", "color", "intensity", "shadows", "diffuse", "specular", "position",
              "quadratic", "linear", "constant", "falloff_exponent"),
    "directional": ("name", "type", "color", "intensity", "shadows", "diffuse", "specular",
                    "direction"),
    "spot": ("name", "type", "color", "intensity", "shadows", "diffuse", "specular", "position",
             "direction", "quadratic", "linear", "constant", "half_angle", "edge_exponent"),
}
#: The lights' keys in the three.js model.
THREEJS_LIGHT_KEYS = {
    "point": ("name", "type", "color", "intensity", "shadows", "position", "distance", "decay"),
    "directional": ("name", "type", "color", "intensity", "shadows", "direction"),
    "spot": ("name", "type", "color", "intensity", "shadows", "position", "direction", "distance",
             "decay", "half_angle", "penumbra"),
}
#: The lights' keys in the X3D / VRML97 model.
X3D_LIGHT_KEYS = {
    "point": ("name", "type", "color", "intensity", "shadows", "position", "ambient",
              "constant", "linear", "quadratic", "radius"),
    "directional": ("name", "type", "color", "intensity", "shadows", "direction", "ambient"),
    "spot": ("name", "type", "color", "intensity", "shadows", "position", "direction",
             "ambient", "constant", "linear", "quadratic", "radius", "half_angle", "beam_width"),
}
OBJECT_KEYS = ("name", "shape", "location", "rotation", "size", "segments", "bake", "label",
               "lights", "terms", "material", "shadows")
BAKES = ("vertex", "image")
MATERIAL_KEYS = ("color", "specular_color", "exponent", "blinn", "irradiant", "texture",
                 "shading")
THREEJS_MATERIAL_KEYS = ("type", "color", "specular_color", "exponent", "irradiant", "texture",
                         "shading")
X3D_MATERIAL_KEYS = ("color", "ambient_intensity", "specular_color", "exponent", "irradiant",
                     "texture", "shading")
#: A material's shading (docs/shading_modes.md): where the model is evaluated.
SHADINGS = ("pixel", "vertex", "face")
TEXTURE_KEYS = ("type", "color2", "scale")


def parse(data: dict, path: str = "<scene>") -> dict:
    """Validate a TOML document (already parsed); returns the scene with defaults filled."""
    c = _Checker(path)
    c.unknown(data, TOP_KEYS, "")
    model = c.string(data, "model", "", default=models.DEFAULT, choices=tuple(models.MODELS))
    schema = models.get(model).scene_schema   # the readers of its lights and materials
    scene = {
        "title": c.string(data, "title", ""),
        "model": model,
        "source": c.string(data, "source", "", default=""),
        "description": c.string(data, "description", "", default=""),
        "aspect": c.number(data, "aspect", "", default=1.0, minimum=0.1, maximum=10.0),
    }
    scene["camera"] = _camera(c, c.table(data, "camera", ""))
    scene["ambient"] = _ambient(c, c.table(data, "ambient", "", required=False))
    scene["lights"] = _lights(c, c.array_of_tables(data, "lights", "", required=False), schema)
    scene["objects"] = _objects(c, c.array_of_tables(data, "objects", ""),
                                [light["name"] for light in scene["lights"]], schema)
    return scene


def _camera(c: _Checker, cam: dict) -> dict:
    c.unknown(cam, CAMERA_KEYS, "camera")
    camera = {
        "type": c.string(cam, "type", "camera", default="perspective", choices=CAMERA_TYPES),
        "location": c.vector(cam, "location", "camera"),
        "look_at": c.vector(cam, "look_at", "camera", default=(0.0, 0.0, 0.0)),
        "lens": c.number(cam, "lens", "camera", default=50.0, minimum=1.0, maximum=5000.0),
        "ortho_scale": c.number(cam, "ortho_scale", "camera", default=10.0, minimum=0.0,
                                exclusive_min=True),
    }
    if camera["location"] == camera["look_at"]:
        c.fail("camera.look_at", "a point other than camera.location", camera["look_at"])
    return camera


def _ambient(c: _Checker, amb: dict) -> dict:
    c.unknown(amb, AMBIENT_KEYS, "ambient")
    return {
        "intensity": c.number(amb, "intensity", "ambient", default=0.0, minimum=0.0),
        "color": c.color(amb, "color", "ambient", "#FFFFFF"),
    }


def _lights(c: _Checker, raws: list, model: str = "seeds") -> list:
    lights = []
    for index, raw in enumerate(raws):
        where = f"lights[{index}]"
        light = LIGHT_READERS[model](c, raw, where, index)
        if any(other["name"] == light["name"] for other in lights):
            c.fail(f"{where}.name", "a name not used by another light", light["name"])
        lights.append(light)
    return lights


def _light_head(c: _Checker, raw: dict, where: str, index: int, keys: dict) -> dict:
    """What every light has in both models (name, type, color, intensity), its keys checked
    against *keys* (light type -> allowed keys)."""
    kind = c.string(raw, "type", where, choices=LIGHT_TYPES)
    c.unknown(raw, keys[kind], where)
    return {
        "name": c.string(raw, "name", where, default=f"light{index}", pattern=NAME_RE),
        "type": kind,
        "color": c.color(raw, "color", where, "#FFFFFF"),
        "intensity": c.number(raw, "intensity", where, default=1.0, minimum=0.0),
        "shadows": c.boolean(raw, "shadows", where, default=False),
    }


def _light(c: _Checker, raw: dict, where: str, index: int) -> dict:
    light = _light_head(c, raw, where, index, LIGHT_KEYS)
    kind = light["type"]
    light["diffuse"] = c.number(raw, "diffuse", where, default=1.0, minimum=0.0)
    light["specular"] = c.number(raw, "specular", where, default=1.0, minimum=0.0)
    if kind in ("point", "spot"):
        light["position"] = c.vector(raw, "position", where)
        for key, default in FALLOFF_DEFAULTS.items():
            light[key] = c.number(raw, key, where, default=default, minimum=0.0)
        if light["quadratic"] == light["linear"] == light["constant"] == 0.0:
            c.fail(f"{where}.quadratic", "quadratic, linear and constant not all 0", 0)
    if kind == "point" and "falloff_exponent" in raw:
        k = c.number(raw, "falloff_exponent", where, minimum=0.0, maximum=MAX_FALLOFF_EXPONENT)
        if any(key in raw for key in ("quadratic", "linear", "constant")):
            c.fail(f"{where}.falloff_exponent", "either falloff_exponent or quadratic, linear "
                   "and constant, not both", raw["falloff_exponent"])
        light["falloff_exponent"] = k
        if k in FALLOFF_EXPONENTS:  # the light's γ, β or α = 1: i0/d^k exactly
            light["quadratic"], light["linear"], light["constant"] = FALLOFF_EXPONENTS[k]
        else:  # the light's power falloff (phong_falloff POWER, phong_power_k)
            light["falloff"], light["power_k"] = "POWER", k
    if kind in ("directional", "spot"):
        light["direction"] = c.vector(raw, "direction", where, nonzero=True)
    if kind == "spot":
        light["half_angle"] = c.number(raw, "half_angle", where, default=30.0, minimum=0.0,
                                       maximum=90.0, exclusive_min=True)
        light["edge_exponent"] = c.number(raw, "edge_exponent", where, default=0.0,
                                          minimum=0.0)
    return light


def _threejs_light(c: _Checker, raw: dict, where: str, index: int) -> dict:
    """A light of a three.js scene: three.js's settings and defaults (docs/threejs.md)."""
    light = _light_head(c, raw, where, index, THREEJS_LIGHT_KEYS)
    kind = light["type"]
    if kind in ("point", "spot"):
        light["position"] = c.vector(raw, "position", where)
        light["distance"] = c.number(raw, "distance", where, default=0.0, minimum=0.0)
        light["decay"] = c.number(raw, "decay", where, default=2.0, minimum=0.0)
    if kind in ("directional", "spot"):
        light["direction"] = c.vector(raw, "direction", where, nonzero=True)
    if kind == "spot":
        light["half_angle"] = c.number(raw, "half_angle", where, default=60.0, minimum=0.0,
                                       maximum=90.0, exclusive_min=True)
        light["penumbra"] = c.number(raw, "penumbra", where, default=0.0, minimum=0.0,
                                     maximum=1.0)
    return light


def _x3d_light(c: _Checker, raw: dict, where: str, index: int) -> dict:
    """A light of an X3D / VRML97 scene: X3D's fields and defaults (docs/x3d.md)."""
    light = _light_head(c, raw, where, index, X3D_LIGHT_KEYS)
    kind = light["type"]
    light["ambient"] = c.number(raw, "ambient", where, default=0.0, minimum=0.0, maximum=1.0)
    if kind in ("point", "spot"):
        light["position"] = c.vector(raw, "position", where)
        for key, default in (("constant", 1.0), ("linear", 0.0), ("quadratic", 0.0)):
            light[key] = c.number(raw, key, where, default=default, minimum=0.0)
        light["radius"] = c.number(raw, "radius", where, default=X3D_RADIUS, minimum=0.0,
                                   exclusive_min=True)
    if kind in ("directional", "spot"):
        light["direction"] = c.vector(raw, "direction", where, nonzero=True)
    if kind == "spot":
        light["half_angle"] = c.number(raw, "half_angle", where, default=90.0, minimum=0.0,
                                       maximum=90.0, exclusive_min=True)
        light["beam_width"] = math.radians(c.number(
            raw, "beam_width", where, default=math.degrees(X3D_BEAM_WIDTH), minimum=0.0,
            maximum=180.0, exclusive_min=True))
    return light


#: a model's scene schema (``LightingModel.scene_schema``) -> the reader of its lights.
LIGHT_READERS = {"seeds": _light, "threejs": _threejs_light, "x3d": _x3d_light}


def _objects(c: _Checker, raws: list, light_names: list, model: str = "seeds") -> list:
    if not raws:
        c.fail("objects", "at least one [[objects]] table", [])
    objects = []
    for index, raw in enumerate(raws):
        where = f"objects[{index}]"
        c.unknown(raw, OBJECT_KEYS, where)
        obj = {
            "name": c.string(raw, "name", where, pattern=NAME_RE),
            "shape": c.string(raw, "shape", where, default="sphere", choices=SHAPES),
            "location": c.vector(raw, "location", where, default=(0.0, 0.0, 0.0)),
            "rotation": c.vector(raw, "rotation", where, default=(0.0, 0.0, 0.0)),
            "size": c.number(raw, "size", where, default=1.0, minimum=0.0, exclusive_min=True),
            "segments": c.number(raw, "segments", where, default=64, minimum=3, maximum=256),
        }
        if obj["segments"] != int(obj["segments"]):
            c.fail(f"{where}.segments", "a whole number from 3 to 256", obj["segments"])
        obj["segments"] = int(obj["segments"])
        obj["bake"] = c.string(raw, "bake", where, default="", choices=("",) + BAKES)
        obj["label"] = c.string(raw, "label", where, default=obj["name"])
        obj["shadows"] = c.boolean(raw, "shadows", where, default=True)
        obj["lights"] = c.names(raw, "lights", where, light_names, light_names)
        obj["terms"] = c.names(raw, "terms", where, TERMS, TERMS)
        obj["material"] = _material(c, c.table(raw, "material", where, required=False),
                                    f"{where}.material", model)
        if any(other["name"] == obj["name"] for other in objects):
            c.fail(f"{where}.name", "a name not used by another object", obj["name"])
        objects.append(obj)
    return objects


def _material(c: _Checker, mat: dict, where: str, model: str = "seeds") -> dict:
    material = MATERIAL_READERS[model](c, mat, where)
    material["texture"] = None
    material["shading"] = c.string(mat, "shading", where, default="pixel", choices=SHADINGS)
    if "texture" in mat:
        tex = c.table(mat, "texture", where)
        twhere = f"{where}.texture"
        c.unknown(tex, TEXTURE_KEYS, twhere)
        material["texture"] = {
            "type": c.string(tex, "type", twhere, choices=TEXTURES),
            "color2": c.color(tex, "color2", twhere, "#333333"),
            "scale": c.number(tex, "scale", twhere, default=4.0, minimum=0.0,
                              exclusive_min=True),
        }
    return material


def _seeds_material(c: _Checker, mat: dict, where: str) -> dict:
    c.unknown(mat, MATERIAL_KEYS, where)
    color = c.color(mat, "color", where, "#CCCCCC")
    return {"color": color, "ambient_color": list(color),
            "specular_color": c.color(mat, "specular_color", where, "#FFFFFF"),
            "exponent": c.number(mat, "exponent", where, default=30.0, minimum=0.0),
            "blinn": c.number(mat, "blinn", where, default=0.0, minimum=0.0, maximum=1.0),
            "irradiant": c.color(mat, "irradiant", where, (0.0, 0.0, 0.0))}


def _threejs_material(c: _Checker, mat: dict, where: str) -> dict:
    c.unknown(mat, THREEJS_MATERIAL_KEYS, where)
    color = c.color(mat, "color", where, "#FFFFFF")
    return {"color": color, "ambient_color": list(color),
            "specular_color": c.color(mat, "specular_color", where, "#111111"),
            "exponent": c.number(mat, "exponent", where, default=30.0, minimum=0.0),
            "blinn": 0.0,
            "irradiant": c.color(mat, "irradiant", where, (0.0, 0.0, 0.0)),
            "type": c.string(mat, "type", where, default="phong", choices=THREEJS_MATERIALS)}


def _x3d_material(c: _Checker, mat: dict, where: str) -> dict:
    """An X3D Material's fields (docs/x3d.md): Ka = ambientIntensity × diffuseColor."""
    c.unknown(mat, X3D_MATERIAL_KEYS, where)
    color = c.color(mat, "color", where, (0.8, 0.8, 0.8))
    ambient = c.number(mat, "ambient_intensity", where, default=0.2, minimum=0.0, maximum=1.0)
    return {"color": color, "ambient_intensity": ambient,
            "ambient_color": [ambient * v for v in color],
            "specular_color": c.color(mat, "specular_color", where, (0.0, 0.0, 0.0)),
            "exponent": c.number(mat, "exponent", where, default=25.6, minimum=0.0,
                                 maximum=128.0),
            "blinn": 1.0,
            "irradiant": c.color(mat, "irradiant", where, (0.0, 0.0, 0.0))}


#: a model's scene schema -> the reader of its materials.
MATERIAL_READERS = {"seeds": _seeds_material, "threejs": _threejs_material,
                    "x3d": _x3d_material}


def load(path: str) -> dict:
    """Read and validate one scene file; the scene's ``name`` is the file's stem."""
    name = os.path.splitext(os.path.basename(path))[0]
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except FileNotFoundError:
        raise SceneError(f"{path}: no such scene file") from None
    except OSError as error:
        raise SceneError(f"{path}: cannot read: {error.strerror}") from None
    except tomllib.TOMLDecodeError as error:
        raise SceneError(f"{path}: not valid TOML: {error}") from None
    scene = parse(data, path)
    if not NAME_RE.match(name):
        raise SceneError(f"{path}: file name: expected lower-case letters, digits and _ "
                         f"(the scene's name), got {name!r}")
    scene["name"] = name
    scene["path"] = os.path.abspath(path)
    return scene


def available(folder: str = SCENES_DIR) -> list:
    """Names of the scene files in *folder*, sorted."""
    return sorted(f[:-5] for f in os.listdir(folder) if f.endswith(".toml"))


def resolve(spec: str | None, folder: str = SCENES_DIR) -> list:
    """Scene file paths for a ``--scenes`` value: comma-separated names of shipped scenes
    and/or paths to .toml files; None or "all" = every shipped scene."""
    if spec is None or spec.strip() in ("", "all"):
        return [os.path.join(folder, f"{n}.toml") for n in available(folder)]
    paths = []
    names = available(folder)
    for item in (s.strip() for s in spec.split(",")):
        if not item:
            continue
        if item.endswith(".toml") or os.sep in item:
            paths.append(item)
        elif item in names:
            paths.append(os.path.join(folder, f"{item}.toml"))
        else:
            raise SceneError(f"--scenes: unknown scene {item!r}; expected one of "
                             f"{', '.join(names)} or a path to a .toml file")
    if not paths:
        raise SceneError("--scenes: no scene given")
    return paths


def load_all(paths) -> list:
    """Validate every file first (all or nothing); duplicate names are refused."""
    scenes = [load(p) for p in paths]
    seen = {}
    for scene in scenes:
        if scene["name"] in seen:
            raise SceneError(f"{scene['path']}: scene name {scene['name']!r} also used by "
                             f"{seen[scene['name']]}")
        seen[scene["name"]] = scene["path"]
    return scenes


def _shard_numbers(spec: str) -> tuple:
    match = re.match(r"^(\d+)/(\d+)$", spec.strip())
    if not match or not 1 <= int(match.group(1)) <= int(match.group(2)):
        raise SceneError(f"--shard: expected i/n with 1 <= i <= n (e.g. 2/4) or auto, "
                         f"got {spec!r}")
    return int(match.group(1)), int(match.group(2))


def shard(items: list, spec: str | None) -> list:
    """The part *i/n* (1-based) of *items*: every n-th item starting at i."""
    if not spec:
        return list(items)
    i, n = _shard_numbers(spec)
    return items[i - 1::n]


#: The help of every command's ``--shard`` option (demo, compare, bake): parse it with
#: :func:`resolve_shard`.
SHARD_HELP = ("i/n: only every n-th scene starting at the i-th (1-based); auto (or auto/N): "
              "i and n from a Slurm job array (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT) or "
              "a Kubernetes Indexed Job (JOB_COMPLETION_INDEX, with N)")


def _env_int(environ, name: str, default: int | None = None) -> int:
    value = environ.get(name, "")
    if default is not None and not value.strip():
        return default
    try:
        return int(value)
    except ValueError:
        raise SceneError(f"--shard auto: {name}={value!r} is not a whole number") from None


def resolve_shard(spec: str | None, environ=None) -> tuple:
    """The ``--shard`` value as ``(i/n or None, where it came from)``.

    ``i/n`` is returned as given (validated).  ``auto`` reads the scheduler's variables:
    a Slurm job array's ``SLURM_ARRAY_TASK_ID`` minus ``SLURM_ARRAY_TASK_MIN`` of
    ``SLURM_ARRAY_TASK_COUNT`` tasks (a contiguous array such as ``--array=0-3``), or a
    Kubernetes Indexed Job's ``JOB_COMPLETION_INDEX``, which needs the count: ``auto/N``.
    With ``auto/N`` the index itself is the 0-based shard number (``SLURM_ARRAY_TASK_ID``
    or ``JOB_COMPLETION_INDEX`` in 0..N-1), so one task resubmitted alone
    (``sbatch --array=2``) still takes shard 3 of N.  SceneError when nothing is set or a
    value does not fit."""
    if not spec:
        return None, ""
    match = re.match(r"^auto(?:/(\d+))?$", spec.strip())
    if not match:
        _shard_numbers(spec)
        return spec.strip(), ""
    environ = os.environ if environ is None else environ
    count = int(match.group(1)) if match.group(1) else None
    if count == 0:
        raise SceneError("--shard auto/N: N must be at least 1, got 0")
    if "SLURM_ARRAY_TASK_ID" in environ:
        task = _env_int(environ, "SLURM_ARRAY_TASK_ID")
        if count is None:
            count = _env_int(environ, "SLURM_ARRAY_TASK_COUNT")
            low = _env_int(environ, "SLURM_ARRAY_TASK_MIN", 0)
            high = _env_int(environ, "SLURM_ARRAY_TASK_MAX", low + count - 1)
            if high - low + 1 != count:
                raise SceneError(
                    f"--shard auto: the Slurm array {low}-{high} has {count} task(s), not "
                    f"{high - low + 1}: submit a contiguous array (--array=0-{count - 1}) "
                    "or give the number of shards, --shard auto/N")
            index, what = task - low, f"SLURM_ARRAY_TASK_ID={task}"
            source = (f"SLURM_ARRAY_TASK_ID={task} of SLURM_ARRAY_TASK_COUNT={count}"
                      f"{f' from SLURM_ARRAY_TASK_MIN={low}' if low else ''}")
        else:
            index, what = task, f"SLURM_ARRAY_TASK_ID={task}"
            source = f"{what} of {count}"
    elif "JOB_COMPLETION_INDEX" in environ:
        index = _env_int(environ, "JOB_COMPLETION_INDEX")
        what = f"JOB_COMPLETION_INDEX={index}"
        if count is None:
            raise SceneError(f"--shard auto: JOB_COMPLETION_INDEX={index} gives no count: "
                             "use --shard auto/N with N the Indexed Job's completions")
        source = f"{what} of {count}"
    else:
        raise SceneError("--shard auto: no scheduler index in the environment (Slurm's "
                         "SLURM_ARRAY_TASK_ID in a job array, Kubernetes' "
                         "JOB_COMPLETION_INDEX in an Indexed Job); give --shard i/n")
    if not 0 <= index < count:
        hint = " (with auto/N the index is the 0-based shard number)" if match.group(1) else ""
        raise SceneError(f"--shard auto: {what} is outside 0..{count - 1}{hint}")
    return f"{index + 1}/{count}", source
