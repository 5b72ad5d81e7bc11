#!/usr/bin/env python3
"""The layers of libkin, checked against the code (docs/architecture.md).

  architecture.py check [--build DIR]   fail on a circle between files or a
                                        dependency that goes up a layer
  architecture.py stats [--build DIR]   folders, largest files, depth, circles
  architecture.py picture OUT.png       the layer picture of docs/architecture.md

C: a file depends on another when it includes one of its folder's headers
(from the sources) or calls a function the other defines (from the symbols
of the built objects, `nm`, when --build is given: an include alone misses a
call declared in a shared header). Python: a module depends on every module
it imports, at the top or inside a function (a lazy import that closes a
circle is still a circle). Standard library only, but for the picture
(matplotlib).
"""
import argparse
import ast
import collections
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The C layers, lowest first: a folder may use only folders of a lower layer
# (and itself). The one place this order is written; docs/architecture.md
# explains it.
C_LAYERS = [
    ["model"],                                # the handle, options, status, the SVD analysis (paper 2-3.1)
    ["path", "io", "symmetry", "homotopy"],   # following (3.2), files, symmetry, complete solver (3.4)
    ["locate"],                               # detection and location (4)
    ["branches"],                             # second order, branch paths, follow to event (3.3-3.4, 5)
]
# The Python layers, lowest first, by subpackage (or top-level module) of
# the libkin package: a module may import from its own layer or below, never
# above, and no two modules may import each other, even through others.
PY_LAYERS = [
    ["_native", "errors", "_compat", "parallel"],   # the cffi boundary, exceptions, executors
    ["assembly"],                                   # Assembly: analysis, paths, location, branches
    ["io", "homotopy", "symmetry", "plot", "cliargs"],
    ["atlas"],                                      # libkin.explore
    ["__init__"],                                   # the package root: the public API
    ["studies"],                                    # the sail study application (public API only)
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
    base = os.path.join(ROOT, "libkin")
    out = []
    for folder in sorted(os.listdir(base)):
        d = os.path.join(base, folder)
        if os.path.isdir(d):
            out += [f"{folder}/{f}" for f in sorted(os.listdir(d)) if f.endswith((".c", ".h"))]
    return out


def c_graph(build):
    """nodes: the files of libkin/ ("path/step_lu.c", "path/path.h"); edges:
    a file to each private header it includes, and (from --build's objects)
    a .c to each .c that defines a function it calls"""
    files = c_files()
    edges = collections.defaultdict(set)
    why = collections.defaultdict(set)
    inc = re.compile(r'#\s*include\s+"([a-z_]+/[A-Za-z0-9_]+\.h)"')
    for f in files:
        with open(os.path.join(ROOT, "libkin", f), encoding="utf-8") as fh:
            for m in inc.finditer(fh.read()):
                to = m.group(1)
                if to != f and to in files:
                    edges[f].add(to)
                    why[(f, to)].add("#include")
    if build:
        objdir = os.path.join(build, "CMakeFiles", "kin_static.dir", "libkin")
        defs, undef = {}, {}
        for f in files:
            obj = os.path.join(objdir, f + ".o")
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

PKG = os.path.join(ROOT, "python", "src", "libkin")


def py_modules():
    mods = {}
    for dirpath, _, names in os.walk(PKG):
        for n in names:
            if n.endswith(".py"):
                rel = os.path.relpath(os.path.join(dirpath, n), PKG)
                parts = rel[:-3].split(os.sep)
                is_pkg = parts[-1] == "__init__"
                if is_pkg:
                    parts = parts[:-1]
                mods[".".join(["libkin"] + parts)] = (os.path.join(dirpath, n), is_pkg)
    return mods


def py_graph():
    mods = py_modules()
    edges = collections.defaultdict(set)
    for name, (path, is_pkg) in mods.items():
        with open(path, encoding="utf-8") as fh:
            tree = ast.parse(fh.read())
        pkg = name if is_pkg else name.rpartition(".")[0]
        for node in ast.walk(tree):
            targets = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = pkg.split(".")
                    base = base[:len(base) - node.level + 1]
                    mod = ".".join(base + ([node.module] if node.module else []))
                else:
                    mod = node.module or ""
                targets = [mod] + [f"{mod}.{a.name}" for a in node.names]
            for t in targets:
                while t and t not in mods:
                    t = t.rpartition(".")[0]
                if t and t != name and t.startswith("libkin"):
                    # a package importing its own submodules is its
                    # interface, not a dependency of the submodule
                    edges[name].add(t)
    return sorted(mods), edges, mods


def py_group(mod):
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


# ----------------------------------------------------------- graphs ----

def cycles(nodes, edges):
    """strongly connected components with more than one node (Tarjan)"""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
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

    sys.setrecursionlimit(10000)
    for v in nodes:
        if v not in index:
            visit(v)
    return out


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


def py_edges_without_package_exports(mods, edges):
    """drop the edges from a module to a package that contains it: Python
    has that package in sys.modules already while its parts load (a package
    importing its own parts is kept: whoever imports the package runs them)"""
    out = collections.defaultdict(set)
    for a, bs in edges.items():
        for b in bs:
            if mods[b][1] and a.startswith(b + "."):
                continue
            out[a].add(b)
    return out


# ------------------------------------------------------------ check ----

def check(build):
    problems = []
    units, edges, why = c_graph(build)
    if not build:
        print("architecture: no --build: includes only (calls between files not checked)")
    for comp in cycles(units, edges):
        problems.append("C circle: " + " <-> ".join(comp))
    for u in units:
        folder = u.split("/")[0]
        lu = layer_of(C_LAYERS, folder)
        if lu is None:
            problems.append(f"C folder libkin/{folder}/ is in no layer (tools/architecture.py C_LAYERS)")
            continue
        for v in edges.get(u, ()):
            fv = v.split("/")[0]
            lv = layer_of(C_LAYERS, fv)
            if fv != folder and (lv is None or lv >= lu):
                problems.append(f"C {u} (layer {lu}) uses {v} (layer {lv}): {sorted(why[(u, v)])[:4]}")
    if os.path.isdir(PKG):
        names, pedges, mods = py_graph()
        pedges = py_edges_without_package_exports(mods, pedges)
        for comp in cycles(names, pedges):
            problems.append("Python circle: " + " <-> ".join(comp))
        for a in names:
            ga = py_group(a)
            la = layer_of(PY_LAYERS, ga)
            if la is None:
                problems.append(f"Python {a}: {ga} is in no layer (tools/architecture.py PY_LAYERS)")
                continue
            for b in pedges.get(a, ()):
                gb = py_group(b)
                lb = layer_of(PY_LAYERS, gb)
                # peers of one layer may use each other (no circle between
                # modules is checked above); never a higher layer
                if gb != ga and (lb is None or lb > la):
                    problems.append(f"Python {a} (layer {la}) imports {b} (layer {lb})")
    for p in problems:
        print(p)
    print(f"architecture: {len(problems)} problem(s)")
    return 1 if problems else 0


def file_lines(path):
    with open(path, encoding="utf-8", errors="replace") as fh:
        return sum(1 for _ in fh)


def stats(build):
    units, edges, _ = c_graph(build)
    cfiles = c_files()
    folders = sorted({f.split("/")[0] for f in cfiles})
    lines = {f: file_lines(os.path.join(ROOT, "libkin", f)) for f in cfiles}
    print(f"C: {len(cfiles)} files in {len(folders)} folders ({', '.join(folders)}), "
          f"{sum(lines.values())} lines; largest: " +
          ", ".join(f"{f} {n}" for f, n in sorted(lines.items(), key=lambda x: -x[1])[:3]))
    print(f"C: dependency depth {depth(units, edges)} files; circles: {cycles(units, edges) or 'none'}")
    names, pedges, mods = py_graph()
    pedges = py_edges_without_package_exports(mods, pedges)
    plines = {m: file_lines(p) for m, (p, _) in mods.items() if not m.endswith("_cdef")}
    pk = sorted({py_group(m) for m in names if mods[m][1] and m != "libkin"})
    print(f"Python: {len(names)} modules, {len(pk)} subpackages ({', '.join(pk)}), {sum(plines.values())} lines "
          "(without the generated _cdef); largest: " +
          ", ".join(f"{m} {n}" for m, n in sorted(plines.items(), key=lambda x: -x[1])[:3]))
    print(f"Python: import depth {depth(names, pedges, lambda v: 0 if mods[v][1] else 1)} modules "
          f"({depth(names, pedges)} counting packages' __init__); circles: {cycles(names, pedges) or 'none'}")
    return 0


# ---------------------------------------------------------- picture ----

# what each C folder holds, by the paper's sections (docs/architecture.md)
C_SECTIONS = {
    "model": "handle, H, SVD: §2-3.1",
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
    names, pedges, mods = py_graph()
    pedges = py_edges_without_package_exports(mods, pedges)
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
    if not cycles(sorted(pfold), pfold):
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

    row(C_LAYERS, 0.5, 2.2, 0.1, 7.3, True, "#dbe9f6")
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
    a = ap.parse_args(argv)
    if a.command == "check":
        return check(a.build)
    if a.command == "stats":
        return stats(a.build)
    if not a.out:
        ap.error("picture needs OUT.png")
    return picture(a.out, a.build)


if __name__ == "__main__":
    sys.exit(main())
