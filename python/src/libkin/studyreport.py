"""Markdown reports and figures of the sail studies (see sailstudy.py)."""
import numpy as np

from .plot import _plt, draw


def _fmt(v, nd=3):
    return f"{v:.{nd}g}" if isinstance(v, float) else str(v)


def _event_row(name, ev, paper):
    if not ev:
        return f"| {name} | not reached | | | | | | | | {paper} |"
    pm = ev.get("paper_method", {})
    if "factorizations" in pm:
        pcol = f"{pm['factorizations']} ({pm['forward']} forward), {pm['v_r_rel']:.0e}"
    else:
        pcol = "gave up" if pm else ""
    return (f"| {name} | {ev.get('l', float('nan')):.4f} | {ev['m']} / {ev['s']} | {ev['steps']} | "
            f"{ev['factorizations']} ({ev['forward']} forward) | {ev['method']} | {ev['v_r_rel']:.1e} | "
            f"{ev['hub_out_of_plane']:.3f} | {pcol} | {paper} |")


def _path_map_figure(pmap, out, plt):
    """Nodes at (x-y extent, m); a node and its mirror image (same place) are
    drawn once; line width grows with the number of directed paths; the
    fold-deploy route R^A - R^B - R^C is drawn in red."""
    nodes, names = pmap.nodes, pmap.names()
    place, label = {}, {}
    for i, n in enumerate(nodes):
        key = (round(n["xy_extent"], 3), n["m"])
        place[i] = key
        label.setdefault(key, []).append(names[i])
    fig, ax = plt.subplots(figsize=(10, 5.8))
    agg = {}
    for e in pmap.edges:
        if e["to"] is not None and place[e["from"]] != place[e["to"]]:
            k = (place[e["from"]], place[e["to"]])
            agg[k] = agg.get(k, 0) + 1
    route = {("R^A", "R^B"), ("R^B", "R^C")}
    for (p, q), cnt in agg.items():
        on_route = any(names[i] in (r[0],) and any(names[j] == r[1] for j in range(len(nodes)) if place[j] == q)
                       for r in route for i in range(len(nodes)) if place[i] == p)
        ax.annotate("", xy=q, xytext=p,
                    arrowprops=dict(arrowstyle="->", color="C3" if on_route else "0.55",
                                    lw=(2.2 if on_route else 0.6 + 0.35 * cnt), shrinkA=7, shrinkB=7,
                                    connectionstyle="arc3,rad=0.15"))
    by_row = {}
    for key in label:
        by_row.setdefault(key[1], []).append(key)
    for m, keys in by_row.items():
        for j, key in enumerate(sorted(keys)):
            main = any(nm in ("R^A", "R^B", "R^C") for nm in label[key])
            ax.plot(*key, "o", color="C3" if main else "C0", ms=11 if main else 7, zorder=3)
            text = ", ".join(sorted(set(label[key]), key=len))
            ax.annotate(text, key, xytext=(0, 10 if j % 2 == 0 else -16), textcoords="offset points",
                        fontsize=7.5, ha="center", fontweight="bold" if main else "normal")
    ax.invert_xaxis()
    ms = sorted(by_row)
    ax.set_yscale("log")
    ax.set_yticks(ms)
    ax.set_yticklabels([str(m) for m in ms])
    ax.minorticks_off()
    ax.set_ylim(min(ms) * 0.85, max(ms) * 1.25)
    ax.set_xlabel("x-y extent of the sail (largest distance of a node from the hub axis): unfolded -> folded")
    ax.set_ylabel("internal mechanisms m at the bifurcation")
    ax.set_title("Path map: bifurcations reached along symmetric paths (red: the fold R^A - R^B - R^C; "
                 "' = mirror image)", fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "path_map.png", dpi=100)
    plt.close(fig)


def hexagonal(res, track, stages, out, pmap=None):
    plt = _plt()
    from .assembly import Assembly
    a = Assembly.sail(res["n_sides"], res["n_loops"])
    a_bars = a.bars
    # Figure 13: xy (top) and xz (bottom) projections of the stages
    fig, axs = plt.subplots(2, len(stages), figsize=(3.2 * len(stages), 6.6), squeeze=False)
    for k, (title, x) in enumerate(stages):
        draw(x, a_bars, ax=axs[0, k], plane="xy", fixed=a.fixed.all(axis=1), title=title)
        draw(x, a_bars, ax=axs[1, k], plane="xz", fixed=a.fixed.all(axis=1), color="C1")
        for r in range(2):
            axs[r, k].set_xlim(-2.4, 2.4)
            axs[r, k].set_ylim(-2.4, 2.4)
    fig.suptitle("Figure 13-like: folding stages, projected on x-y (top) and x-z (bottom)")
    fig.tight_layout()
    fig.savefig(out / "fig13_stages.png", dpi=90)
    plt.close(fig)
    # Figure 14: the 15 lowest singular values along the whole run
    l = np.array(track.l)
    sv = np.array(track.sv)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for j in range(sv.shape[1]):
        ax.plot(l, sv[:, j], lw=1)
    marks = [(k, v) for k, v in res["events"].items() if v and "l_total" in v]
    for k, v in marks:
        ax.axvline(v["l_total"], color="k", ls=":", lw=0.8)
        ax.text(v["l_total"], ax.get_ylim()[1] * 0.95, k.split("_")[0].replace("R", "R^"), rotation=90,
                va="top", fontsize=8)
    ax.set_xlabel("path length travelled (fold, then deploy)")
    ax.set_ylabel(f"{sv.shape[1]} lowest singular values")
    ax.set_title("Figure 14-like: lowest singular values of H over the fold-deploy run")
    fig.tight_layout()
    fig.savefig(out / "fig14_singular_values.png", dpi=100)
    plt.close(fig)
    # strain and hub planarity
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    a1.semilogy(l, np.maximum(track.strain, 1e-18), ".", ms=3)
    a1.set_ylabel("max |L - L0| / L0")
    a2.plot(l, track.hub_z, "-")
    a2.set_ylabel("max |z| of hub nodes")
    a2.set_xlabel("path length travelled")
    a1.set_title("bar strain at every accepted step, and the hub's out-of-plane displacement")
    fig.tight_layout()
    fig.savefig(out / "strain_hub.png", dpi=100)
    plt.close(fig)
    if pmap is not None and pmap.nodes:
        _path_map_figure(pmap, out, plt)
    _write_hex_md(res, out)


def _write_hex_md(res, out):
    ev = res["events"]
    flat = res["flat"]
    L = []
    L.append(f"# Folding and deployment of the solar sail ({res['model']})\n")
    L.append("Generated by `libkin study` (python/src/libkin/sailstudy.py); numbers in summary.json.\n")
    if "failed" in res:
        L.append(f"**The run stopped early: {res['failed']}.**\n")
    L.append("## The flat state R^A\n")
    L.append(f"H is {flat['nfree']} x {flat['nbars']}; m = {flat['m']} internal mechanisms, s = {flat['s']} "
             "self-stresses.")
    if "complete" in flat:
        c = flat["complete"]
        L.append(f" Complete solver over all {c['paths']} homotopy paths: {c['real']} real endpoints "
                 f"({c['real_distinct']} distinct), {c['nonreal']} complex, {c['singular']} singular, "
                 f"{c['failed']} failed, in {c['seconds']} s.")
        if (c["singular"] == 0 and c["failed"] == 0 and c.get("duplicates", 1) == 0 and c.get("unpaired", 1) == 0
                and c["real"] == c["real_distinct"]):
            L.append(" Every endpoint is a certified simple root reached by one path, and the complex ones pair "
                     "up with their conjugates: these are all the solutions (docs/branches.md).")
    sym = flat["symmetric"]
    L.append(f"\n\nRestricted to motions that keep the hub's {res['model'].split()[1]} supports' rotational "
             f"symmetry: {sym['k']} mechanisms, {sym['s']} equations, {sym['accounting']['real_distinct']} real "
             f"solutions of {sym['accounting']['paths']} paths.\n")
    if "chosen" in flat:
        ch = flat["chosen"]
        L.append("**Choice of the folding branch (automatic).** Criterion: the path keeps the rotational "
                 "symmetry and its first bifurcation has every loop-1 node directly above or below its hub "
                 "vertex, alternately up and down (loop 1 wrapped, as in the paper's Figure 13(c)); of "
                 "those, the shortest. "
                 f"{flat['candidates']} symmetric directed candidates were followed: "
                 f"{flat['candidates_reaching_bifurcation']} reach a bifurcation, "
                 f"{flat['candidates_wrapping_loop1']} wrap loop 1. Chosen: solution {ch['beta']}, sign "
                 f"{ch['sign']:+d}, reaching R^B at l = {ch['reached']:.4f}.\n")
    L.append("## Bifurcations along the run\n")
    L.append("| point | l from previous | m / s | steps | factorizations to locate | method | v_r / v_max "
             "| hub max abs z | paper's method here (tol 1e-6): factorizations, v_r | paper (steps) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    L.append(_event_row("R^B (folding)", ev.get("RB_fold"), 35))
    L.append(_event_row("R^C (folding)", ev.get("RC_fold"), 26))
    L.append(_event_row("R^B (deploying)", ev.get("RB_deploy"), 58))
    L.append(_event_row("R^A (deploying)", ev.get("RA_deploy"), 149))
    L.append("\n'steps' are the path steps from the previous bifurcation until the detector fired; the "
             "factorizations (SVDs, QR and LU factorizations) are those of locating after that, to "
             "v_r / v_max <= 1e-10 for every singular value that vanishes there, by the fast method "
             "(Hermite interpolation, docs/locate.md). The paper's method was run from the same point at the "
             "paper's own tolerance for comparison; the paper's counts are its locator steps at 1e-6, each "
             "at least one factorization.\n")
    for key, name in (("RB", "R^B"), ("RC", "R^C")):
        if key in res:
            r = res[key]
            if "accounting" in r:
                a = r["accounting"]
                L.append(f"At {name}: m = {r['m']}, s = {r['s']}; the complete solver accounts for all "
                         f"{a['paths']} homotopy paths: {a['real']} real ({a['real_distinct']} distinct), "
                         f"{a['nonreal']} complex, {a['singular']} singular, {a['failed']} failed; "
                         f"{r['directed_paths_ok']} directed paths exist with the right tangent, "
                         f"{r['distinct_paths']} distinct.")
            else:
                L.append(f"At {name}: m = {r['m']}, s = {r['s']} ({r.get('skipped', '')}).")
            if "chosen" in r:
                ch = r["chosen"]
                L.append(f" Onward folding path chosen: symmetric, not the arrival path, smallest x-y extent "
                         f"after l = 0.5 ({ch['xy_extent_at_0.5']:.4f}); cos with the arrival chord "
                         f"{ch['cos_with_arrival']:.3f}; the centre node moves {'down' if ch['centre_dz'] < 0 else 'up'}"
                         f" (the paper's two axisymmetric folding motions: node 1 up or down).")
            L.append("\n")
    if "map" in res:
        L.append("## Path map (symmetric paths)\n")
        L.append("Every directed path out of R^A, R^B and R^C that keeps the three-fold symmetry, followed to "
                 "its next bifurcation (nodes are the same when their coordinates agree to 1e-6; a prime "
                 "marks a mirror image z -> -z):\n")
        L.append("| from | to | directed paths | path lengths |")
        L.append("|---|---|---|---|")
        edges = res["map"]["edges"]
        done = set()
        for i, e in enumerate(edges):
            if i in done:
                continue
            to = e["to"] or "no bifurcation located"
            # a path and its mirror image: one row
            for j in range(i + 1, len(edges)):
                f = edges[j]
                if (j not in done and f["from"] == e["from"] and e["to"] and f["to"] and f["l"] == e["l"]
                        and f["paths"] == e["paths"] and f["to"] in (e["to"] + "'", e["to"].rstrip("'"))
                        and f["to"] != e["to"]):
                    to = f"{e['to']} and {f['to']} (mirror)"
                    done.add(j)
                    break
            L.append(f"| {e['from']} | {to} | {e['paths']} each | {', '.join(f'{v:.4f}' for v in e['l'])} |"
                     if " and " in to else
                     f"| {e['from']} | {to} | {e['paths']} | {', '.join(f'{v:.4f}' for v in e['l'])} |")
        L.append("\n| node | m / s | x-y extent |")
        L.append("|---|---|---|")
        for n in res["map"]["nodes"]:
            L.append(f"| {n['name']} | {n['m']} / {n['s']} | {n['xy_extent']:.4f} |")
        if "RC" in res and "onward" in res["RC"]:
            rc = res["RC"]
            ends = ", ".join(f"{o['to']} (l = {o['l']:.4f})" if o["to"] else "none" for o in rc["onward"])
            verdict = ("every one of them ends at a less compact state, so R^C is as far as the structure "
                       "folds along symmetric paths" if rc["most_compact"] else
                       "at least one ends at a more compact state")
            L.append(f"\n**Onward from R^C.** Its symmetric directed paths lead to {ends}: {verdict}.\n")
        L.append("![path map](path_map.png)\n")
    L.append("## The paper's three questions\n")
    cont = "failed" not in res
    L.append(f"1. **Continuous strain-free motion from open to folded?** "
             f"{'Yes' if cont else 'Not shown'}: the run went R^A -> R^B -> R^C and back to R^A with a "
             f"largest bar strain of {res.get('max_strain', float('nan')):.1e} at any accepted step "
             f"({res.get('steps_total', 0)} steps, total path length {res.get('path_length_total', 0):.3f}); "
             f"closure error on return to the flat state {res.get('closure', float('nan')):.1e}.")
    pts = ", ".join(f"{k.split('_')[0]} at l = {v['l_total']:.4f} (m = {v['m']}, s = {v['s']})"
                    for k, v in ev.items() if v and "l_total" in v)
    L.append(f"2. **Where are the bifurcations?** {pts}. At each the sail can leave the intended path "
             "(the counts of distinct paths are above), so the deployment can go astray there.")
    L.append(f"3. **Does the hub stay planar?** No: the largest out-of-plane displacement of a hub node is "
             f"{res.get('max_hub_out_of_plane', float('nan')):.3f} (hub side 1); see strain_hub.png.\n")
    L.append("## Figures\n")
    L.append("![stages](fig13_stages.png)\n")
    L.append("![singular values](fig14_singular_values.png)\n")
    L.append("![strain and hub](strain_hub.png)\n")
    L.append(f"Run time {res['seconds']} s.\n")
    (out / "report.md").write_text("\n".join(L))


def square(res, a, br, out):
    plt = _plt()
    ok = [(i, p) for i, p in enumerate(br.paths) if p.exists and p.tangent_ok]
    cols = 8
    rows = max(1, (len(ok) + cols - 1) // cols)
    fig, axs = plt.subplots(rows, cols, figsize=(2.2 * cols, 2.3 * rows), squeeze=False)
    # red: the paths that reach the compact state (same m, s as the flat one)
    folded = {f["path"] for f in res["fully_folded_paths"] if f.get("m") == res["flat"]["m"]}
    for k, ax in enumerate(axs.flat):
        if k >= len(ok):
            ax.axis("off")
            continue
        i, p = ok[k]
        draw(p.final_coords, a.bars, ax=ax, plane="xy", color="C3" if i in folded else "C0",
             title=f"path {i} ({'+' if p.sign > 0 else '-'}b{p.beta})")
        ax.set_xlim(-1.8, 1.8)
        ax.set_ylim(-1.8, 1.8)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_xlabel("")
        ax.set_ylabel("")
    fig.suptitle("Figure 11-like: x-y projections at l = 1.75 of every path out of the flat state "
                 "(red: to the fully folded state)")
    fig.tight_layout()
    fig.savefig(out / "fig11_paths.png", dpi=80)
    plt.close(fig)
    acc = res["accounting"]
    L = ["# Square-hub solar sail: every path out of the flat state\n",
         f"Flat state: m = {res['flat']['m']} internal + {res['flat']['m_rigid']} rigid mechanisms, "
         f"s = {res['flat']['s']}.\n",
         f"Complete solver: {acc['paths']} homotopy paths, {acc['real']} real ({acc['real_distinct']} distinct), "
         f"{acc['nonreal']} complex, {acc['singular']} singular, {acc['failed']} failed. "
         f"The paper's root scan found 15 of the 16.\n",
         f"{res['directed_paths_ok']} directed paths (both signs of each solution) reach l = 1.75 with the "
         f"right tangent; {res['distinct_paths']} are distinct.\n",
         "## Paths to the fully folded state\n"]
    L.append("Criterion: the path keeps the two-fold symmetry (rotation by 180 degrees about z, which maps the "
             "supports V0, V2 onto each other) and moves V1, V3 to one side and O0, O2 to the other; each such "
             "path is followed on until the next bifurcation.\n")
    L.append("| path | pattern | next bifurcation at l | m / s there | z of V0..V3, O0..O3 there | hub fold |")
    L.append("|---|---|---|---|---|---|")
    for f in res["fully_folded_paths"]:
        if "m" in f:
            L.append(f"| {f['path']} | {f['pattern']} | {f['ends_at_l']:.4f} | {f['m']} / {f['s']} | "
                     f"{', '.join(f'{v:.3f}' for v in f['end_z'])} | {f['hub_fold_deg']:.1f} deg |")
        else:
            L.append(f"| {f['path']} | {f['pattern']} | not reached | | | |")
    L.append("\nBoth directions of travel reach the compact state in which the hub is folded by 90 degrees "
             "about its diagonal V0-V2 (V1, V3 at z = -+0.707) and the sail is stacked: two distinct paths lead "
             "to it and two to its mirror image. The paper reports one path (its path 12: nodes 2, 4 = V1, V3 "
             "down, 5, 7 = O0, O2 up) and the mirror that its scan missed; the complete solver finds both of "
             "those and a second pair.\n")
    L.append("## Symmetry relations between paths\n")
    if res["symmetry_relations"]:
        for r in res["symmetry_relations"]:
            L.append(f"- path {r['other']} = {r['by']}(path {r['path']})")
    else:
        L.append("none found")
    L.append("\n![paths](fig11_paths.png)\n")
    (out / "report.md").write_text("\n".join(L))
