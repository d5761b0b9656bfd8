# SPDX-License-Identifier: GPL-3.0-or-later
"""The folders state the dependency rule: ``node_groups`` and ``core`` never import ``bpy``
(nor the Blender layer), and the package imports in a Python where ``import bpy`` fails."""

import ast
import os
import re
import subprocess
import sys
import tomllib

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
    for package in PURE + ("addon", "cli"):
        for folder, _dirs, files in os.walk(os.path.join(ROOT, package)):
            for name in (f for f in files if f.endswith(".py")):
                path = os.path.join(folder, name)
                bad += [f"{os.path.relpath(path, ROOT)}: {module}" for module, level in
                        _imports(path) if level == 0 and module.split(".")[0] in
                        ("phong_nodes", "addon", "core", "node_groups")]
    assert not bad, bad


def _python_files():
    skip = {".git", "__pycache__", "node_modules"}
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in skip and not d.startswith(".venv")]
        yield from (os.path.join(folder, f) for f in files if f.endswith(".py"))


def test_nothing_edits_sys_path_or_loads_a_module_by_path():
    """Every module is imported by its package name (``pip install -e .``): no ``sys.path``
    edit, no ``spec_from_file_location`` / ``SourceFileLoader`` / ``runpy.run_path``."""
    pattern = re.compile(r"sys\.path\.(insert|append|extend)|sys\.path\s*[+]?=|"
                         r"spec_from_file_location|SourceFileLoader|run_path\(")
    bad = [f"{os.path.relpath(path, ROOT)}:{number}" for path in _python_files()
           if os.path.abspath(path) != os.path.abspath(__file__)  # the pattern itself
           for number, line in enumerate(open(path, encoding="utf-8"), 1)
           if pattern.search(line)]
    assert not bad, bad


def test_one_package_one_command_one_version():
    """pyproject.toml makes the tree the package ``phong_nodes`` with the ``phong`` command;
    its version is the extension's, and every sub-package of the tree is in its list."""
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as handle:
        project = tomllib.load(handle)
    with open(os.path.join(ROOT, "blender_manifest.toml"), "rb") as handle:
        manifest = tomllib.load(handle)
    assert project["project"]["version"] == manifest["version"]
    assert project["project"]["scripts"]["phong"] == "phong_nodes.cli:console"
    listed = set(project["tool"]["setuptools"]["packages"])
    found = {"phong_nodes" + ("." + os.path.relpath(folder, ROOT).replace(os.sep, ".")
                              if folder != ROOT else "")
             for folder, _dirs, files in os.walk(ROOT) if "__init__.py" in files
             and not os.path.relpath(folder, ROOT).split(os.sep)[0] in ("tests", "benchmarks",
                                                                       "tools")
             and ".venv" not in folder and "node_modules" not in folder}
    assert found == listed, (sorted(found - listed), sorted(listed - found))


def test_the_phong_command_lists_its_subcommands():
    """The installed command (``.venv/bin/phong``) answers --help, naming every subcommand."""
    phong = os.path.join(os.path.dirname(sys.executable), "phong")
    result = subprocess.run([phong, "--help"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    for command in ("demo", "compare", "bake", "report", "slurm", "cluster", "which"):
        assert re.search(rf"^\s+{command}\s", result.stdout, re.M), result.stdout
    which = subprocess.run([phong, "which"], capture_output=True, text=True, timeout=60)
    assert which.returncode == 0 and which.stdout.startswith("bpy "), which.stdout


#: The rooms of the Blender layer from the ground up (docs/architecture.md): a room imports
#: only rooms before it in this list, never one after it.
ADDON_ROOMS = ("compat", "loader", "lighting", "shading", "scene", "interchange", "baking",
               "comparison", "demos", "ui")


def _addon_targets(path, depth):
    """The addon-level names that the module *path* (*depth* folders below addon/) imports:
    ``from ..lighting import x`` gives lighting, ``from .. import loader`` gives loader."""
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == depth + 1:
            if node.module:
                yield node.module.split(".")[0]
            else:
                yield from (alias.name for alias in node.names)


def test_addon_rooms_import_only_the_rooms_below_them():
    bad = []
    for index, room in enumerate(ADDON_ROOMS):
        folder = os.path.join(ROOT, "addon", room)
        files = ([os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".py")]
                 if os.path.isdir(folder) else [folder + ".py"])
        for path in files:
            for name in _addon_targets(path, 1 if os.path.isdir(folder) else 0):
                if name in ADDON_ROOMS and ADDON_ROOMS.index(name) > index:
                    bad.append(f"addon/{room}/{os.path.basename(path)} imports {name}")
    assert not bad, bad
