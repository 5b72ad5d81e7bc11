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

Each checker is a function of a source tree (tools/architecture.py), so the
tests at the end also show it failing on a small tree that breaks its rule.
"""
import importlib
import importlib.util
import pathlib
import sys
import warnings

import pytest

import libkin
from libkin import _compat

# The checkers are tools/architecture.py's (it also checks the layers of the
# C library and of these subpackages, ctest `architecture`): one import graph.
_spec = importlib.util.spec_from_file_location(
    "architecture", pathlib.Path(__file__).resolve().parents[2] / "tools" / "architecture.py")
architecture = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(architecture)
SRC = architecture.SRC
MAX_LINES = architecture.MAX_LINES
import_graph, circles = architecture.import_graph, architecture.circles
long_modules, private_uses = architecture.long_modules, architecture.private_uses


# ---- the package ------------------------------------------------------------

def test_no_import_circle():
    graph = import_graph(SRC)
    assert len(graph) > 40 and "libkin.atlas.explorer" in graph["libkin.atlas"]
    assert circles(graph) == []


def test_no_long_module():
    assert long_modules(SRC) == []


def test_studies_use_the_public_api_only():
    assert private_uses(SRC) == []


def test_studies_do_not_import_the_package_root():
    # each name from the public module that defines it (libkin.assembly,
    # libkin.version, ...), never `libkin` itself: the root imports
    # everything, so an import of it puts the whole package under a study
    graph = import_graph(SRC)
    studies = [m for m in graph if m == "libkin.studies" or m.startswith("libkin.studies.")]
    assert len(studies) > 10
    assert [m for m in studies if "libkin" in graph[m]] == []


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


def test_checker_measures_c_functions():
    body = "    x += 1;\n" * 130
    text = ("/* a comment { with braces } */\nstruct s { int a; };\nstatic const int t[] = {1, 2};\n"
            "static int short_one(int x)\n{\n    const char *c = \"}{\";\n    return x + '{';\n}\n"
            "int long_one(int x)\n{\n" + body + "    return x;\n}\n")
    found = {name: (line, n) for name, line, n in architecture.c_functions(text)}
    assert set(found) == {"short_one", "long_one"}
    assert found["short_one"] == (5, 4) and found["long_one"] == (10, 133)


def test_no_long_c_function():
    # the limit and the ratchet of tools/architecture.py (ctest `architecture` checks it too)
    assert architecture.long_functions() == []
    follow = (pathlib.Path(architecture.ROOT) / "libkin" / "branches" / "follow.c").read_text()
    assert max(n for _, _, n in architecture.c_functions(follow)) <= architecture.MAX_FUNCTION_LINES
