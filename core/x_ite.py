# SPDX-License-Identifier: GPL-3.0-or-later
"""The X_ITE peer renderer: an X3D / VRML97 file rendered by X_ITE, a complete X3D browser, in
headless Chromium, and its pixels read back.  No ``bpy`` here.

X_ITE (npm ``x_ite``, MIT, by Holger Seelig) implements the standards' lighting equation in its
own shaders (``src/assets/shaders/webgl2/common/Material2.glsl.js`` and ``Lighting2.glsl.js``
of create3000/x_ite): per light ``attenuation·spot·color·(ambientIntensity·O_a + intensity·
(O_d·max(N·L, 0) + O_s·max(N·H, 0)^(128·shininess)))`` within the radius, the attenuation
``1/max(a0 + a1·d + a2·d², 1)``, the linear spot ramp from ``beamWidth`` to ``cutOffAngle``,
``pow(x, 0)`` taken as 1 for shininess 0, plus ``emissiveColor``; at most 8 lights per shape.
Two deviations from the standard, both tested (``tests/test_x_ite.py``): a light whose
intensity is 0 is switched off whole, its ambient term too (``X3DLightNode.set_on__``), and
``ambientIntensity`` (lights and Material) and ``shininess`` are clamped to [0, 1].

What :func:`render_text` / :func:`render_file` do:

* The file's text is embedded in a page (``<script type="application/json">``; a gzipped file
  is unpacked here first) and given to ``Browser.createX3DFromString`` with the file's own URL
  as the base for relative URLs, so every encoding X_ITE reads works (X3D XML, ClassicVRML,
  VRML97, X3D JSON).  X_ITE fetches an ``Inline`` with ``fetch``, which Chromium refuses for
  ``file://``: an Inline of a local file is not shown (a warning names it).
* Browser options (:data:`BROWSER_OPTIONS`): ``Shading PHONG`` (the default is ``GOURAUD``;
  in 15.0.1 both light every fragment with the same ``Material2.glsl.js``, PHONG is asked so
  that no release can light per vertex), ``Antialiased FALSE`` with ``Multisampling 0`` (one
  sample per pixel, at its centre: X_ITE 15.0.1 throws on the ``multisampling`` attribute of
  ``<x3d-canvas>``, so the option is set from the script), ``ContentScale 1`` (the drawing
  buffer is exactly width × height), ``ColorSpace SRGB``, ``ToneMapping NONE``,
  ``Exposure 1``, no order-independent transparency, no logarithmic depth buffer, quality
  HIGH for primitives and textures, ``StraightenHorizon FALSE``.
* The colour (``ColorSpace``): X_ITE's default, ``LINEAR_WHEN_PHYSICAL_MATERIAL``, is
  ``SRGB`` for a ``Material``: the colours of the file enter the equation as they are, and the
  equation's result *I* is written to the 8-bit canvas as it is (``toneMap`` multiplies by the
  exposure, 1, and nothing else; the RGBA8 framebuffer clips at 1 and rounds): **byte =
  round(255 · min(I, 1))**, the X3D 3 rule that the lighting result is the display value.
  ``LINEAR`` would instead write ``255 · min(I, 1)^(1/2.2)`` (``ToneMapping2.glsl.js``'s
  ``linearToSRGB`` is a 2.2 power, not the sRGB curve) and decode textures with that power.
  We keep ``SRGB``: the canvas then holds the standard's *I* itself, with no transfer curve,
  which is what Blender computes before its view transform (a scene in the X3D model gives
  the file's values to the equation unchanged), so the comparison reads X_ITE's byte / 255 as
  *I* (see ``core.compare.compare_x3d_display``).
* The picture's background is transparent: a ``Background { transparency 1 }`` is put first
  in the scene before it is shown, so it is the one bound (the file's own Background is not
  drawn) and the alpha channel is the coverage (255 where a surface is, 0 elsewhere).
* The file's bound Viewpoint (its first) is the camera, as X_ITE binds it: a perspective
  ``fieldOfView`` is the angle of the smaller side of the picture (ISO/IEC 19775-1 §23.4.2);
  an OrthoViewpoint's ``fieldOfView`` (minX minY maxX maxY) is widened along one axis to the
  picture's aspect ratio.  NavigationInfo's ``headlight`` is X_ITE's: a white
  DirectionalLight of intensity 1 along the view.
* The page waits until X_ITE has nothing left to load and the drawing buffer has the size
  asked, renders further frames, reads the canvas back (``readPixels``; the canvas keeps its
  buffer, ``preserveDrawingBuffer``) and writes it as base64 RGBA into the page, which
  ``core/browser.py`` reads (the page's title says when it is done).

X_ITE itself is not part of the repository: ``tools/phong.sh setup`` installs the version
pinned by ``tools/x_ite/package-lock.json`` with npm into :func:`x_ite_dir`.  The page loads
X_ITE from there (``file://``), so a page kept in a report shows on the machine that wrote it.
"""

from __future__ import annotations

import gzip
import html
import json
import os
import shutil
import pathlib
import zlib

from . import browser, outputs, threejs

X_ITE_VERSION = "15.0.1"
SCRIPT_NAME = "x_ite.min.js"

#: Browser options set before the scene loads (names and values as ``Browser.setBrowserOption``
#: takes them); the colour space is :func:`page_html`'s *color_space*.
BROWSER_OPTIONS = {
    "Shading": "PHONG",
    "Antialiased": False,
    "Multisampling": 0,
    "ContentScale": 1,
    "ToneMapping": "NONE",
    "Exposure": 1,
    "OrderIndependentTransparency": False,
    "LogarithmicDepthBuffer": False,
    "PrimitiveQuality": "HIGH",
    "TextureQuality": "HIGH",
    "StraightenHorizon": False,
    "Notifications": False,
    "Timings": False,
}
#: X_ITE's ColorSpace values this module takes; SRGB is the one the comparison uses.
COLOR_SPACES = ("SRGB", "LINEAR", "LINEAR_WHEN_PHYSICAL_MATERIAL")
#: Most lights X_ITE applies to one shape (WebGL 2: ``X3DRenderingContext`` sets 8).
MAX_LIGHTS = 8


class XIteMissing(RuntimeError):
    """X_ITE is not installed where :func:`x_ite_dir` says."""


def x_ite_dir() -> str:
    """The folder holding ``node_modules/x_ite``: ``$PHONG_X_ITE_DIR`` if set, else
    ``${XDG_CACHE_HOME:-~/.cache}/phong-nodes/x_ite-<version>``."""
    return browser.package_dir("PHONG_X_ITE_DIR", "x_ite", X_ITE_VERSION)


def x_ite_script() -> str:
    """Path of X_ITE's browser bundle; :class:`XIteMissing` if absent."""
    return browser.package_file(x_ite_dir(), "x_ite", os.path.join("dist", SCRIPT_NAME),
                                "X_ITE", X_ITE_VERSION, XIteMissing)


def missing_message() -> str:
    """One line: what the X_ITE peer renderer lacks (Chromium, npm) and how to install it."""
    if browser.find_browser() is not None and shutil.which("npm") is not None:
        return f"Chromium and npm are there; X_ITE {X_ITE_VERSION}: bash tools/phong.sh setup"
    return browser.missing_message("X_ITE")


def unavailable() -> str | None:
    """What the X_ITE peer lacks on this machine (one line naming what to install), or None
    when Chromium and X_ITE are both there."""
    if browser.find_browser() is None:
        return missing_message()
    try:
        x_ite_script()
    except XIteMissing as error:
        return str(error) if shutil.which("npm") else missing_message()
    return None


def read_text(path: str) -> str:
    """The text of an X3D / VRML file, unpacked when gzipped (by its magic bytes, whatever its
    name), decoded as UTF-8 (Latin-1 where that fails: old VRML files)."""
    with open(path, "rb") as stream:
        data = stream.read()
    if data[:2] == b"\x1f\x8b":
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError, zlib.error) as error:
            raise ValueError(f"{path}: not a readable gzip stream ({error})") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def _json_in_script(value) -> str:
    """JSON that is safe inside a ``<script>`` element (see ``threejs.scene_json``)."""
    text = json.dumps(value, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    return (text.replace("</", "<\\/").replace("<!--", "\\u003c!--")
            .replace("\u2028", "\\u2028").replace("\u2029", "\\u2029"))


def _file_url(path: str) -> str:
    """A file:// URL of *path*, percent-encoded (pathlib: the zip imports no network module)."""
    return pathlib.Path(os.path.abspath(path)).as_uri()


def page_html(x3d_text: str, width: int, height: int, base_url: str = "", title: str = "",
              color_space: str = "SRGB", script_url: str | None = None,
              frames: int = 2) -> str:
    """The page's text: X_ITE renders *x3d_text* at *width* × *height* and the page leaves its
    pixels.  *base_url*: the URL relative URLs of the file resolve against (the file's own);
    *color_space*: X_ITE's ColorSpace option (:data:`COLOR_SPACES`); *script_url*: where X_ITE's
    bundle is (default: the installed one, :class:`XIteMissing` without it); *frames*: frames
    rendered after loading before the pixels are read."""
    if not (isinstance(width, int) and isinstance(height, int) and width > 0 and height > 0):
        raise ValueError(f"width and height must be positive integers, not {width!r}, {height!r}")
    if color_space not in COLOR_SPACES:
        raise ValueError(f"color_space must be one of {', '.join(COLOR_SPACES)}, "
                         f"not {color_space!r}")
    if script_url is None:
        script_url = _file_url(x_ite_script())
    options = {"width": width, "height": height, "frames": max(1, int(frames)),
               "browser": dict(BROWSER_OPTIONS, ColorSpace=color_space),
               "max_lights": MAX_LIGHTS}
    attributes = {"preserveDrawingBuffer": "true", "splashScreen": "false",
                  "notifications": "false", "contextMenu": "false", "antialiased": "false",
                  "contentScale": "1", "colorSpace": color_space, "toneMapping": "NONE",
                  "update": "false", "timings": "false"}
    if base_url:
        attributes["baseURL"] = base_url
    attrs = " ".join(f'{key}="{html.escape(value)}"' for key, value in attributes.items())
    return (_PAGE.replace("@TITLE@", html.escape(title))
            .replace("@VERSION@", X_ITE_VERSION)
            .replace("@WIDTH@", str(width)).replace("@HEIGHT@", str(height))
            .replace("@ATTRIBUTES@", attrs)
            .replace("@SCRIPT@", html.escape(script_url))
            .replace("@CAPTURE@", threejs.capture_js())
            .replace("@OPTIONS@", _json_in_script(options))
            .replace("@RENDER@", _RENDER_JS.strip())
            .replace("@X3D@", _json_in_script(x3d_text)))


def write_page(path: str, x3d_text: str, width: int, height: int, base_url: str = "",
               title: str = "", color_space: str = "SRGB", frames: int = 2) -> None:
    """Write the page *path* (atomically); X_ITE is loaded from its installation."""
    text = page_html(x3d_text, width, height, base_url, title, color_space, frames=frames)
    os.makedirs(os.path.dirname(os.path.abspath(path)) or ".", exist_ok=True)
    outputs.write_file(path, text)


def render_text(x3d_text: str, width: int, height: int, page_path: str, base_url: str = "",
                title: str = "", color_space: str = "SRGB", timeout: float = 180,
                frames: int = 2) -> browser.PageResult:
    """Render *x3d_text* with X_ITE at *width* × *height* through the page *page_path* (written
    and kept); the result's ``rgba`` is the canvas, row 0 at the top.  BrowserError when
    Chromium fails or the page leaves no pixels, XIteMissing without X_ITE."""
    write_page(page_path, x3d_text, width, height, base_url, title, color_space, frames)
    result = browser.render_page(page_path, timeout=timeout, until_done=True)
    if result.rgba.shape[:2] != (height, width):
        raise browser.BrowserError(f"X_ITE drew {result.rgba.shape[1]}×{result.rgba.shape[0]}"
                                   f" pixels, not {width}×{height}", result.errors, result.title)
    return result


def render_file(path: str, width: int, height: int, page_path: str | None = None,
                color_space: str = "SRGB", timeout: float = 180,
                frames: int = 2) -> browser.PageResult:
    """Render the X3D / VRML file *path* with X_ITE (see :func:`render_text`); the page is
    *page_path* (default: ``<path>.x_ite.html`` beside the file)."""
    page_path = page_path or path + ".x_ite.html"
    return render_text(read_text(path), width, height, page_path, _file_url(path),
                       os.path.basename(path), color_space, timeout, frames)


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>phong: loading</title>
<style>
body { background: #444; color: #eee; font: 14px sans-serif; margin: 1em; }
#phong-view { display: block; box-sizing: content-box; width: @WIDTH@px; height: @HEIGHT@px;
              padding: 0; border: 0; margin: 0;
              background: repeating-conic-gradient(#777 0 25%, #999 0 50%) 0 0 / 16px 16px; }
#phong-errors { color: #f88; white-space: pre-wrap; }
#phong-errors:empty, #phong-pixels { display: none; }
</style>
</head>
<body>
<h1 id="phong-title">@TITLE@</h1>
<x3d-canvas id="phong-view" @ATTRIBUTES@></x3d-canvas>
<p>X_ITE @VERSION@ (MIT) &middot; Phong Nodes X_ITE peer renderer</p>
<pre id="phong-errors"></pre>
<pre id="phong-pixels" data-width="0" data-height="0"></pre>
<script>
@CAPTURE@
</script>
<script src="@SCRIPT@"></script>
<script type="application/json" id="phong-options">@OPTIONS@</script>
<script type="application/json" id="phong-x3d">@X3D@</script>
<script>
@RENDER@
</script>
</body>
</html>
"""

# Loads the file into X_ITE, waits until it is shown, then writes the pixels into the page.
_RENDER_JS = r"""
(async function () {
  "use strict";
  var report = window.phongReport, describe = window.phongDescribe;
  function fail(message) { throw new Error(message); }
  try {
    if (typeof X3D !== "function") { fail("X_ITE did not load (x_ite.min.js)"); }
    var options = JSON.parse(document.getElementById("phong-options").textContent);
    var text = JSON.parse(document.getElementById("phong-x3d").textContent);
    await X3D();
    var canvas = document.getElementById("phong-view");
    var browser = X3D.getBrowser(canvas);
    Object.keys(options.browser).forEach(function (name) {
      browser.setBrowserOption(name, options.browser[name]);
    });
    var scene = await browser.createX3DFromString(text);
    // A transparent background bound first: the alpha channel is the coverage.
    var background = scene.createNode("Background");
    background.transparency = 1;
    var roots = new X3D.MFNode(background);
    for (var i = 0; i < scene.rootNodes.length; i++) { roots.push(scene.rootNodes[i]); }
    scene.rootNodes = roots;
    await browser.replaceWorld(scene);
    var gl = browser.getContext();
    var width = options.width, height = options.height, waited = 0;
    function loading() {
      var count = browser._loadCount;
      return count && typeof count.getValue === "function" ? count.getValue() : 0;
    }
    while (loading() > 0 || gl.drawingBufferWidth !== width || gl.drawingBufferHeight !== height) {
      if (++waited > 600) {
        fail("X_ITE did not finish loading (" + loading() + " files left) or its drawing buffer is " +
             gl.drawingBufferWidth + " x " + gl.drawingBufferHeight + ", not " + width + " x " + height);
      }
      await browser.nextFrame();
    }
    for (var f = 0; f < options.frames; f++) { await browser.nextFrame(); }
    var wanted = options.browser;
    ["Shading", "ColorSpace"].forEach(function (name) {
      if (String(browser.getBrowserOption(name)).toUpperCase() !== String(wanted[name]).toUpperCase()) {
        fail("X_ITE's " + name + " is " + browser.getBrowserOption(name) + ", not " + wanted[name]);
      }
    });
    if (browser.getRenderingProperty("Multisampling") !== 0) {
      fail("X_ITE renders with " + browser.getRenderingProperty("Multisampling") + " samples");
    }
    window.phongWritePixels({getContext: function () { return gl; }}, width, height);
    document.title = "phong: done";
  } catch (error) {
    report("exception: " + describe(error));
    document.title = "phong: error";
  }
})();
"""
