"""The package's layout (libkin/__init__.py lists the layers):

(a) no import circle between modules: every ``import`` and ``from ... import``
    anywhere in a module (module level, in a function, under TYPE_CHECKING;
    relative or absolute) is an edge to the module it names (``from P import
    x`` is an edge to the submodule P.x when there is one, else to P); a
    package's __init__ importing its own submodules is fine, a submodule
    importing its package (or a sibling) that imports it back is a circle;
(b) no module over 500 lines (the generated _native/_cdef.py aside);
(c) libkin.studies uses only the public API: no private module (a dotted
    part starting with "_") and no private name is imported, nor read as an
    attribute of something imported from libkin;
(d) every old flat module name of the alias table (libkin._compat.ALIASES)
    still imports, with a DeprecationWarning naming the importer, and is the
    new module itself.

Each checker is a function of a source tree, so the tests at the end also
show it failing on a small tree that breaks its rule.
"""
import ast
import importlib
import pathlib
import sys
import warnings
from typing import Dict, List, Set, Tuple

import pytest

import libkin
from libkin import _compat

SRC = pathlib.Path(__file__).resolve().parents[1] / "src"
MAX_LINES = 500
GENERATED = {"libkin._native._cdef"}


def modules(src: pathlib.Path, package: str = "libkin") -> Dict[str, pathlib.Path]:
    """Dotted module name -> file, for every .py of the package (a package is its __init__.py)."""
    out = {}
    for f in sorted((src / package).rglob("*.py")):
        parts = list(f.relative_to(src).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = f
    return out


def _is_package(name: str, mods: Dict[str, pathlib.Path]) -> bool:
    return mods[name].name == "__init__.py"


def imports(name: str, mods: Dict[str, pathlib.Path]) -> List[Tuple[str, List[str], int]]:
    """(resolved module, imported names, line) of every import statement of module `name`."""
    tree = ast.parse(mods[name].read_text(), str(mods[name]))
    here = name if _is_package(name, mods) else name.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name, [], node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here.split(".")
                base = base[:len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            out.append((target, [a.name for a in node.names], node.lineno))
    return out


def import_graph(src: pathlib.Path, package: str = "libkin") -> Dict[str, Set[str]]:
    """module -> the modules of the package it imports (see the module docstring)."""
    mods = modules(src, package)
    graph: Dict[str, Set[str]] = {m: set() for m in mods}
    for m in mods:
        for target, names, _ in imports(m, mods):
            if target != package and not target.startswith(package + "."):
                continue
            subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in mods]
            if subs:
                graph[m].update(subs)
            if len(subs) < len(names) or not names:
                # a name of the module itself (or `import a.b.c`: the deepest module named)
                t = target
                while t not in mods and "." in t:
                    t = t.rpartition(".")[0]
                if t in mods:
                    graph[m].add(t)
        graph[m].discard(m)
    return graph


def circles(graph: Dict[str, Set[str]]) -> List[List[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: Dict[str, int] = {}
    low: Dict[str, int] = {}
    stack: List[str] = []
    on: Set[str] = set()
    out: List[List[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10000))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def long_modules(src: pathlib.Path, package: str = "libkin", limit: int = MAX_LINES) -> List[str]:
    return [f"{m}: {len(f.read_text().splitlines())} lines" for m, f in modules(src, package).items()
            if m not in GENERATED and len(f.read_text().splitlines()) > limit]


def _private(part: str) -> bool:
    return part.startswith("_") and not (part.startswith("__") and part.endswith("__"))


def private_uses(src: pathlib.Path, package: str = "libkin", app: str = "studies") -> List[str]:
    """Private modules or names the application package imports from the library (or reads off it)."""
    mods = modules(src, package)
    bad = []
    for m in (m for m in mods if m == f"{package}.{app}" or m.startswith(f"{package}.{app}.")):
        lib_names: Set[str] = set()
        for target, names, line in imports(m, mods):
            if target != package and not target.startswith(package + "."):
                continue
            if any(_private(p) for p in target.split(".")):
                bad.append(f"{m}:{line}: imports the private module {target}")
            for n in names:
                if _private(n):
                    bad.append(f"{m}:{line}: imports the private name {target}.{n}")
        tree = ast.parse(mods[m].read_text())
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                mod = node.module or "" if isinstance(node, ast.ImportFrom) else ""
                if isinstance(node, ast.ImportFrom) and not node.level and not mod.startswith(package):
                    continue
                for a in node.names:
                    if isinstance(node, ast.Import) and not a.name.startswith(package):
                        continue
                    lib_names.add((a.asname or a.name).split(".")[0])
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and _private(node.attr) and isinstance(node.value, ast.Name)
                    and node.value.id in lib_names):
                bad.append(f"{m}:{node.lineno}: reads the private name {node.value.id}.{node.attr}")
    return bad


# ---- the package ------------------------------------------------------------

def test_no_import_circle():
    graph = import_graph(SRC)
    assert len(graph) > 40 and "libkin.atlas.explorer" in graph["libkin.atlas"]
    assert circles(graph) == []


def test_no_long_module():
    assert long_modules(SRC) == []


def test_studies_use_the_public_api_only():
    assert private_uses(SRC) == []


# where the code of each old flat module went (kept here independently of the table)
MOVED = {
    "model_json": "io.model_json", "fold": "io.fold", "atlas_index": "atlas.index", "atlas_tasks": "atlas.tasks",
    "atlas_cli": "atlas.cli", "atlas_condense": "atlas.condense", "atlas_orbits": "atlas.orbits",
    "atlas_plot": "atlas.plot", "atlas_report": "atlas.report", "automorphisms": "symmetry.automorphisms",
    "homotopy_shards": "homotopy.shards", "sailstudy": "studies.sailstudy", "squarestudy": "studies.squarestudy",
    "sailmap": "studies.sailmap", "sailmeasure": "studies.sailmeasure", "studyfigures": "studies.studyfigures",
    "studyreport": "studies.studyreport", "draw3d": "plot.draw3d",
    "_cdef": "_native._cdef", "_lib": "_native._lib", "_arrays": "_native._arrays", "_progress": "_native._progress",
    "_startup": "_native._startup", "_base": "assembly._base", "_path": "assembly._path",
    "_locating": "assembly._locating", "_branching": "assembly._branching",
}


def test_alias_table():
    assert _compat.ALIASES == {f"libkin.{k}": f"libkin.{v}" for k, v in MOVED.items()}
    for old in MOVED:  # one table, no stub files
        assert not (SRC / "libkin" / f"{old}.py").exists()


@pytest.mark.parametrize("old", sorted(_compat.ALIASES))
def test_old_module_names(old):
    new = _compat.ALIASES[old]
    target = importlib.import_module(new)
    sys.modules.pop(old, None)
    parent, _, attr = old.rpartition(".")
    vars(sys.modules[parent]).pop(attr, None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mod = importlib.import_module(old)
    assert mod is target
    assert mod.__name__ == new and mod.__spec__.name == new  # the new module, untouched
    dep = [w for w in caught if issubclass(w.category, DeprecationWarning)]
    assert len(dep) == 1 and old in str(dep[0].message) and new in str(dep[0].message)
    assert getattr(sys.modules[parent], attr) is target


def test_old_names_by_attribute_and_from_import():
    for old in ("libkin.fold", "libkin.automorphisms"):
        sys.modules.pop(old, None)
        vars(libkin).pop(old.rpartition(".")[2], None)
    with pytest.warns(DeprecationWarning, match="libkin.fold is deprecated") as rec:
        from libkin import fold
    assert rec[0].filename == __file__  # the warning names the importer
    assert fold is importlib.import_module("libkin.io.fold") and fold.read_fold is libkin.io.fold.read_fold
    with pytest.warns(DeprecationWarning, match="libkin.automorphisms"):
        assert libkin.automorphisms.mechanism_group is libkin.symmetry.mechanism_group
    with pytest.raises(AttributeError):
        libkin.no_such_module  # noqa: B018


def test_top_level_names():
    for name in libkin.__all__:
        assert getattr(libkin, name) is not None
    assert libkin.Assembly is libkin.assembly.Assembly
    assert libkin.explore is libkin.atlas.explore


# ---- each checker fails on a tree that breaks its rule -------------------------

def _tree(tmp_path, files):
    for rel, text in files.items():
        f = tmp_path / "pkg" / rel
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
    return tmp_path


def test_checker_finds_circles(tmp_path):
    src = _tree(tmp_path, {
        "__init__.py": "from .a import A\n",
        "a.py": "def A():\n    from .b import B  # a function-level import counts\n",
        "b.py": "from pkg.a import A as B\n",
        "sub/__init__.py": "from .c import C\n",         # a package importing its submodule: fine
        "sub/c.py": "C = 1\n",
        "sub/d.py": "from . import c\nfrom pkg import sub\n",  # d -> sub -> c: fine (sub does not import d)
        "sub/e.py": "from . import f\n",
        "sub/f.py": "import pkg.sub.e\n",
        "g/__init__.py": "from .h import H\n",
        "g/h.py": "from pkg.g import H2\nH = 1\n",          # a submodule importing back its package
    })
    found = circles(import_graph(src, "pkg"))
    assert ["pkg.a", "pkg.b"] in found and ["pkg.sub.e", "pkg.sub.f"] in found and ["pkg.g", "pkg.g.h"] in found
    assert len(found) == 3


def test_checker_finds_long_modules(tmp_path):
    src = _tree(tmp_path, {"__init__.py": "", "long.py": "x = 1\n" * (MAX_LINES + 1), "ok.py": "x = 1\n" * MAX_LINES})
    assert long_modules(src, "pkg") == [f"pkg.long: {MAX_LINES + 1} lines"]


def test_checker_finds_private_uses(tmp_path):
    src = _tree(tmp_path, {
        "__init__.py": "", "_native/__init__.py": "", "_native/_lib.py": "", "atlas.py": "_x = 1\n",
        "studies/__init__.py": "",
        "studies/ok.py": "from pkg import atlas\nfrom . import ok2\nimport numpy as np\nnp._x\n",
        "studies/bad.py": "from pkg._native import _lib\nfrom pkg.atlas import _x\nfrom .. import atlas\n"
                          "def f():\n    return atlas._x\n",
    })
    bad = private_uses(src, "pkg")
    assert len(bad) == 4 and all(b.startswith("pkg.studies.bad:") for b in bad)
