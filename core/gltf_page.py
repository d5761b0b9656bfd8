# SPDX-License-Identifier: GPL-3.0-or-later
"""A page that shows a .glb file with three.js's own GLTFLoader, for the check of glTF with
Baked Phong Lighting: ``core/browser.py`` renders it in headless Chromium and reads the
pixels back, as it does the three.js peer's page (``core/threejs.py``).

The folder of the page holds the page, three.js's ES modules (``three.module.js``,
``three.core.js``, ``addons/loaders/GLTFLoader.js`` and the one helper it imports, copied
from the pinned npm package of :func:`threejs.three_dir`, with three's licence) and the
.glb; an import map points ``three`` and ``three/addons/`` at them.  The .glb rides inline
as base64 (``file://`` pages cannot ``fetch`` files) and GLTFLoader parses it; the scene is
drawn with the camera given as matrices (the one of the Blender scene, so three.js and
Cycles see the same pixels), no tone mapping, the sRGB canvas cleared to alpha 0.  The
page writes the picture as :mod:`core.threejs` pages do (``phong-pixels``,
``phong-errors``, the title ``phong: done`` / ``phong: error``).  No ``bpy`` here.
"""

from __future__ import annotations

import base64
import json
import os

from . import outputs, threejs

#: Files of the three.js package the page loads: (path in the package, path by the page).
MODULES = (("build/three.module.js", "three/three.module.js"),
           ("build/three.core.js", "three/three.core.js"),
           ("examples/jsm/loaders/GLTFLoader.js", "three/addons/loaders/GLTFLoader.js"),
           ("examples/jsm/utils/BufferGeometryUtils.js",
            "three/addons/utils/BufferGeometryUtils.js"),
           ("LICENSE", "three/LICENSE"))
#: Blender's Z-up world as glTF's Y-up one: (x, y, z) -> (x, z, -y), what Blender's
#: exporter does with export_yup.
Y_UP = ((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0), (0.0, -1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))


def y_up(matrix_rows) -> list:
    """A Blender world matrix (4 rows) in glTF's Y-up world, column-major (16 floats)."""
    rows = [[sum(Y_UP[r][k] * float(matrix_rows[k][c]) for k in range(4)) for c in range(4)]
            for r in range(4)]
    return [rows[r][c] for c in range(4) for r in range(4)]


def write_page(folder: str, glb_path: str, camera: dict, width: int, height: int,
               title: str = "glTF with Baked Phong Lighting") -> str:
    """The page ``folder/gltf.html`` showing *glb_path* through *camera* ({"type",
    "matrix_world" (column-major, glTF's Y-up world), "projection" (column-major)}) at
    width × height pixels; returns its path.  ThreeMissing when three.js is not installed."""
    package = os.path.dirname(os.path.dirname(threejs.three_module()))
    os.makedirs(folder, exist_ok=True)
    for source, target in MODULES:
        path = os.path.join(folder, target)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(os.path.join(package, source), "rb") as stream:
            outputs.write_file(path, stream.read())
    with open(glb_path, "rb") as stream:
        glb = base64.b64encode(stream.read()).decode("ascii")
    spec = {"width": int(width), "height": int(height), "camera": camera}
    text = (_PAGE.replace("@TITLE@", title)
            .replace("@SPEC@", threejs.scene_json(spec))
            .replace("@GLB@", glb)
            .replace("@CAPTURE@", threejs.capture_js()))
    return outputs.write_file(os.path.join(folder, "gltf.html"), text)


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>phong: loading</title>
<script type="importmap">
{"imports": {"three": "./three/three.module.js", "three/addons/": "./three/addons/"}}
</script>
</head>
<body>
<h1>@TITLE@</h1>
<div id="phong-view"></div>
<p>three.js (MIT, see three/LICENSE) GLTFLoader &middot; Phong Nodes</p>
<pre id="phong-errors"></pre>
<pre id="phong-pixels" data-width="0" data-height="0"></pre>
<script>
@CAPTURE@
</script>
<script type="application/json" id="phong-spec">@SPEC@</script>
<script type="text/plain" id="phong-glb">@GLB@</script>
<script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

const report = window.phongReport, describe = window.phongDescribe;
try {
  const spec = JSON.parse(document.getElementById("phong-spec").textContent);
  const text = atob(document.getElementById("phong-glb").textContent.trim());
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) { bytes[i] = text.charCodeAt(i); }
  const gltf = await new GLTFLoader().parseAsync(bytes.buffer, "./");
  const camera = spec.camera.type === "orthographic" ? new THREE.OrthographicCamera()
                                                      : new THREE.PerspectiveCamera();
  camera.matrixAutoUpdate = false;
  camera.matrix.fromArray(spec.camera.matrix_world);
  camera.matrix.decompose(camera.position, camera.quaternion, camera.scale);
  camera.matrixWorld.copy(camera.matrix);
  camera.matrixWorldInverse.copy(camera.matrixWorld).invert();
  camera.projectionMatrix.fromArray(spec.camera.projection);
  camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
  const renderer = new THREE.WebGLRenderer({antialias: false, alpha: true,
                                            preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  renderer.setSize(spec.width, spec.height);
  renderer.setClearColor(0x000000, 0);
  document.getElementById("phong-view").appendChild(renderer.domElement);
  const textures = [];
  gltf.scene.traverse((object) => {
    if (object.isMesh) {
      object.frustumCulled = false;
      const map = object.material.map;
      if (map) { textures.push(map); }
    }
  });
  // GLTFLoader decodes images asynchronously: wait until every texture has its pixels
  for (let tries = 0; tries < 200 && textures.some((t) => !t.image); tries++) {
    await new Promise((resolve) => setTimeout(resolve, 10));
  }
  renderer.render(gltf.scene, camera);
  window.phongWritePixels(renderer, spec.width, spec.height);
  document.title = "phong: done";
} catch (error) {
  report("exception: " + describe(error));
  document.title = "phong: error";
}
</script>
</body>
</html>
"""
