"""The contact studies' reports: the interference study's (contactstudy.py)
and the contact map's section of the hexagonal study's (contactmap.py).

interference_chart(): how far each member folds before its first contact,
against the membrane's thickness, one curve per member; interference_md():
the tables behind it and the paper's two claims, checked member by member;
contact_map_md(): the hexagonal study report's section on its contact map
(contactmap.py).
"""
import json
import pathlib
from typing import Any, Dict, List, Optional

from libkin.atomic import replacing, staged_folder, write_text
from libkin.plot import pyplot

from .common import jsonable


def _label(m: Dict[str, Any]) -> str:
    hub = {6: "hexagonal", 8: "octagonal"}.get(m["n_sides"], f"{m['n_sides']}-gon")
    return f"{hub} hub, {m['n_loops']} loop" + ("s" if m["n_loops"] > 1 else "")


def interference_chart(study: Dict[str, Any], path: Any) -> None:
    """One curve per member: the share of its fold done before the first
    contact (100 %: none along the whole fold), at each thickness."""
    plt = pyplot()
    ts = study["thicknesses"]
    fig, ax = plt.subplots(figsize=(8.0, 4.8))
    colours = {6: "tab:blue", 8: "tab:red"}
    styles = {1: "-", 2: "--", 3: "-.", 4: ":"}
    for m in study["members"]:
        y = [100.0 * c["fold_fraction"] for c in m["contacts"]]
        x = list(range(len(ts)))
        ax.plot(x, y, styles.get(m["n_loops"], "-"), color=colours.get(m["n_sides"], "k"), lw=1.8,
                label=f"{_label(m)} ({m['bifurcations']} bifurcation{'s' if m['bifurcations'] != 1 else ''})")
        for xi, c, yi in zip(x, m["contacts"], y):
            ax.plot(xi, yi, "o", ms=6, color=colours.get(m["n_sides"], "k"),
                    mfc="white" if not c["contact"] else colours.get(m["n_sides"], "k"))
    ax.set_xticks(range(len(ts)))
    ax.set_xticklabels(["0 (bare)"] + [f"{t:g}" for t in ts[1:]] if ts and ts[0] == 0 else [f"{t:g}" for t in ts])
    ax.set_xlabel("membrane thickness t / a (a = hub side; bars of radius t/2)")
    ax.set_ylabel("fold done before first contact (% of path)")
    ax.set_ylim(-3, 103)
    ax.grid(alpha=0.3)
    ax.set_title("How far each sail folds along its radially sequential path before two parts touch\n"
                 "(filled: contact; open: none along the whole fold)", fontsize=10)
    ax.legend(fontsize=7.5, loc="lower left", ncol=2)
    fig.tight_layout()
    with replacing(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def contact_figure(member: Dict[str, Any], path: Any) -> bool:
    """3D views of the member at its first contact, bare and at the largest
    thickness: the membrane's panels light, its bars grey, the two parts that
    touch in red and orange, their closest points in black. False (nothing
    written) when no thickness gave a contact."""
    import numpy as np
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from libkin.assembly import Assembly
    from libkin.plot import draw3d

    from .sailmeasure import sail_panels
    rows = [c for c in member["contacts"] if c["contact"]]
    if not rows:
        return False
    rows = [rows[0]] if len(rows) == 1 else [rows[0], rows[-1]]
    a = Assembly.sail(member["n_sides"], member["n_loops"])
    panels, bars = sail_panels(a), np.asarray(a.bars)
    plt = pyplot()
    fig = plt.figure(figsize=(5.2 * len(rows), 4.6))
    for k, c in enumerate(rows):
        x = np.asarray(c["coords"])
        ax = fig.add_subplot(1, len(rows), k + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection([x[p] for p in panels], facecolor=(0.75, 0.82, 0.92, 0.35),
                                             edgecolor="none"))
        for i, j in bars:
            ax.plot(*x[[i, j]].T, color="0.55", lw=0.7)
        for (kind, idx), colour in zip(c["part_ids"], ("tab:red", "tab:orange")):
            if kind == "bar":
                ax.plot(*x[bars[idx]].T, color=colour, lw=3.2)
            else:
                ax.add_collection3d(Poly3DCollection([x[panels[idx]]], facecolor=colour, alpha=0.75,
                                                     edgecolor=colour))
        pts = np.asarray(c["points"])
        ax.scatter(*pts.T, color="k", s=18, depthshade=False)
        draw3d.equal_limits(ax, x, pad=0.02)
        ax.view_init(28, -58)
        ax.tick_params(labelsize=6, pad=0)
        t = "bare (t = 0)" if c["t"] == 0 else f"t = {c['t']:g} a"
        ax.set_title(f"{t}: first contact at l = {c['l']:.3f}\n({100 * c['fold_fraction']:.1f} % of the fold)\n"
                     f"red: {c['parts'][0]}; orange: {c['parts'][1]}", fontsize=8)
    fig.suptitle(f"{_label(member)}: the two parts that touch first (hub sides a)", fontsize=10)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.82, wspace=0.05)
    with replacing(path) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
    return True


def _contact_cell(c: Dict[str, Any]) -> str:
    if not c["contact"]:
        return "none"
    return (f"l = {c['l']:.4f} ({100 * c['fold_fraction']:.1f} %, leg {c['leg']} at "
            f"{100 * c['leg_fraction']:.0f} %): {' / '.join(c['parts'])}")


def interference_md(study: Dict[str, Any], chart: str = "interference.png") -> str:
    """The report's section (markdown)."""
    ts = study["thicknesses"]
    lines: List[str] = [
        "## Interference and thickness: the paper's open question",
        "",
        "Each member is folded along its radially sequential path (studies/sequential.py: loop 1 wrapped "
        "first, then at each bifurcation the symmetric onward path whose next bifurcation is more compact, "
        "searched depth first), with the membrane as panels (every bar triangle and the hub polygon) and "
        "bars of radius t/2, panels of thickness t. The first contact along the fold is found by a certified "
        "search (contactstudy.py), located to 1e-7 hub sides of path length. Lengths in hub sides a.",
        "",
        f"![fold before contact against thickness]({chart})",
        "",
        "*How far each member folds before two of its parts touch, by membrane thickness t/a. "
        "Filled markers: a contact; open: none along the whole fold.*",
        "",
        "| member | free coords | loops / bifurcations on the fold | fold length | parts through each other "
        "(t = 0, share of the fold) | " + " | ".join(f"first contact, t = {t:g}" for t in ts) + " |",
        "|---|---|---|---|---|" + "---|" * len(ts),
    ]
    for m in study["members"]:
        lines.append(f"| {_label(m)} | {m['nfree']} | {m['n_loops']} / {m['bifurcations']} | "
                     f"{m['path_length']:.3f} | {100 * m.get('intersecting_share', 0.0):.1f} % | " + " | ".join(_contact_cell(c) for c in m["contacts"]) + " |")
    lines += ["", "### The paper's claims, member by member", "",
              "| member | bifurcations (claim: one per loop) | loop radii at each bifurcation (hub circumradii) "
              "| why the fold stopped |", "|---|---|---|---|"]
    for m in study["members"]:
        radii = "; ".join("(" + ", ".join(f"{r:.3f}" for r in leg["loop_radii"]) + ")"
                          for leg in m["legs"] if leg["event"] == "bifurcation")
        ok = "holds" if m["bifurcations"] == m["n_loops"] else "does not hold"
        lines.append(f"| {_label(m)} | {m['bifurcations']} of {m['n_loops']}: {ok} | {radii} | {m['stop']} |")
    return "\n".join(lines) + "\n"


def write_interference(study: Dict[str, Any], out: Any) -> None:
    """report.md, summary.json and interference.png into the folder out,
    committed whole (libkin.atomic.staged_folder)."""
    out = pathlib.Path(out)
    with staged_folder(out) as stage:
        interference_chart(study, stage / "interference.png")
        views = []
        for m in study["members"]:
            name = f"contact_{m['n_sides']}_{m['n_loops']}.png"
            if contact_figure(m, stage / name):
                views.append(f"![{_label(m)} at first contact]({name})\n")
        write_text(stage / "report.md", "# libkin: sail interference study\n\n" + interference_md(study)
                   + "\n### The first contacts in 3D\n\n" + "\n".join(views))
        write_text(stage / "summary.json", json.dumps(study, indent=1, default=jsonable) + "\n")


def contact_map_md(cm: Dict[str, Any], plain_paths: Optional[int] = None, picture: Optional[str] = None) -> List[str]:
    """The report's section on the contact map (lines of markdown)."""
    L = ["## Which mapped paths a membrane can follow\n"]
    ev = cm["edge_events"]
    L.append(f"The path map above lets parts pass through each other, as the paper does. Explored again with "
             f"the membrane as {cm['panels']} panels (every bar triangle and the hub), thickness t/a = "
             f"{cm['thickness']:g}, and contact as an event (`libkin study --contact`; docs/contact.md), every "
             f"path stops at the first contact of two parts that share no joint: of its {cm['paths']} directed "
             f"paths (depth {cm['depth']}) **{ev.get('contact', 0)} end in contact** and **{cm['free']} reach their "
             f"next event free of it**" + (f" (the map without contact has {plain_paths} paths: a path that "
                                          "touches stops, so what lies beyond it is not reached)"
                                          if plain_paths is not None else "") + ".\n")
    L.append("| from | paths | end in contact | free to their next event | first contacts (parts: paths, shortest path length in a) |")
    L.append("|---|---|---|---|---|")
    for r in cm["by_node"]:
        cs = "; ".join(f"{c['parts']}: {c['paths']}, l = {c['l_min']:.4f}" for c in r["contacts"][:4])
        if len(r["contacts"]) > 4:
            cs += f"; and {len(r['contacts']) - 4} more pairs"
        L.append(f"| {r['node']} | {r['paths']} | {r['contact']} | {r['free']} | {cs or '-'} |")
    L.append("")
    if picture:
        L.append(f"![contact map]({picture})\n")
        L.append("*The contact map as the explorer draws it: the paths that end in contact in their own colour, "
                 "the others to the bifurcation they reach.*\n")
    return L
