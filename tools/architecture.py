#!/usr/bin/env python3
"""The layers of libkin, checked against the code (docs/architecture.md).

  architecture.py check [--build DIR]   fail on a circle between files or a
                                        dependency that goes up a layer (or,
                                        inside a folder, up a sub-layer)
  architecture.py stats [--build DIR]   folders, largest files, depth, circles
  architecture.py picture OUT.png       the layer picture of docs/architecture.md

C: a file depends on another when it includes one of its headers (from the
sources) or calls a function the other defines (from the symbols of the
built objects, `nm`, when --build is given: an include alone misses a call
declared in a shared header). A large folder is split into subfolders
(libkin/homotopy/track/), layered in their turn (C_SUBLAYERS). Python: a
module depends on every module it imports, at the top or inside a function
(a lazy import that closes a circle is still a circle). Standard library
only, but for the picture (matplotlib).
"""
import argparse
import ast
import collections
import os
import re
import pathlib
import subprocess
import sys
from typing import Dict, List, Set, Tuple

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The C layers, lowest first: a folder may use only folders of a lower layer
# (and itself). The one place this order is written; docs/architecture.md
# explains it.
C_LAYERS = [
    ["model"],                                # the handle, options, status, the SVD analysis (paper 2-3.1)
    ["contact"],                              # panels, thickness, clearance between parts (issue 23)
    ["path", "io", "symmetry", "homotopy"],   # following (3.2), files, symmetry, complete solver (3.4)
    ["locate"],                               # detection and location (4)
    ["branches"],                             # second order, branch paths, follow to event (3.3-3.4, 5)
]
# The layers inside a folder split into subfolders, lowest first: a file of
# a subfolder may use only files of its own subfolder or of a lower
# sub-layer; TOP stands for the files directly in the folder (its entry
# points), the highest. docs/architecture.md explains each subfolder.
TOP = ""
C_SUBLAYERS = {
    "homotopy": [
        ["track", "certify"],  # the one-path tracker and certificate, its kernels, LU, Pade, lockstep lanes | interval proofs (Arb)
        ["param", "solver"],   # the parameter tracker (and its lanes) | set-up, thread pool, runs, checks, merge
        ["symmetric"],         # the symmetric solver: group, equivariant start, monodromy (uses both above)
        [TOP],                 # homotopy/*.c: the entry points (plain, symmetric, orbit ranges)
    ],
}
# The Python layers, lowest first, by subpackage (or top-level module) of
# the libkin package: a module may import from its own layer or below, never
# above, and no two modules may import each other, even through others.
PY_LAYERS = [
    ["_native", "errors", "_compat", "parallel", "shared", "atomic", "_bounded", "version", "_lifeline"],  # cffi, exceptions, executors,
    # arrays shared with the workers, writes, reads
    ["assembly"],                                   # Assembly: analysis, paths, location, branches
    ["io", "homotopy", "symmetry", "plot", "cliargs"],
    ["atlas"],                                      # libkin.explore
    ["studies"],                                    # the sail study application (public modules only, never the root)
    ["__init__"],                                   # the package root: the public API
    ["cli"],
    ["__main__"],
]


def layer_of(layers, group):
    for i, names in enumerate(layers):
        if group in names:
            return i
    return None


# ---------------------------------------------------------------- C ----

def c_files():
    """the library's sources, "folder/file" or "folder/subfolder/file" (a file
    directly in libkin/, as in the flat layout before 0.3, is "./file")"""
    base = os.path.join(ROOT, "libkin")
    out = []
    for folder in sorted(os.listdir(base)):
        d = os.path.join(base, folder)
        if os.path.isdir(d):
            for sub, dirs, names in os.walk(d):
                dirs.sort()
                rel = os.path.relpath(sub, base).replace(os.sep, "/")
                out += [f"{rel}/{f}" for f in sorted(names) if f.endswith((".c", ".h"))]
        elif folder.endswith((".c", ".h")):
            out.append(f"./{folder}")
    return sorted(out)


def c_folder(f):
    """the top folder of a source ("homotopy" for "homotopy/track/x.c")"""
    return f.split("/")[0]


def c_subfolder(f):
    """the subfolder of a source within its folder ("track" for
    "homotopy/track/x.c"), TOP for a file directly in the folder"""
    parts = f.split("/")
    return parts[1] if len(parts) > 2 else TOP


def c_subfolders():
    """every subfolder that holds sources, "folder/subfolder" """
    return sorted({"/".join(f.split("/")[:2]) for f in c_files() if len(f.split("/")) > 2})


def c_graph(build):
    """nodes: the files of libkin/ ("path/step_lu.c", "path/path.h"); edges:
    a file to each private header it includes, and (from --build's objects)
    a .c to each .c that defines a function it calls"""
    files = c_files()
    edges = collections.defaultdict(set)
    why = collections.defaultdict(set)
    # a private header by its path from libkin/ ("homotopy/track/x.h"), or
    # by its bare name from its own folder
    inc = re.compile(r'#\s*include\s+"((?:[a-z_]+/)*)([A-Za-z0-9_]+\.h)"')
    for f in files:
        with open(os.path.join(ROOT, "libkin", f), encoding="utf-8") as fh:
            for m in inc.finditer(fh.read()):
                to = f"{m.group(1).rstrip('/') or os.path.dirname(f)}/{m.group(2)}"
                if to != f and to in files:
                    edges[f].add(to)
                    why[(f, to)].add("#include")
    if build:
        objdir = os.path.join(build, "CMakeFiles", "kin_static.dir", "libkin")
        defs, undef = {}, {}
        for f in files:
            obj = os.path.normpath(os.path.join(objdir, f + ".o"))
            if not f.endswith(".c") or not os.path.exists(obj):
                continue
            out = subprocess.run(["nm", obj], capture_output=True, text=True, check=True).stdout
            undef[f] = set()
            for line in out.splitlines():
                p = line.split()
                if len(p) == 3 and p[1] in "TDBRCVW":
                    defs[p[2]] = f
                elif len(p) == 2 and p[0] == "U":
                    undef[f].add(p[1])
        if not undef:
            sys.exit(f"architecture: no objects under {objdir}: build first")
        for f, syms in undef.items():
            for sym in syms:
                d = defs.get(sym)
                if d and d != f:
                    edges[f].add(d)
                    why[(f, d)].add(sym)
    return files, edges, why


# ----------------------------------------------------------- Python ----
# The import graph of the package (python/tests/test_layout.py checks the
# package with these same functions): every ``import`` and ``from ...
# import`` anywhere in a module (module level, in a function, under
# TYPE_CHECKING; relative or absolute) is an edge to the module it names
# (``from P import x`` to the submodule P.x when there is one, else to P). A
# package's __init__ importing its own submodules is fine; a submodule
# importing its package (or a sibling) that imports it back is a circle.

SRC = pathlib.Path(ROOT) / "python" / "src"
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


def py_group(mod):
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


# ----------------------------------------------------------- graphs ----

def depth(nodes, edges, weight=lambda v: 1):
    """longest chain of dependencies (levels, each node counting weight(v):
    a package's __init__ that only re-exports counts 0), circles cut"""
    memo, busy = {}, set()

    def d(v):
        if v in memo:
            return memo[v]
        if v in busy:
            return 0
        busy.add(v)
        r = weight(v) + max((d(w) for w in edges.get(v, ())), default=0)
        busy.discard(v)
        memo[v] = r
        return r

    return max((d(v) for v in nodes), default=0)


# ------------------------------------------------------- functions ----
# A newcomer reads a function whole: none of the library's is longer than
# MAX_FUNCTION_LINES. The few written before this limit are listed with the
# length they may not exceed (a ratchet: each may only shrink, and leaves
# the list when split); the check fails on any other long function and on a
# listed one that grew.
MAX_FUNCTION_LINES = 120
LONG_FUNCTIONS = {
    "locate/locate.c:locate_impl": 277,
    "locate/locate_hermite.c:hermite_run": 195,
    "homotopy/track/homotopy_batch.c:kin__hom_track_batch": 180,
    "path/sparse.c:kin__sparse_prepare": 160,
    "path/path.c:attempt": 155,
    "symmetry/symmetry_graph.c:kin__graph_automorphisms": 142,
    "homotopy/track/homotopy_track.c:kin__hom_track": 139,
    "path/path.c:step_impl": 129,
}


def _strip_c(src):
    """comments, strings and character constants blanked, lines kept"""
    src = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), src, flags=re.S)
    src = re.sub(r"//[^\n]*", "", src)
    src = re.sub(r'"(\\.|[^"\\\n])*"', '""', src)
    return re.sub(r"'(\\.|[^'\\\n])*'", "''", src)


def c_functions(text):
    """(name, first line, lines) of every function defined at file scope in
    C source `text`: a body is a brace block at depth 0 whose head ends in
    ')' (a struct, enum or initializer is not a function)"""
    s = _strip_c(text)
    out, depth, head_start, start = [], 0, 0, None
    line = 1
    for i, ch in enumerate(s):
        if ch == "\n":
            line += 1
        elif ch == "{":
            if depth == 0:
                head = s[head_start:i].rstrip()
                names = re.findall(r"([A-Za-z_]\w*)\s*\(", head)
                start = (names[-1], line) if head.endswith(")") and names else None
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                if start:
                    out.append((start[0], start[1], line - start[1] + 1))
                start = None
                head_start = i + 1
        elif ch == ";" and depth == 0:
            head_start = i + 1
    return out


def long_functions(root=None):
    """'folder/file.c:name: N lines' for every function over the limit that
    is not listed, or listed and longer than its cap"""
    base = os.path.join(root or ROOT, "libkin")
    out = []
    for f in c_files():
        with open(os.path.join(base, f), encoding="utf-8", errors="replace") as fh:
            text = fh.read()
        for name, _, n in c_functions(text):
            key = f"{f}:{name}"
            cap = LONG_FUNCTIONS.get(key, MAX_FUNCTION_LINES)
            if n > cap:
                out.append(f"{key}: {n} lines (at most {cap})")
    return out


# ------------------------------------------------------------ check ----

def layer_problems(kind, nodes, edges, group_of, layers, why):
    """A node (a C file, a Python module) may use its own group (folder,
    subpackage) and the groups of lower layers, never a peer group of C's
    layer (C folders of one layer are independent) or a higher layer. Peers
    of one Python layer may import each other: no circle between modules is
    checked apart."""
    out = []
    for u in nodes:
        gu = group_of(u)
        lu = layer_of(layers, gu)
        if lu is None:
            out.append(f"{kind} {u}: {gu} is in no layer (tools/architecture.py "
                       f"{'C_LAYERS' if kind == 'C' else 'PY_LAYERS'})")
            continue
        for v in edges.get(u, ()):
            gv = group_of(v)
            lv = layer_of(layers, gv)
            if gv != gu and (lv is None or (lv >= lu if kind == "C" else lv > lu)):
                out.append(f"{kind} {u} (layer {lu}) uses {v} (layer {lv})" + (f": {why(u, v)}" if why else ""))
    return out


def check(build):
    problems = []
    units, edges, why = c_graph(build)
    if not build:
        print("architecture: no --build: includes only (calls between files not checked)")
    for comp in circles({u: edges.get(u, set()) for u in units}):
        problems.append("C circle: " + " <-> ".join(comp))
    problems += layer_problems("C", units, edges, c_folder, C_LAYERS, lambda u, v: sorted(why[(u, v)])[:4])
    problems += sublayer_problems(units, edges, why)
    if SRC.is_dir():
        pedges = import_graph(SRC)
        names = sorted(pedges)
        for comp in circles(pedges):
            problems.append("Python circle: " + " <-> ".join(comp))
        problems += layer_problems("Python", names, pedges, py_group, PY_LAYERS, None)
    problems += [f"C function too long: {x}" for x in long_functions()]
    problems += doc_problems()
    for p in problems:
        print(p)
    print(f"architecture: {len(problems)} problem(s)")
    return 1 if problems else 0


def sublayer_problems(units, edges, why):
    """inside a folder of C_SUBLAYERS: every subfolder in a sub-layer, and
    no file using (including, calling) a file of its own sub-layer's other
    subfolders or of a higher one; a folder with subfolders needs sub-layers"""
    out = []
    for sf in c_subfolders():
        folder, sub = sf.split("/")
        if folder not in C_SUBLAYERS:
            out.append(f"C folder libkin/{folder}/ has subfolders but no sub-layers "
                       "(tools/architecture.py C_SUBLAYERS)")
        elif layer_of(C_SUBLAYERS[folder], sub) is None:
            out.append(f"C subfolder libkin/{sf}/ is in no sub-layer (tools/architecture.py C_SUBLAYERS)")
    for u in units:
        folder = c_folder(u)
        layers = C_SUBLAYERS.get(folder)
        if layers is None:
            continue
        su = c_subfolder(u)
        lu = layer_of(layers, su)
        if lu is None:
            continue
        for v in edges.get(u, ()):
            sv = c_subfolder(v)
            if c_folder(v) != folder or sv == su:
                continue
            lv = layer_of(layers, sv)
            if lv is None or lv >= lu:
                out.append(f"C {u} (sub-layer {lu} of {folder}/) uses {v} (sub-layer {lv}): "
                           f"{sorted(why[(u, v)])[:4]}")
    return out


def doc_problems():
    """docs/architecture.md must match the tree: it names every C folder
    and Python subpackage of the layers, and every source path it names
    (`libkin/...`, `python/src/libkin/...`, `model/options.c`, ...) exists"""
    doc_path = os.path.join(ROOT, "docs", "architecture.md")
    if not os.path.exists(doc_path):
        return ["docs/architecture.md is missing"]
    with open(doc_path, encoding="utf-8") as fh:
        doc = fh.read()
    out = []
    for folder in sorted({c_folder(f) for f in c_files()}):
        if f"libkin/{folder}/" not in doc:
            out.append(f"docs/architecture.md does not name the C folder libkin/{folder}/")
    for sf in c_subfolders():
        if f"libkin/{sf}/" not in doc:
            out.append(f"docs/architecture.md does not name the C subfolder libkin/{sf}/")
    if SRC.is_dir():
        for g in sorted({py_group(m) for m in modules(SRC)} - {"__init__"}):
            if f"libkin.{g}" not in doc:
                out.append(f"docs/architecture.md does not name the Python package libkin.{g}")
    folders = {c_folder(f) for f in c_files()}
    for ref in sorted(set(re.findall(r"[A-Za-z0-9_./]+\.(?:c|h|py)\b", doc))):
        if ref.startswith(("python/", "include/", "tools/", "tests/", "bench/")):
            cand = [ref]
        elif ref.startswith("libkin/"):   # the C library, or the Python package's own path
            cand = [ref, f"python/src/{ref}"]
        elif ref.split("/")[0] in folders:
            cand = [f"libkin/{ref}"]
        elif "/" in ref:   # the package's, or a C path from within its folder ("track/homotopy_lu.h")
            cand = [f"python/src/libkin/{ref}", f"libkin/{ref}"] + [f"libkin/{f}" for f in c_files()
                                                                   if f.endswith("/" + ref)]
        else:   # a bare file name: somewhere in libkin/, the public headers or the package
            cand = [f"libkin/{f}" for f in c_files() if f.endswith("/" + ref)] + [f"include/libkin/{ref}"]
            if SRC.is_dir():
                cand += [str(p.relative_to(ROOT)) for p in SRC.rglob(ref)]
        if not any(os.path.exists(os.path.join(ROOT, c)) for c in cand):
            out.append(f"docs/architecture.md names {ref}, which does not exist")
    return out


def file_lines(path):
    with open(path, encoding="utf-8", errors="replace") as fh:
        return sum(1 for _ in fh)


def stats(build):
    units, edges, _ = c_graph(build)
    cfiles = c_files()
    folders = sorted({c_folder(f) for f in cfiles})
    lines = {f: file_lines(os.path.join(ROOT, "libkin", f)) for f in cfiles}
    print(f"C: {len(cfiles)} files in {len(folders)} folders ({', '.join(folders)}), "
          f"{sum(lines.values())} lines; largest: " +
          ", ".join(f"{f} {n}" for f, n in sorted(lines.items(), key=lambda x: -x[1])[:3]))
    per = collections.Counter(c_folder(f) for f in cfiles)
    subs = collections.Counter((c_folder(f), c_subfolder(f)) for f in cfiles)
    parts = []
    for folder in folders:
        inner = sorted(sb for (fd, sb) in subs if fd == folder and sb != TOP)
        detail = ""
        if inner:
            detail = (f" ({subs[(folder, TOP)]} at the top; "
                      + ", ".join(f"{sb}/ {subs[(folder, sb)]}" for sb in inner) + ")")
        parts.append(f"{folder}/ {per[folder]}{detail}")
    print("C: files (.c and .h) per folder: " + ", ".join(parts))
    print(f"C: dependency depth {depth(units, edges)} files; "
          f"circles: {circles({u: edges.get(u, set()) for u in units}) or 'none'}")
    pedges = import_graph(SRC)
    mods = modules(SRC)
    names = sorted(pedges)
    plines = {m: file_lines(p) for m, p in mods.items() if m not in GENERATED}
    pk = sorted({py_group(m) for m in names if _is_package(m, mods) and m != "libkin" and m.count(".") == 1})
    print(f"Python: {len(names)} modules, {len(pk)} subpackages ({', '.join(pk)}), {sum(plines.values())} lines "
          "(without the generated _cdef); largest: " +
          ", ".join(f"{m} {n}" for m, n in sorted(plines.items(), key=lambda x: -x[1])[:3]))
    print(f"Python: import depth {depth(names, pedges, lambda v: 0 if _is_package(v, mods) else 1)} modules "
          f"({depth(names, pedges)} counting packages' __init__); circles: {circles(pedges) or 'none'}")
    return 0


# ---------------------------------------------------------- picture ----

# what each C folder holds, by the paper's sections (docs/architecture.md)
C_SECTIONS = {
    "model": "handle, H, SVD: §2-3.1",
    "contact": "panels, clearance",
    "path": "steps: §3.2",
    "io": "files, §5-6 models",
    "symmetry": "the group (nauty)",
    "homotopy": "all 2^s roots of eq. 18",
    "locate": "detect, locate: §4",
    "branches": "eq. 17, paths: §3.3-3.4",
}


def reduction(fold):
    """transitive reduction of a small DAG of groups: the arrows a reader needs"""
    def reach(a, seen):
        for b in fold.get(a, ()):
            if b not in seen:
                seen.add(b)
                reach(b, seen)
        return seen
    out = {}
    for a, bs in fold.items():
        out[a] = {b for b in bs if not any(b in reach(c, set()) for c in bs if c != b)}
    return out


def picture(out, build):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch

    units, edges, _ = c_graph(build)
    pedges = import_graph(SRC)
    names = sorted(pedges)
    cfold = collections.defaultdict(set)
    for u, vs in edges.items():
        for v in vs:
            if u.split("/")[0] != v.split("/")[0]:
                cfold[u.split("/")[0]].add(v.split("/")[0])
    pfold = collections.defaultdict(set)
    for a, bs in pedges.items():
        for b in bs:
            ga, gb = py_group(a), py_group(b)
            if ga != gb:
                pfold[ga].add(gb)
    if not circles({g: pfold.get(g, set()) for g in set(pfold) | {x for v in pfold.values() for x in v}}):
        pfold = reduction(pfold)
    cfold = reduction(cfold)
    count = collections.Counter(u.split("/")[0] for u in units if u.endswith(".c"))
    pcount = collections.Counter(py_group(m) for m in names)

    fig, ax = plt.subplots(figsize=(16, 8.4))
    ax.set_xlim(0, 16)
    ax.set_ylim(-0.4, 8.7)
    ax.axis("off")
    pos = {}

    def row(layers, y0, dy, x0, x1, c_side, colour):
        for i, group in enumerate(layers):
            y = y0 + i * dy
            w = (x1 - x0) / len(group)
            for j, g in enumerate(group):
                cx = x0 + w * (j + 0.5)
                bw = min(w - 0.15, 2.8)
                ax.add_patch(FancyBboxPatch((cx - bw / 2, y - 0.34), bw, 0.68, boxstyle="round,pad=0.02",
                                            fc=colour, ec="#333333", lw=1))
                fs = 9.5 if len(group) < 4 else 8.5
                if c_side:
                    title, sub = f"libkin/{g}/", f"{C_SECTIONS.get(g, '')} · {count.get(g, 0)} .c files"
                else:
                    title = "libkin (root)" if g == "__init__" else g
                    sub = f"{pcount.get(g, 0)} module{'s' if pcount.get(g, 0) != 1 else ''}"
                ax.text(cx, y + 0.12, title, ha="center", va="center", fontsize=fs, weight="bold")
                for k, line in enumerate(sub.split(" · ")):
                    ax.text(cx, y - 0.06 - 0.16 * k, line, ha="center", va="center", fontsize=7.3, color="#444444")
                pos[(c_side, g)] = (cx, y)

    row(C_LAYERS, 0.5, 7.0 / max(len(C_LAYERS) - 1, 1), 0.1, 7.3, True, "#dbe9f6")
    row([[g for g in grp if pcount.get(g)] for grp in PY_LAYERS if any(pcount.get(g) for g in grp)],
        0.5, 1.0, 8.0, 15.9, False, "#fde9d0")

    def arrows(fold, c_side):
        for a, bs in fold.items():
            for b in bs:
                if (c_side, a) in pos and (c_side, b) in pos:
                    (x0, y0), (x1, y1) = pos[(c_side, a)], pos[(c_side, b)]
                    if abs(y0 - y1) < 1e-9:   # peers in one layer: side by side
                        ax.annotate("", xy=(x1 + (0.6 if x1 < x0 else -0.6), y1),
                                    xytext=(x0 + (-0.6 if x1 < x0 else 0.6), y0),
                                    arrowprops=dict(arrowstyle="->", color="#777777", lw=0.8))
                        continue
                    ax.annotate("", xy=(x1, y1 + 0.31), xytext=(x0, y0 - 0.31),
                                arrowprops=dict(arrowstyle="->", color="#777777", lw=0.8, alpha=0.6,
                                                connectionstyle="arc3,rad=0.05"))

    arrows(cfold, True)
    arrows(pfold, False)
    ax.text(3.7, 8.45, "C library, libkin/: a folder uses only folders below it", ha="center", fontsize=11.5)
    ax.text(11.95, 8.45, "Python package libkin (python/src/libkin): never a layer above", ha="center",
            fontsize=11.5)
    ax.annotate("", xy=(7.35, 0.5), xytext=(7.95, 0.5), arrowprops=dict(arrowstyle="->", color="#aa5500", lw=1.6))
    ax.text(7.65, 0.0, "cffi over\ninclude/libkin", ha="center", fontsize=7.5, color="#aa5500")
    ax.text(0.1, -0.3, "An arrow: 'uses' (calls, includes, imports; the shortest arrows that imply the rest), "
            "measured from the code by tools/architecture.py", fontsize=8, color="#555555")
    fig.savefig(out, dpi=100, bbox_inches="tight")
    print(f"architecture: wrote {out}")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["check", "stats", "picture"])
    ap.add_argument("out", nargs="?", help="picture: the PNG to write")
    ap.add_argument("--build", help="the CMake build folder (symbols of the built objects)")
    ap.add_argument("--root", help="stats of another checkout (default: this one)")
    a = ap.parse_args(argv)
    if a.root:
        global ROOT, SRC
        ROOT = os.path.abspath(a.root)
        SRC = pathlib.Path(ROOT) / "python" / "src"
    if a.command == "check":
        return check(a.build)
    if a.command == "stats":
        return stats(a.build)
    if not a.out:
        ap.error("picture needs OUT.png")
    return picture(a.out, a.build)


if __name__ == "__main__":
    sys.exit(main())
