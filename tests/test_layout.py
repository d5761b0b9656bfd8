# SPDX-License-Identifier: GPL-3.0-or-later
"""The folders state the dependency rule: ``node_groups`` and ``core`` never import ``bpy``
(nor the Blender layer), and the package imports in a Python where ``import bpy`` fails."""

import ast
import os
import subprocess
import sys

import phong_nodes

ROOT = os.path.dirname(phong_nodes.__file__)
PURE = ("node_groups", "core")
BLENDER_ONLY = {"bpy", "bmesh", "mathutils", "addon_utils", "gpu", "bl_math"}

NO_BPY = """
import importlib, pkgutil, sys
sys.modules["bpy"] = None          # `import bpy` raises ImportError from here on
import phong_nodes
names = []
for package in ("node_groups", "core"):
    module = importlib.import_module(f"phong_nodes.{package}")
    for info in pkgutil.iter_modules(module.__path__):
        importlib.import_module(f"phong_nodes.{package}.{info.name}")
        names.append(f"{package}.{info.name}")
try:
    import bpy
except ImportError:
    pass
else:
    raise SystemExit("bpy imported")
loaded = sorted(m for m in sys.modules if m.startswith("phong_nodes.addon"))
print(" ".join(names) if not loaded else "LOADED " + " ".join(loaded))
"""


def test_pure_packages_import_where_bpy_cannot():
    result = subprocess.run([sys.executable, "-c", NO_BPY], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
    names = result.stdout.split()
    assert "LOADED" not in names, result.stdout
    for expected in ("node_groups.expr", "node_groups.library", "node_groups.reference",
                     "core.scenes", "core.compare", "core.report", "core.outputs", "core.mtl"):
        assert expected in names, f"{expected} missing from {names}"


def _imports(path):
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, 0
        elif isinstance(node, ast.ImportFrom):
            yield node.module or "", node.level


def test_no_pure_module_imports_blender_or_the_blender_layer():
    bad = []
    for package in PURE:
        for folder, _dirs, files in os.walk(os.path.join(ROOT, package)):
            for name in files:
                if not name.endswith(".py"):
                    continue
                path = os.path.join(folder, name)
                for module, level in _imports(path):
                    top = module.split(".")[0]
                    if (level == 0 and top in BLENDER_ONLY) or (level >= 2 and top == "addon"):
                        bad.append(f"{os.path.relpath(path, ROOT)}: {module}")
    assert not bad, bad


def test_extension_modules_use_relative_imports_only():
    """Blender's extension rules: the package must not import itself by an absolute name."""
    bad = []
    for package in PURE + ("addon",):
        for folder, _dirs, files in os.walk(os.path.join(ROOT, package)):
            for name in (f for f in files if f.endswith(".py")):
                path = os.path.join(folder, name)
                bad += [f"{os.path.relpath(path, ROOT)}: {module}" for module, level in
                        _imports(path) if level == 0 and module.split(".")[0] in
                        ("phong_nodes", "addon", "core", "node_groups")]
    assert not bad, bad
