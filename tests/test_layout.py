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
                     "core.scenes", "core.compare", "core.report", "core.outputs", "core.mtl",
                     "core.xmlsafe", "core.x3d", "core.collada", "core.fbx"):
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


#: The packages of ``core/`` from the ground up (docs/architecture.md): a module imports only
#: modules before it in its list (never one after it, nor the package's ``__init__``, which
#: imports them all and re-exports what callers use).  Every module of the folder is listed.
CORE_PACKAGES = {
    "x3d": ("numeric", "model", "context", "graph", "parse_classic", "parse_xml", "fields",
            "files", "protos", "geometry", "build", "flatten", "document", "phong", "write"),
    "collada": ("model", "context", "numbers", "geometry", "effects", "lights_cameras", "nodes",
                "read", "write"),
    "fbx": ("model", "read", "phong", "write"),
}
#: The most lines a module of ``core/`` may have (issue 44: one job a file).
CORE_MODULE_LINES = 1200


def _sibling_targets(path):
    """The modules of its own package that *path* imports (``from .x import y``, ``from . import
    x``), anywhere in the file (a function's import counts too)."""
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                yield node.module.split(".")[0]
            else:
                yield from (alias.name for alias in node.names)


def test_the_order_check_finds_what_it_should(tmp_path):
    (tmp_path / "low.py").write_text("from .high import x\n\ndef f():\n    from . import high\n")
    assert list(_sibling_targets(str(tmp_path / "low.py"))) == ["high", "high"]
    (tmp_path / "ok.py").write_text("from ..outputs import write_file\nimport os\n")
    assert list(_sibling_targets(str(tmp_path / "ok.py"))) == []


def test_core_packages_import_only_the_modules_below_them():
    bad = []
    for package, order in CORE_PACKAGES.items():
        folder = os.path.join(ROOT, "core", package)
        found = sorted(f[:-3] for f in os.listdir(folder)
                       if f.endswith(".py") and f != "__init__.py")
        assert found == sorted(order), f"core/{package}/ holds {found}, the order {order}"
        for index, module in enumerate(order):
            for name in _sibling_targets(os.path.join(folder, module + ".py")):
                if name not in order[:index]:
                    bad.append(f"core/{package}/{module}.py imports {name}")
    assert not bad, bad


def _class_methods(tree) -> set:
    """The names of the methods that the classes of a module define."""
    return {item.name for node in ast.walk(tree) if isinstance(node, ast.ClassDef)
            for item in node.body if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef))}


def _hidden_dependencies(sources: dict) -> list:
    """Where the modules of one package (*sources*: name → text, in the package's order)
    depend on a sibling without importing it, so that the order check above cannot see it:
    a class built on a class of a sibling module (the parts of a reader as mixins sharing
    ``self``), a call ``self.f(...)`` of a method that no class of the module defines (it
    lives in another module, reached through ``self``), and a call ``self.x.f(...)`` of a
    method that only modules later in the order define (an upward call through an object
    kept on ``self``, such as a reader handed to its parser)."""
    trees = {name: ast.parse(text, name) for name, text in sources.items()}
    methods = {name: _class_methods(tree) for name, tree in trees.items()}
    order = list(trees)
    found = []
    for index, (name, tree) in enumerate(trees.items()):
        siblings = {alias.asname or alias.name for node in ast.walk(tree)
                    if isinstance(node, ast.ImportFrom) and node.level == 1
                    for alias in node.names}
        earlier = set().union(*(methods[m] for m in order[:index + 1]))
        later = set().union(*(methods[m] for m in order[index + 1:]))
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef):
                found += [f"{name}: class {node.name} is built on {base.id}" for base in
                          node.bases if isinstance(base, ast.Name) and base.id in siblings]
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                attr, owner = node.func.attr, node.func.value
                if isinstance(owner, ast.Name) and owner.id == "self":
                    if attr not in methods[name]:
                        found.append(f"{name}:{node.lineno}: self.{attr}() is defined in no "
                                     "class of this module")
                elif (isinstance(owner, ast.Attribute) and isinstance(owner.value, ast.Name)
                      and owner.value.id == "self" and attr in later and attr not in earlier):
                    found.append(f"{name}:{node.lineno}: {ast.unparse(node.func)}() is a "
                                 "method of a later module")
    return found


def test_the_hidden_dependency_check_finds_what_it_should():
    sources = {
        "low": "class Part:\n    def read(self):\n        return self.build(1)\n\n"
               "class Parser:\n    def __init__(self, reader):\n        self.reader = reader\n\n"
               "    def header(self):\n        return self.reader.unit(2)\n",
        "high": "from .low import Part\n\nclass Reader(Part):\n    def build(self, x):\n"
                "        return x\n\n    def unit(self, x):\n        return self.build(x)\n",
    }
    found = _hidden_dependencies(sources)
    assert len(found) == 3, found
    assert any("self.build()" in f for f in found)
    assert any("self.reader.unit()" in f for f in found)
    assert any("class Reader is built on Part" in f for f in found)
    plain = {
        "low": "class Notes:\n    def add(self, x):\n        self.last = x\n\n"
               "def parse(ctx, text):\n    ctx.notes.add(text)\n    return text.split()\n\n"
               "class Parser:\n    def __init__(self, ctx):\n        self.ctx = ctx\n\n"
               "    def header(self):\n        self.ctx.notes.add(1)\n        return self.header\n",
        "high": "from .low import parse\n\ndef build(ctx, text):\n    return parse(ctx, text)\n",
    }
    assert _hidden_dependencies(plain) == []


def test_core_readers_hide_no_dependency():
    """The readers of ``core/`` hand one explicit reading context to plain functions: no
    mixins sharing ``self``, no call through ``self`` or through a handed-down reader into a
    module later in the order, so the order check above sees every dependency."""
    found = []
    for package, order in CORE_PACKAGES.items():
        folder = os.path.join(ROOT, "core", package)
        sources = {}
        for module in order:
            with open(os.path.join(folder, module + ".py"), encoding="utf-8") as handle:
                sources[module] = handle.read()
        found += [f"core/{package}/{line}" for line in _hidden_dependencies(sources)]
    assert not found, "dependencies the order check cannot see:\n" + "\n".join(found)


def _import_graph(root) -> dict:
    """{module: the modules of the package it imports}, by every relative import (also one
    inside a function), for the package at *root*; modules by dotted path from *root*
    (``addon.lighting.rig``; a package by its folder's path)."""
    modules = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d != "__pycache__" and not d.startswith(".venv")]
        for name in (f for f in files if f.endswith(".py")):
            rel = os.path.relpath(os.path.join(folder, name), root)[:-3].split(os.sep)
            if rel[0] in ("tests", "benchmarks", "tools"):
                continue
            modules[".".join(rel[:-1] if rel[-1] == "__init__" else rel)] = (
                os.path.join(folder, name), rel[-1] == "__init__")
    graph = {}
    for module, (path, is_package) in modules.items():
        package = module.split(".") if is_package else module.split(".")[:-1]
        if module == "":
            package = []
        found = set()
        for node in ast.walk(ast.parse(open(path, encoding="utf-8").read(), path)):
            if isinstance(node, ast.ImportFrom) and node.level:
                base = package[:len(package) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
                for alias in node.names:
                    full = f"{target}.{alias.name}" if target else alias.name
                    found.add(full if full in modules else target)
        graph[module] = {m for m in found if m in modules and m != module}
    return graph


def _import_circles(graph) -> list:
    """The circles of *graph* (its strongly connected parts of more than one module)."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                part = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    part.append(member)
                    if member == node:
                        break
                if len(part) > 1:
                    circles.append(sorted(part))
    return circles


def test_the_circle_check_finds_what_it_should(tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "cli" / "__init__.py").write_text("")
    (tmp_path / "cli" / "runs.py").write_text("def f():\n    from .apply import g\n")
    (tmp_path / "cli" / "apply.py").write_text("from .runs import f\nfrom ..core import x\n")
    (tmp_path / "cli" / "bake.py").write_text("from .runs import f\n")
    (tmp_path / "core").mkdir()
    (tmp_path / "core" / "__init__.py").write_text("")
    (tmp_path / "core" / "x.py").write_text("from . import y\n")
    (tmp_path / "core" / "y.py").write_text("import os\n")
    graph = _import_graph(str(tmp_path))
    assert graph["cli.apply"] == {"cli.runs", "core.x"} and graph["core.x"] == {"core.y"}
    assert _import_circles(graph) == [["cli.apply", "cli.runs"]]


def test_no_import_circle():
    """No module of the package imports, even inside a function, a module that imports it
    back, directly or around a longer circle: every dependency goes one way."""
    assert _import_circles(_import_graph(ROOT)) == []


def test_no_core_module_is_longer_than_its_limit():
    long = []
    for folder, _dirs, files in os.walk(os.path.join(ROOT, "core")):
        for name in (f for f in files if f.endswith(".py")):
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as handle:
                lines = sum(1 for _ in handle)
            if lines > CORE_MODULE_LINES:
                long.append(f"{os.path.relpath(path, ROOT)}: {lines} lines")
    assert not long, long


def test_the_architecture_names_every_core_module():
    """docs/architecture.md's core row names each module of ``core/``, and each package with its
    modules in their order: ``x3d/`` (`numeric`, `model`, ...)."""
    with open(os.path.join(ROOT, "docs", "architecture.md"), encoding="utf-8") as handle:
        text = handle.read()
    folder = os.path.join(ROOT, "core")
    missing = [f"`{name}`" for name in sorted(os.listdir(folder))
               if name.endswith(".py") and name != "__init__.py" and f"`{name}`" not in text]
    for package, order in CORE_PACKAGES.items():
        listed = re.search(rf"`{package}/` \(([^):]*)", text)   # up to a colon
        named = re.findall(r"`(\w+)`", listed.group(1)) if listed else []
        if named != list(order):
            missing.append(f"`{package}/` ({', '.join(order)}); the page has {named}")
    assert not missing, missing

def test_the_architecture_names_every_module():
    """docs/architecture.md names every module of the package (issue 44: the map had gone
    stale): each file in backticks, by its name, or by its room and name where two rooms
    have a file of that name (``lighting/forwarding.py``)."""
    with open(os.path.join(ROOT, "docs", "architecture.md"), encoding="utf-8") as handle:
        text = handle.read()
    paths = []
    for top in ("node_groups", "core", "addon", "cli"):
        for folder, _dirs, files in os.walk(os.path.join(ROOT, top)):
            if "__pycache__" in folder:
                continue
            paths += [os.path.relpath(os.path.join(folder, f), ROOT) for f in files
                      if f.endswith(".py") and f != "__init__.py"]
    names = [os.path.basename(p) for p in paths]
    missing = []
    for path in sorted(paths):
        name = os.path.basename(path)
        if os.path.basename(os.path.dirname(path)) in CORE_PACKAGES:
            continue  # named with their package (test above)
        room = os.path.basename(os.path.dirname(path))
        wanted = f"`{name}`" if names.count(name) == 1 else f"`{room}/{name}`"
        if wanted not in text:
            missing.append(f"{path} (as {wanted})")
    assert not missing, missing


# -- sockets by identifier, never by position (issue 37) -----------------------------------

SOCKET_COLLECTIONS = {"inputs", "outputs"}
#: Owners of ``inputs`` / ``outputs`` that are the library's own data, not Blender nodes: a
#: group definition's socket specs (node_groups/library.py) and an operation's identifiers.
DATA_OWNERS = {"definition", "op"}


def _positional_socket_access(source: str, path: str) -> list:
    """Where *source* reaches a node's socket by position: ``x.inputs[0]``, ``x.outputs[-1]``,
    ``x.inputs[:3]``, ``x.inputs[i + 1]``, ``list(x.outputs)[0]``, ``zip(x.inputs, ...)`` or
    ``enumerate(x.outputs)`` (pairing sockets with positions).  A string, a name or an
    attribute as the key (an identifier or an interface name) is allowed."""
    found = []

    def collection(node):
        if isinstance(node, ast.Attribute) and node.attr in SOCKET_COLLECTIONS:
            return not (isinstance(node.value, ast.Name) and node.value.id in DATA_OWNERS)
        return (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id in ("list", "tuple") and node.args
                and collection(node.args[0]))

    for node in ast.walk(ast.parse(source, path)):
        if isinstance(node, ast.Subscript) and collection(node.value):
            key = node.slice
            numeric = isinstance(key, ast.Slice) or (
                isinstance(key, ast.Constant) and isinstance(key.value, int)) or (
                isinstance(key, ast.UnaryOp) and isinstance(key.operand, ast.Constant)) or (
                isinstance(key, ast.BinOp))
            if numeric:
                found.append(f"{path}:{node.lineno}: {ast.unparse(node)}")
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
              and node.func.id in ("zip", "enumerate")
              and any(collection(arg) for arg in node.args)):
            found.append(f"{path}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_the_positional_socket_check_finds_what_it_should():
    bad = ("a = node.inputs[0]\nb = node.outputs[-1]\nfor s in node.inputs[:3]: pass\n"
           "c = list(node.outputs)[1]\nd = node.inputs[k + 1]\n"
           "for s, v in zip(node.inputs, values): pass\nfor i, s in enumerate(n.outputs): pass\n")
    assert len(_positional_socket_access(bad, "bad.py")) == 7
    good = ('a = node.inputs["Value_001"]\nb = node.outputs[name]\nc = node.inputs[spec.name]\n'
            'for s in node.inputs: pass\n')
    assert _positional_socket_access(good, "good.py") == []


def test_no_socket_is_reached_by_position():
    """Blender 5.3 inserted sockets before existing ones (Vector Transform's LightIndex):
    ``addon/`` and ``node_groups/`` reach sockets by identifier, through ``compat``."""
    found = []
    for package in ("addon", "node_groups"):
        for folder, _dirs, files in os.walk(os.path.join(ROOT, package)):
            for name in files:
                if name.endswith(".py"):
                    path = os.path.join(folder, name)
                    found += _positional_socket_access(open(path, encoding="utf-8").read(),
                                                       os.path.relpath(path, ROOT))
    assert not found, "sockets reached by position:\n" + "\n".join(found)


# -- product text explains itself: no tracker numbers ----------------------------------------

#: A tracker reference: "issue 43", "Issues 5-38", "issue #30", also broken across two lines.
TRACKER_NUMBER = re.compile(r"\bissues?\s*#?\d+", re.I)


def _product_text_files():
    """The files a user or a reader of the code gets: the package's Python outside tests/ and
    benchmarks/, the demo scenes, the docs and the README."""
    for path in _python_files():
        if os.path.relpath(path, ROOT).split(os.sep)[0] not in ("tests", "benchmarks"):
            yield path
    for folder, suffix in (("scenes", ".toml"), ("docs", ".md")):
        yield from sorted(os.path.join(ROOT, folder, f)
                          for f in os.listdir(os.path.join(ROOT, folder)) if f.endswith(suffix))
    yield os.path.join(ROOT, "README.md")


def test_no_product_text_cites_an_issue_number():
    """Code, scenes and docs state the reason or the measurement, not the tracker's number
    for it (a reader has no tracker; a demo sheet's subtitle is read by users)."""
    found = []
    for path in _product_text_files():
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
        lines = text.splitlines()
        for match in TRACKER_NUMBER.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            found.append(f"{os.path.relpath(path, ROOT)}:{number}: {lines[number - 1].strip()}")
    assert not found, "issue numbers in product text:\n" + "\n".join(found)


def _is_model(node) -> bool:
    """Whether *node* names a scene's lighting model: ``model``, ``self.model``,
    ``data["model"]``, ``scene.get("model")``."""
    if isinstance(node, ast.Name):
        return node.id == "model"
    if isinstance(node, ast.Attribute):
        return node.attr == "model"
    if isinstance(node, ast.Subscript):
        return isinstance(node.slice, ast.Constant) and node.slice.value == "model"
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
        return node.func.attr == "get" and bool(node.args) and \
            isinstance(node.args[0], ast.Constant) and node.args[0].value == "model"
    return False


def _model_comparisons(source: str) -> list:
    """The line numbers of comparisons of a lighting model by name (``model == "x3d"``,
    ``data["model"] != "threejs"``, ``model in ("seeds", ...)``) in *source*."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare) and any(
                isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops) \
                and any(_is_model(side) for side in [node.left, *node.comparators]):
            lines.append(node.lineno)
    return lines


def test_the_model_comparison_count_finds_what_it_should():
    found = _model_comparisons('if model == "x3d": pass\nx = self.model != "seeds"\n'
                               'y = data["model"] in NAMES\nz = s.get("model") == "threejs"\n'
                               'ok = models.get(name).native\nw = kind == "x3d"\n')
    assert found == [1, 2, 3, 4]


def test_no_exporter_or_core_module_asks_for_a_lighting_model_by_name():
    """What a lighting model means outside Blender (its reference, its X3D, FBX and three.js
    values) is its object's (``node_groups/models.py``): the exporters and ``core/`` ask the
    model, never compare its name."""
    found = []
    for folder in (os.path.join(ROOT, "addon", "interchange"), os.path.join(ROOT, "core")):
        for here, _dirs, files in os.walk(folder):
            for name in (f for f in files if f.endswith(".py")):
                path = os.path.join(here, name)
                with open(path, encoding="utf-8") as handle:
                    found += [f"{os.path.relpath(path, ROOT)}:{line}"
                              for line in _model_comparisons(handle.read())]
    assert found == [], found


# -- one writer of the Phong material: its control nodes are named in the recipe alone -------

RECIPE = os.path.join(ROOT, "addon", "lighting", "recipe.py")
#: The Phong material's modules in their order: each imports only the ones before it (what it
#: is, what its outputs show, its opacity, its writer, its reader, its source).
MATERIAL_MODULES = ("recipe", "engine_outputs", "opacity", "writer", "feeds", "sources")
#: Product strings spelt like a control node but meaning something else: the World's ambient
#: colour is a custom property of the World (lighting/properties.py), not a node.
OTHER_MEANINGS = {(os.path.join("addon", "lighting", "properties.py"), "phong_ambient_color")}


def _control_names(source: str) -> set:
    """The control node names the recipe lists: the keys of ``CONTROLS`` and the names
    assigned to ``AMBIENT_CONTROL`` and ``OPACITY``, read from *source* (recipe.py's text)."""
    names = set()
    for node in ast.parse(source).body:
        if not isinstance(node, ast.Assign) or not isinstance(node.targets[0], ast.Name):
            continue
        target = node.targets[0].id
        if target == "CONTROLS" and isinstance(node.value, ast.Dict):
            names |= {key.value for key in node.value.keys}
        elif target in ("AMBIENT_CONTROL", "OPACITY") and isinstance(node.value, ast.Constant):
            names.add(node.value.value)
    return names


def _control_spellings(source: str, path: str, names) -> list:
    """Where *source* spells one of *names* as a string of its own (a node looked up or made
    by its name): ``tree.nodes["phong_exponent"]``, ``{"phong_blinn": ...}``."""
    return [f"{path}:{node.lineno}: {node.value}" for node in ast.walk(ast.parse(source, path))
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and node.value in names]


def test_the_control_name_count_finds_what_it_should():
    names = _control_names('CONTROLS = {"phong_a": 1, "phong_b": 2}\nAMBIENT_CONTROL = "phong_c"\n'
                           'OPACITY = "phong_d"\nOTHER = "phong_e"\n')
    assert names == {"phong_a", "phong_b", "phong_c", "phong_d"}
    bad = 'x = tree.nodes["phong_a"]\ny = {"phong_c": 1}\nz = f"{a}"\n"""phong_b in prose"""\n'
    assert len(_control_spellings(bad, "bad.py", names)) == 2


def test_only_the_recipe_names_the_control_nodes():
    """Importers, the demos and every other module hand the writer (``lighting/writer.py``)
    values by the lights group's input names; the control nodes' names ("phong_exponent",
    ...) are spelt in ``lighting/recipe.py`` alone: 0 elsewhere in product code."""
    names = _control_names(open(RECIPE, encoding="utf-8").read())
    assert {"phong_object_color", "phong_exponent", "phong_blinn", "phong_opacity"} <= names
    found = []
    for path in _product_text_files():
        relative = os.path.relpath(path, ROOT)
        if not path.endswith(".py") or os.path.abspath(path) == os.path.abspath(RECIPE):
            continue
        found += [hit for hit in _control_spellings(open(path, encoding="utf-8").read(),
                                                    relative, names)
                  if (relative, hit.rsplit(": ", 1)[1]) not in OTHER_MEANINGS]
    assert len(found) == 0, "control nodes named outside the recipe:\n" + "\n".join(found)


def test_the_material_modules_import_only_the_ones_before_them():
    folder = os.path.join(ROOT, "addon", "lighting")
    bad = []
    for index, name in enumerate(MATERIAL_MODULES):
        for target in _sibling_targets(os.path.join(folder, name + ".py")):
            if target in MATERIAL_MODULES and MATERIAL_MODULES.index(target) >= index:
                bad.append(f"lighting/{name}.py imports {target}")
    assert not bad, bad
