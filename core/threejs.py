# SPDX-License-Identifier: GPL-3.0-or-later
"""The three.js peer renderer's page: a scene as one self-contained HTML file.

The Blender side exports a scene as a plain dict; :func:`write_page` turns it into a page that
three.js (MeshPhongMaterial / MeshLambertMaterial) renders, and ``core/browser.py`` renders that
page in headless Chromium and reads the pixels back.  No ``bpy`` here.

The scene dict (format ``phong-nodes-threejs``, version 1; every colour is linear Rec.709)::

    {
      "format": "phong-nodes-threejs", "version": 1,
      "title": "...",                  # shown on the page
      "width": 256, "height": 128,     # pixels of the picture
      "camera": {"type": "perspective" | "orthographic",
                 "matrix_world": [16 floats, column-major, as THREE.Matrix4.fromArray],
                 "projection": [16 floats, column-major, OpenGL clip convention]},
      "ambient": {"color": [r, g, b], "intensity": float},  # an AmbientLight when intensity > 0
      "lights": [{"name": str, "type": "directional" | "point" | "spot",
                  "color": [r, g, b], "intensity": float, "position": [x, y, z],
                  "target": [x, y, z],        # directional, spot
                  "distance": float,          # point, spot: cutoff, 0 = none
                  "decay": float,             # point, spot
                  "angle": float,             # spot: half angle, radians
                  "penumbra": float}],        # spot: 0..1
      "materials": [{"name": str, "type": "phong" | "lambert", "color": [r, g, b],
                     "emissive": [r, g, b],
                     "specular": [r, g, b], "shininess": float,  # phong
                     "specular_strength": float}],               # phong, 0..1, default 1
      "meshes": [{"name": str, "material": int,   # index into materials
                  "lights": [int, ...],           # indices into lights: the only lights it sees
                  "positions": [x, y, z, ...],    # world space, 3 corners per triangle
                  "normals": [x, y, z, ...],      # one per corner, same layout
                  "cast_shadow": bool, "receive_shadow": bool}],   # optional, false
      "shadows": bool,                 # optional, false: renderer.shadowMap.enabled
    }

A light of a page with ``shadows`` may have ``"cast_shadow": true`` and ``"shadow":
{"map_size": int, "near": float, "far": float, "extent": float (directional: the half width
of its orthographic shadow camera), "normal_bias": float}`` (:func:`with_shadows` fills
them in from the meshes' bounds).

How the page renders it (three.js 0.181.0, physically based light units, no legacy lights):

* ``new THREE.Color().setRGB(r, g, b, THREE.LinearSRGBColorSpace)`` for every colour; the
  renderer writes sRGB (``outputColorSpace`` default, no tone mapping) into an RGBA canvas
  cleared to black with alpha 0 (``alpha: true``, no antialiasing, pixel ratio 1).
* The camera is a PerspectiveCamera or an OrthographicCamera (so ``isOrthographic`` is right)
  whose matrices are set from the dict as given (``updateProjectionMatrix`` is never called).
* DirectionalLight / PointLight / SpotLight with their targets.  Shadows only where the dict
  has ``shadows`` (the exported page, never the comparison's peer): three.js's shadow maps
  (``PCFShadowMap``, ``castShadow`` / ``receiveShadow`` per light and mesh), an approximation
  of "Phong plus shadow rays" (the map's resolution and its bias shift and blur the edges); a
  caster of another light set is drawn into each set's shadow maps only (no colour, no depth).
* three.js has no light linking, so the meshes are grouped by their ``lights`` list: each
  distinct set becomes one THREE.Scene (its meshes, its lights, the ambient light), and the
  scenes are rendered one after the other into the same canvas (``autoClear`` off, one clear
  before the first): the depth buffer keeps the nearest surface and every mesh is lit by its
  own lights only.
* ``specular_strength`` != 1 becomes a 1 x 1 float ``specularMap`` (with zero UVs).

The page loads ``three.cjs`` (copied beside it, with three's licence as ``three.LICENSE``) as
a classic script through a CommonJS shim and carries the scene inline as JSON, so it opens from
``file://`` in any browser without flags.  When done it holds the picture as base64 RGBA (row 0
at the top) in ``<pre id="phong-pixels" data-width data-height>``, one captured error or warning
per line in ``<pre id="phong-errors">``, and the title ``phong: done`` (``phong: error`` when the
script threw).

three.js itself is not part of the repository: ``tools/phong.sh setup`` installs the version
pinned by ``tools/threejs/package-lock.json`` with npm into :func:`three_dir`.
"""

from __future__ import annotations

import filecmp
import html
import json
import math
import os
import re

import numpy as np

from . import browser, outputs

THREE_VERSION = "0.181.0"
SCENE_FORMAT = "phong-nodes-threejs"
SCENE_VERSION = 1
SCRIPT_NAME = "three.cjs"
LICENSE_NAME = "three.LICENSE"


class ThreeMissing(RuntimeError):
    """three.js is not installed where :func:`three_dir` says."""


def three_dir() -> str:
    """The folder holding ``node_modules/three``: ``$PHONG_THREE_DIR`` if set, else
    ``${XDG_CACHE_HOME:-~/.cache}/phong-nodes/three-<version>``."""
    return browser.package_dir("PHONG_THREE_DIR", "three", THREE_VERSION)


def three_module() -> str:
    """Path of three's self-contained CommonJS bundle; :class:`ThreeMissing` if absent."""
    return browser.package_file(three_dir(), "three", os.path.join("build", SCRIPT_NAME),
                                "three.js", THREE_VERSION, ThreeMissing)


def three_license() -> str:
    return os.path.join(os.path.dirname(os.path.dirname(three_module())), "LICENSE")


def _json_default(value):
    tolist = getattr(value, "tolist", None)  # numpy arrays and scalars
    if tolist is not None:
        return tolist()
    if isinstance(value, tuple):
        return list(value)
    raise TypeError(f"not JSON serializable: {type(value).__name__}")


def scene_json(scene: dict) -> str:
    """The scene as JSON that is safe inside a ``<script>`` element: ``</`` becomes ``<\\/`` and
    ``<!--`` ``\\u003c!--`` (both mean the same to a JSON parser)."""
    text = json.dumps(scene, allow_nan=False, separators=(",", ":"), default=_json_default)
    return text.replace("</", "<\\/").replace("<!--", "\\u003c!--")


#: Shadow map sizes (texels a side): a directional or spot light's map, a point light's cube face.
SHADOW_MAP = 2048
SHADOW_MAP_POINT = 1024


def with_shadows(scene: dict, lights_cast: list, meshes_cast: list) -> dict:
    """*scene* (a page's dict) with shadows: ``shadows`` true where some light of
    *lights_cast* (a bool per light) casts; each such light's ``cast_shadow`` and ``shadow``
    settings, its shadow camera around the bounding sphere of the meshes (a directional light
    moved to 2 radii from the centre along its direction, which is what shades); each mesh
    ``cast_shadow`` (*meshes_cast*) and ``receive_shadow`` true.  Normal bias: 1.5 texels at
    the light's distance from the centre."""
    out = dict(scene)
    points = [p for mesh in scene.get("meshes", ()) for p in
              zip(*(iter(mesh["positions"]),) * 3)]
    if not any(lights_cast) or not points:
        return out
    low = [min(p[i] for p in points) for i in range(3)]
    high = [max(p[i] for p in points) for i in range(3)]
    centre = [(a + b) / 2.0 for a, b in zip(low, high)]
    radius = max(math.dist(low, high) / 2.0, 1e-6)
    out["shadows"] = True
    out["meshes"] = [dict(mesh, cast_shadow=bool(cast), receive_shadow=True)
                     for mesh, cast in zip(scene["meshes"], meshes_cast)]
    lights = []
    for light, cast in zip(scene.get("lights", ()), lights_cast):
        light = dict(light)
        if cast:
            light["cast_shadow"] = True
            light["shadow"] = _shadow_camera(light, centre, radius)
        lights.append(light)
    out["lights"] = lights
    return out


def model_note(model, scene_name: str) -> str | None:
    """The warning of a scene in a lighting model (``node_groups.models``) that is not
    three.js's own (None for three.js's): the page shows three.js's model."""
    if "threejs" in model.native:
        return None
    return (f"scene {scene_name!r} uses the {model.label} model: the page shows three.js's "
            "(set the scene's Lighting Model to three.js to see the same in Blender)")


def material_of(name: str, values: dict) -> tuple:
    """(the page's material, notes) of a Phong material's *values* ("color", "specular",
    "shininess", "emissive", "specular_strength", "ambient" (the Ambient Object Color),
    "blinn"): MeshLambertMaterial where the Specular Strength is 0, else MeshPhongMaterial
    with specularStrength clamped into [0, 1]; notes: what three.js cannot say (an ambient
    colour of its own, a Phong (r·v)^e share of the highlight)."""
    notes = []
    if max(abs(a - b) for a, b in zip(values["ambient"], values["color"])) > 1e-6:
        notes.append("its own Ambient Object Color is not exported (three.js's ambient light "
                     "sees the material's color)")
    if values["blinn"]:
        notes.append("Blinn is not exported (three.js's highlight is always Blinn-Phong)")
    strength = min(max(values["specular_strength"], 0.0), 1.0)
    out = {"name": name, "type": "lambert" if strength == 0.0 else "phong",
           "color": values["color"], "emissive": values["emissive"]}
    if out["type"] == "phong":
        out.update(specular=values["specular"], shininess=values["shininess"],
                   specular_strength=strength)
    return out, notes


def light_of(light: dict, model) -> dict:
    """The page's light of a scene's *light* (plain data: "name", "type" directional / point
    / spot, "color", "intensity", "position", "direction", "half_angle" in degrees and its
    settings) in the lighting *model*: three.js's distance, decay and penumbra as
    ``LightingModel.threejs_light`` maps them; a directional light shines from -direction
    towards the origin, a spot towards position + direction."""
    out = {"name": light["name"], "type": light["type"], "color": light["color"],
           "intensity": light["intensity"]}
    if light["type"] == "directional":
        u = _unit(light["direction"])
        out.update(position=[float(c) for c in -u], target=[0.0, 0.0, 0.0])
        return out
    mapped = model.threejs_light(light)
    out.update(position=light["position"], distance=mapped["distance"],
               decay=mapped["decay"])
    if light["type"] == "spot":
        u = _unit(light["direction"])
        out.update(target=[float(c) for c in np.asarray(light["position"]) + u],
                   angle=math.radians(light["half_angle"]), penumbra=mapped["penumbra"])
    return out


def _unit(vector):
    u = np.asarray(vector, np.float64)
    return u / np.linalg.norm(u)


def _shadow_camera(light: dict, centre: list, radius: float) -> dict:
    """The ``shadow`` settings of *light* (moved, for a directional one) around the sphere
    (*centre*, *radius*)."""
    margin = 1.05 * radius
    if light["type"] == "directional":
        way = [t - p for t, p in zip(light["target"], light["position"])]
        length = math.hypot(*way) or 1.0
        far = 2.0 * radius
        light["position"] = [c - far * w / length for c, w in zip(centre, way)]
        light["target"] = list(centre)
        texel = 2.0 * margin / SHADOW_MAP
        return {"map_size": SHADOW_MAP, "near": max(far - margin, 0.0), "far": far + margin,
                "extent": margin, "normal_bias": 1.5 * texel}
    away = math.dist(light["position"], centre)
    far = away + margin
    size = SHADOW_MAP_POINT if light["type"] == "point" else SHADOW_MAP
    half = math.pi / 4.0 if light["type"] == "point" else min(light["angle"], 1.5)
    texel = 2.0 * max(away, radius) * math.tan(half) / size
    return {"map_size": size, "near": max(away - margin, 1e-3 * far), "far": far,
            "normal_bias": 1.5 * texel}


def _copy_if_changed(source: str, target: str) -> None:
    if os.path.isfile(target) and filecmp.cmp(source, target, shallow=False):
        return
    with open(source, "rb") as stream:
        outputs.write_file(target, stream.read())


def unavailable() -> str | None:
    """What the three.js peer lacks on this machine (one line naming what to install), or
    None when Chromium and three.js are both there."""
    if browser.find_browser() is None:
        return browser.missing_message()
    try:
        three_module()
    except ThreeMissing as error:
        return str(error)
    return None


def capture_js() -> str:
    """The script every page of ours runs first: the capture of errors and warnings
    (``window.phongReport``) and ``window.phongWritePixels(renderer, width, height)``."""
    return _CAPTURE_JS.strip()


def page_html(scene: dict) -> str:
    """The page's text (it expects ``three.cjs`` beside it)."""
    title = html.escape(str(scene.get("title", "")))
    return (_PAGE.replace("@TITLE@", title)
            .replace("@VERSION@", THREE_VERSION)
            .replace("@SCENE@", scene_json(scene))
            .replace("@CAPTURE@", capture_js())
            .replace("@RENDER@", _RENDER_JS.strip()))


def write_page(path: str, scene: dict) -> None:
    """Write the page ``path`` and copy ``three.cjs`` and ``three.LICENSE`` beside it (when not
    already identical).  The page is written to a temp file and moved into place, so it is never
    half-written.  :class:`ThreeMissing` when three.js is not installed."""
    module, license_path = three_module(), three_license()
    text = page_html(scene)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    _copy_if_changed(module, os.path.join(folder, SCRIPT_NAME))
    if os.path.isfile(license_path):
        _copy_if_changed(license_path, os.path.join(folder, LICENSE_NAME))
    outputs.write_file(path, text)


_SCENE_RE = re.compile(
    r'<script type="application/json" id="phong-scene">(.*?)</script>', re.DOTALL)


def read_scene(path: str) -> dict:
    """The scene embedded in a page written by :func:`write_page`."""
    with open(path, encoding="utf-8") as stream:
        match = _SCENE_RE.search(stream.read())
    if match is None:
        raise ValueError(f"{path}: no embedded phong scene")
    return json.loads(match.group(1))


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>phong: loading</title>
<style>
body { background: #444; color: #eee; font: 14px sans-serif; margin: 1em; }
#phong-view canvas { background: repeating-conic-gradient(#777 0 25%, #999 0 50%) 0 0 / 16px 16px; }
#phong-errors { color: #f88; white-space: pre-wrap; }
#phong-errors:empty, #phong-pixels { display: none; }
</style>
</head>
<body>
<h1 id="phong-title">@TITLE@</h1>
<div id="phong-view"></div>
<p>three.js @VERSION@ (MIT, see three.LICENSE) &middot; Phong Nodes three.js peer renderer</p>
<pre id="phong-errors"></pre>
<pre id="phong-pixels" data-width="0" data-height="0"></pre>
<script>
@CAPTURE@
</script>
<script>var module = {exports: {}}, exports = module.exports;</script>
<script src="three.cjs"></script>
<script>var THREE = module.exports;</script>
<script type="application/json" id="phong-scene">@SCENE@</script>
<script>
@RENDER@
</script>
</body>
</html>
"""

# Installed before anything else: every error and warning the page meets, one per line.
_CAPTURE_JS = r"""
(function () {
  "use strict";
  var list = [];
  var shown = document.getElementById("phong-errors");
  function describe(value) {
    if (value instanceof Error) { return value.stack ? String(value.stack) : String(value); }
    if (typeof value === "object" && value !== null) {
      try { return JSON.stringify(value); } catch (e) { return String(value); }
    }
    return String(value);
  }
  function report(message) {
    var line = String(message).replace(/\s*[\r\n]+\s*/g, " | ");
    if (line.length > 4000) { line = line.slice(0, 4000) + " ..."; }
    list.push(line);
    shown.textContent = list.join("\n");
  }
  // The canvas's pixels (8-bit sRGB RGBA, row 0 at the top) as base64 in phong-pixels.
  window.phongWritePixels = function (renderer, expectWidth, expectHeight) {
    var gl = renderer.getContext();
    var width = gl.drawingBufferWidth, height = gl.drawingBufferHeight;
    if (width !== expectWidth || height !== expectHeight) {
      throw new Error("drawing buffer is " + width + " x " + height + ", not " + expectWidth +
                      " x " + expectHeight);
    }
    var bytes = new Uint8Array(width * height * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, bytes);
    var rows = new Uint8Array(bytes.length), stride = width * 4;
    for (var y = 0; y < height; y++) {  // GL's row 0 is the bottom
      rows.set(bytes.subarray((height - 1 - y) * stride, (height - y) * stride), y * stride);
    }
    var text = [];
    for (var i = 0; i < rows.length; i += 0x8000) {
      text.push(String.fromCharCode.apply(null, rows.subarray(i, i + 0x8000)));
    }
    var pixels = document.getElementById("phong-pixels");
    pixels.setAttribute("data-width", String(width));
    pixels.setAttribute("data-height", String(height));
    pixels.textContent = btoa(text.join(""));
  };
  window.phongErrors = list;
  window.phongReport = report;
  window.phongDescribe = describe;
  window.onerror = function (message, source, line, column, error) {
    var where = source ? " (" + String(source).split("/").pop() + ":" + line + ":" + column + ")" : "";
    report("uncaught " + (error ? describe(error) : String(message)) + where);
    return false;
  };
  window.addEventListener("error", function (event) {
    var target = event.target;
    if (target && target !== window && (target.src || target.href)) {
      report("could not load " + (target.src || target.href));
    }
  }, true);
  window.addEventListener("unhandledrejection", function (event) {
    report("unhandled rejection: " + describe(event.reason));
  });
  ["error", "warn"].forEach(function (level) {
    var original = console[level];
    console[level] = function () {
      report("console." + level + ": " + Array.prototype.map.call(arguments, describe).join(" "));
      return original.apply(console, arguments);
    };
  });
})();
"""

# Builds and renders the scene synchronously, then writes the pixels into the page.
_RENDER_JS = r"""
(function () {
  "use strict";
  var report = window.phongReport, describe = window.phongDescribe;

  var shadowsOn = false;  // the scene's "shadows" (set by build)
  function fail(message) { throw new Error(message); }
  function number(spec, key, what, fallback) {
    var value = spec[key];
    if (value === undefined && fallback !== undefined) { return fallback; }
    if (typeof value !== "number" || !isFinite(value)) {
      fail(what + ": '" + key + "' must be a number, not " + JSON.stringify(value));
    }
    return value;
  }
  function vector(spec, key, what, size, fallback) {
    var value = spec[key];
    if (value === undefined && fallback !== undefined) { return fallback; }
    if (!Array.isArray(value) || value.length !== size || !value.every(function (x) {
      return typeof x === "number" && isFinite(x);
    })) {
      fail(what + ": '" + key + "' must be " + size + " numbers, not " + JSON.stringify(value));
    }
    return value;
  }
  function color(spec, key, what, fallback) {
    var c = vector(spec, key, what, 3, fallback);
    return new THREE.Color().setRGB(c[0], c[1], c[2], THREE.LinearSRGBColorSpace);
  }

  function makeCamera(spec) {
    var camera;
    if (spec.type === "perspective") { camera = new THREE.PerspectiveCamera(); }
    else if (spec.type === "orthographic") { camera = new THREE.OrthographicCamera(); }
    else { fail("camera: unknown type " + JSON.stringify(spec.type)); }
    camera.matrixAutoUpdate = false;
    camera.matrix.fromArray(vector(spec, "matrix_world", "camera", 16));
    camera.matrix.decompose(camera.position, camera.quaternion, camera.scale);
    camera.matrixWorld.copy(camera.matrix);
    camera.matrixWorldInverse.copy(camera.matrixWorld).invert();
    camera.projectionMatrix.fromArray(vector(spec, "projection", "camera", 16));
    camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
    return camera;
  }

  // A light's objects (the light and its target): new ones for every scene that uses it,
  // since an object has one parent.
  function makeLight(spec, index) {
    var what = "light " + index + " " + JSON.stringify(spec.name);
    var c = color(spec, "color", what), intensity = number(spec, "intensity", what);
    var light;
    if (spec.type === "directional") {
      light = new THREE.DirectionalLight(c, intensity);
    } else if (spec.type === "point") {
      light = new THREE.PointLight(c, intensity, number(spec, "distance", what, 0),
                                   number(spec, "decay", what, 2));
    } else if (spec.type === "spot") {
      light = new THREE.SpotLight(c, intensity, number(spec, "distance", what, 0),
                                  number(spec, "angle", what), number(spec, "penumbra", what, 0),
                                  number(spec, "decay", what, 2));
    } else {
      fail(what + ": unknown type " + JSON.stringify(spec.type));
    }
    light.name = String(spec.name);
    light.castShadow = Boolean(shadowsOn && spec.cast_shadow);
    if (light.castShadow) {
      var shadow = spec.shadow || {}, sw = what + " shadow";
      var size = number(shadow, "map_size", sw, 2048);
      light.shadow.mapSize.set(size, size);
      light.shadow.camera.near = number(shadow, "near", sw, 0.5);
      light.shadow.camera.far = number(shadow, "far", sw, 500);
      if (spec.type === "directional") {
        var extent = number(shadow, "extent", sw, 5);
        light.shadow.camera.left = -extent; light.shadow.camera.right = extent;
        light.shadow.camera.bottom = -extent; light.shadow.camera.top = extent;
      }
      light.shadow.normalBias = number(shadow, "normal_bias", sw, 0);
      light.shadow.camera.updateProjectionMatrix();
    }
    light.position.fromArray(vector(spec, "position", what, 3));
    if (light.target) {
      light.target.position.fromArray(vector(spec, "target", what, 3));
      return [light, light.target];
    }
    return [light];
  }

  function makeMaterial(spec, index) {
    var what = "material " + index + " " + JSON.stringify(spec.name);
    var params = {
      color: color(spec, "color", what),
      emissive: color(spec, "emissive", what, [0, 0, 0]),
      side: THREE.DoubleSide
    };
    var material, needsUv = false;
    if (spec.type === "phong") {
      params.specular = color(spec, "specular", what);
      params.shininess = number(spec, "shininess", what);
      material = new THREE.MeshPhongMaterial(params);
      var strength = number(spec, "specular_strength", what, 1);
      if (strength !== 1) {
        var map = new THREE.DataTexture(new Float32Array([strength, strength, strength, 1]), 1, 1,
                                        THREE.RGBAFormat, THREE.FloatType);
        map.magFilter = THREE.NearestFilter;
        map.minFilter = THREE.NearestFilter;
        map.generateMipmaps = false;
        map.colorSpace = THREE.NoColorSpace;
        map.needsUpdate = true;
        material.specularMap = map;
        needsUv = true;
      }
    } else if (spec.type === "lambert") {
      material = new THREE.MeshLambertMaterial(params);
    } else {
      fail(what + ": unknown type " + JSON.stringify(spec.type));
    }
    material.name = String(spec.name);
    return {material: material, needsUv: needsUv};
  }

  function makeMesh(spec, index, materials) {
    var what = "mesh " + index + " " + JSON.stringify(spec.name);
    var positions = spec.positions, normals = spec.normals;
    if (!Array.isArray(positions) || positions.length % 9 !== 0) {
      fail(what + ": 'positions' must be 9 numbers per triangle");
    }
    if (!Array.isArray(normals) || normals.length !== positions.length) {
      fail(what + ": 'normals' must be as long as 'positions'");
    }
    var slot = materials[spec.material];
    if (!Number.isInteger(spec.material) || slot === undefined) {
      fail(what + ": no material " + JSON.stringify(spec.material));
    }
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(positions, 3));
    geometry.setAttribute("normal", new THREE.Float32BufferAttribute(normals, 3));
    if (slot.needsUv) {
      geometry.setAttribute("uv", new THREE.Float32BufferAttribute(
        new Float32Array(positions.length / 3 * 2), 2));
    }
    var mesh = new THREE.Mesh(geometry, slot.material);
    mesh.name = String(spec.name);
    mesh.matrixAutoUpdate = false;  // identity: positions are in world space
    mesh.frustumCulled = false;
    mesh.castShadow = Boolean(shadowsOn && spec.cast_shadow);
    mesh.receiveShadow = Boolean(shadowsOn && spec.receive_shadow);
    return mesh;
  }

  function build(scene) {
    if (scene.format !== "phong-nodes-threejs") {
      fail("not a phong-nodes-threejs scene: format " + JSON.stringify(scene.format));
    }
    var width = scene.width, height = scene.height;
    if (!Number.isInteger(width) || !Number.isInteger(height) || width < 1 || height < 1) {
      fail("width and height must be positive integers");
    }
    shadowsOn = scene.shadows === true;
    var camera = makeCamera(scene.camera || {});
    var lights = scene.lights || [], ambient = scene.ambient || {color: [0, 0, 0], intensity: 0};
    var ambientColor = color(ambient, "color", "ambient", [1, 1, 1]);
    var ambientIntensity = number(ambient, "intensity", "ambient", 0);
    var materials = (scene.materials || []).map(makeMaterial);
    var sets = [], byKey = {};
    (scene.meshes || []).forEach(function (spec, index) {
      var mesh = makeMesh(spec, index, materials);
      var used = (spec.lights || []).slice().sort(function (a, b) { return a - b; })
        .filter(function (x, i, all) { return i === 0 || all[i - 1] !== x; });
      used.forEach(function (i) {
        if (!Number.isInteger(i) || lights[i] === undefined) {
          fail("mesh " + index + " " + JSON.stringify(spec.name) + ": no light " + JSON.stringify(i));
        }
      });
      var key = used.join(",");
      if (!(key in byKey)) {
        var group = new THREE.Scene();
        group.name = "lights [" + key + "]";
        if (ambientIntensity > 0) { group.add(new THREE.AmbientLight(ambientColor, ambientIntensity)); }
        used.forEach(function (i) {
          makeLight(lights[i], i).forEach(function (object) { group.add(object); });
        });
        byKey[key] = group;
        sets.push(group);
      }
      byKey[key].add(mesh);
    });
    // A caster of another light set is drawn into this set's shadow maps only.
    if (shadowsOn && sets.length > 1) {
      var hidden = new THREE.MeshBasicMaterial({colorWrite: false, depthWrite: false,
                                                side: THREE.DoubleSide});
      sets.forEach(function (group) {
        sets.forEach(function (other) {
          if (other === group) { return; }
          other.children.forEach(function (object) {
            if (object.isMesh && object.castShadow && !object.userData.proxy) {
              var proxy = new THREE.Mesh(object.geometry, hidden);
              proxy.matrixAutoUpdate = false;
              proxy.frustumCulled = false;
              proxy.castShadow = true;
              proxy.userData.proxy = true;
              group.add(proxy);
            }
          });
        });
      });
    }
    // Unused lights are checked too, so a bad light fails whether or not a mesh sees it.
    lights.forEach(makeLight);
    return {width: width, height: height, camera: camera, scenes: sets, shadows: shadowsOn};
  }

  function render(built) {
    var renderer = new THREE.WebGLRenderer({antialias: false, alpha: true, preserveDrawingBuffer: true});
    renderer.setPixelRatio(1);
    renderer.setSize(built.width, built.height);
    renderer.setClearColor(0x000000, 0);
    renderer.autoClear = false;
    renderer.shadowMap.enabled = built.shadows;
    renderer.shadowMap.type = THREE.PCFShadowMap;
    document.getElementById("phong-view").appendChild(renderer.domElement);
    renderer.clear(true, true, true);
    built.scenes.forEach(function (scene) { renderer.render(scene, built.camera); });
    window.phongWritePixels(renderer, built.width, built.height);
  }

  try {
    if (typeof THREE.WebGLRenderer !== "function") { fail("three.js did not load (three.cjs)"); }
    var scene = JSON.parse(document.getElementById("phong-scene").textContent);
    render(build(scene));
    document.title = "phong: done";
  } catch (error) {
    report("exception: " + describe(error));
    document.title = "phong: error";
  }
})();
"""
