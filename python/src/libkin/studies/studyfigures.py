"""The figures of the hexagonal (or other centre-supported) sail study's report (studyreport.py writes
the text). Lengths are in units of the hub side a; every figure has a
legend or direct labels, and the report a caption for it."""
import re

import numpy as np

from libkin.plot import draw, draw3d, pyplot

from .sailmeasure import BAR_KINDS, bar_kinds, fold_angles, fold_segments

UNIT = "a"  # the model's length unit: the hub side (Assembly.sail(side=1))


def tex(name):
    """'R^B'' -> '$R^{B}$'' for matplotlib labels."""
    return re.sub(r"R\^([A-Z])", r"$R^{\1}$", name) if name else name


def _legend_handles(plt, kinds_present, fixed_kinds):
    from matplotlib.lines import Line2D
    h = [Line2D([], [], **draw3d.KIND_STYLE[k], label=k) for k in BAR_KINDS if k in kinds_present]
    if "pinned" in fixed_kinds:
        h.append(Line2D([], [], ls="", marker="^", color="k", ms=7, label="support: x, y, z fixed"))
    if "partial" in fixed_kinds:
        h.append(Line2D([], [], ls="", marker="s", color="k", ms=6, label="support: x, y fixed, z free"))
    return h


class Model:
    """The sail's bars, their kinds and supports, shared by the figures."""

    def __init__(self, n_sides, n_loops):
        from libkin.assembly import Assembly
        a = Assembly.sail(n_sides, n_loops)
        self.a = a
        self.labels = a.labels
        self.bars = a.bars
        self.kinds = bar_kinds(a.labels, a.bars)
        self.fixed = a.fixed
        self.flat = a.coords
        self.fmap = a.free_map()
        self.segments = fold_segments(a.labels, n_sides, n_loops)


def model_figure(M, out):
    """The flat model, joints numbered, bars by kind, supports marked."""
    plt = pyplot()
    x = M.flat
    fig, ax = plt.subplots(figsize=(8.0, 8.0))
    for (p, q), k in zip(M.bars.tolist(), M.kinds):
        ax.plot(*x[[p, q], :2].T, **draw3d.KIND_STYLE[k], zorder=1)
    sk = draw3d.support_kinds(M.fixed)
    for i, (lab, s) in enumerate(zip(M.labels, sk)):
        marker, size = {"pinned": ("^", 11), "partial": ("s", 9)}.get(s, ("o", 5))
        ax.plot(*x[i, :2], marker, color="k" if s else "0.25", ms=size, zorder=3)
        # labels pushed radially outwards (the centre's to the upper right)
        r = np.hypot(*x[i, :2])
        u = x[i, :2] / r if r > 1e-9 else np.array([0.7, 0.7])
        free = "".join(c for c, f in zip("xyz", M.fmap[i] >= 0) if f) or "pinned"
        ax.annotate(f"{i}: {lab}\n({free})", x[i, :2], xytext=tuple(17 * u), textcoords="offset points",
                    ha="center", va="center", fontsize=7.5,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8), zorder=4)
    ax.legend(handles=_legend_handles(plt, set(M.kinds), set(sk)), loc="lower right", fontsize=8,
              title="bars and supports", title_fontsize=8, framealpha=0.95)
    ax.set_aspect("equal")
    lim = np.abs(x[:, :2]).max() + 0.45
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel(f"x ({UNIT} = hub side)")
    ax.set_ylabel(f"y ({UNIT})")
    ax.set_title(f"The model, flat (z = 0), from above: {len(M.labels)} joints marked 'index: label\n"
                 f"(free coordinates)', {len(M.bars)} bars; lengths in hub sides a", fontsize=10)
    ax.grid(True, alpha=0.2)
    fig.tight_layout()
    draw3d.save_small(fig, out / "model.png", 90)
    plt.close(fig)


def stages_2d(M, stages, out):
    """Figure 13: x-y (top) and x-z (bottom) projections of the stages."""
    plt = pyplot()
    fig, axs = plt.subplots(2, len(stages), figsize=(3.2 * len(stages), 7.0), squeeze=False)
    pinned = M.fixed.all(axis=1)
    for k, (title, x) in enumerate(stages):
        draw(x, M.bars, ax=axs[0, k], plane="xy", fixed=pinned, title=title)
        draw(x, M.bars, ax=axs[1, k], plane="xz", fixed=pinned, color="C1")
        for r, pl in enumerate(("y", "z")):
            axs[r, k].set_xlim(-2.4, 2.4)
            axs[r, k].set_ylim(-2.4, 2.4)
            axs[r, k].set_xlabel(f"x ({UNIT})")
            axs[r, k].set_ylabel(f"{pl} ({UNIT})")
    from matplotlib.lines import Line2D
    fig.legend(handles=[Line2D([], [], color="C0", label="bars, seen from above (x-y)"),
                        Line2D([], [], color="C1", label="bars, seen from the side (x-z)"),
                        Line2D([], [], ls="", marker="^", color="k", label="pinned hub vertices V0, V2, ...")],
               loc="lower center", ncol=3, fontsize=9, frameon=False)
    fig.suptitle("Figure 13-like: folding stages, projected on x-y (top) and x-z (bottom); lengths in hub sides a")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    draw3d.save_small(fig, out / "fig13_stages.png", 80)
    plt.close(fig)


def stages_3d(M, stages, out):
    """The same stages in 3D, one scale on every axis."""
    plt = pyplot()
    n = len(stages)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig = plt.figure(figsize=(4.2 * cols, 3.6 * rows + 0.6))
    allp = np.concatenate([x for _, x in stages])
    for k, (title, x) in enumerate(stages):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        draw3d.draw3d(ax, x, M.bars, M.kinds, M.fixed, joint_size=5)
        draw3d.equal_limits(ax, allp, pad=0.0, zoom=1.1)
        ax.view_init(24, -62)
        ax.set_title(tex(title), fontsize=10)
        ax.tick_params(labelsize=6, pad=0)
        ax.set_xticks([-2, 0, 2])
        ax.set_yticks([-2, 0, 2])
        ax.set_zticks([-1, 0, 1])
    handles = _legend_handles(plt, set(M.kinds), set(draw3d.support_kinds(M.fixed)))
    if n < rows * cols:
        # the legend in the empty last cell
        fig.legend(handles=handles, loc="center", bbox_to_anchor=(1 - 0.5 / cols, 0.5 / rows), fontsize=9,
                   title="bars and supports", frameon=False)
    else:
        fig.legend(handles=handles, loc="lower center", ncol=7, fontsize=8, frameon=False)
    fig.suptitle(f"The folding stages in 3D (equal scale on x, y, z; axes in hub sides {UNIT})", fontsize=11)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.93, wspace=0.02, hspace=0.05)
    draw3d.save_small(fig, out / "stages_3d.png", 80)
    plt.close(fig)


def _event_marks(ax, res, y_top=True):
    for k, v in res["events"].items():
        if v and "l_total" in v:
            ax.axvline(v["l_total"], color="k", ls=":", lw=0.8)
            if y_top:
                ax.text(v["l_total"], 1.01, tex(k.split("_")[0].replace("R", "R^")), transform=ax.get_xaxis_transform(),
                        ha="center", va="bottom", fontsize=9)


def singular_values(res, track, out):
    """Figure 14, the curves grouped by where they vanish."""
    plt = pyplot()
    l = np.array(track.l)
    sv = np.array(track.sv)
    ev = [(k.split("_")[0].replace("R", "R^"), v) for k, v in res["events"].items() if v and "l_total" in v]
    # column j (the (j+1)-th lowest value) vanishes where s > j: group the
    # columns by the set of points where they vanish
    groups = {}
    for j in range(sv.shape[1]):
        where = ["R^A"] + [name for name, v in ev if v["s"] > j and name != "R^A"]
        key = tuple(dict.fromkeys(where))
        groups.setdefault(key, []).append(j)
    cmaps = ["Reds", "Blues", "Greens", "Purples", "Oranges"]
    fig, ax = plt.subplots(figsize=(9.5, 5.0))
    for g, (where, cols) in enumerate(groups.items()):
        cmap = plt.get_cmap(cmaps[g % len(cmaps)])
        for t, j in enumerate(cols):
            shade = 0.85 - 0.45 * t / max(1, len(cols) - 1)
            lab = None
            if t == 0:
                rng = f"$\\sigma_{{{cols[0] + 1}}}$" + (f"-$\\sigma_{{{cols[-1] + 1}}}$" if len(cols) > 1 else "")
                lab = f"{rng} ({len(cols)}): vanish at " + ", ".join(tex(w) for w in where)
            ax.plot(l, sv[:, j], lw=1.3 if g == 0 else 1.0, color=cmap(shade), label=lab)
    _event_marks(ax, res)
    ax.set_xlabel(f"path length travelled ({UNIT}), fold R^A -> R^B -> R^C, then deploy back".replace("R^", "R^")
                  .replace("R^A", "$R^A$").replace("R^B", "$R^B$").replace("R^C", "$R^C$"))
    ax.set_ylabel("singular value of H (dimensionless)")
    ax.set_title(f"Figure 14-like: the {sv.shape[1]} lowest singular values of H, "
                 "$\\sigma_1$ the lowest", fontsize=11, pad=18)
    ax.legend(fontsize=8.5, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=1, frameon=False)
    ax.grid(True, alpha=0.25)
    fig.tight_layout()
    draw3d.save_small(fig, out / "fig14_singular_values.png", 90)
    plt.close(fig)
    return groups


def strain_hub(res, track, out):
    plt = pyplot()
    l = np.array(track.l)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5.2), sharex=True)
    a1.semilogy(l, np.maximum(track.strain, 1e-18), ".", ms=3, label="at an accepted step or a bifurcation")
    a1.axhline(1e-12, color="C3", lw=0.8, ls="--", label="corrector tolerance 1e-12")
    a1.set_ylabel("max bar strain |L - L0| / L0")
    a1.legend(fontsize=8, loc="upper right")
    a2.plot(l, track.hub_z, "-", label="free hub vertices V1, V3, ... (V0, V2, ... are pinned at z = 0)")
    a2.set_ylabel(f"max |z| of hub vertices ({UNIT})")
    a2.set_xlabel(f"path length travelled ({UNIT})")
    a2.legend(fontsize=8, loc="upper right")
    for ax in (a1, a2):
        _event_marks(ax, res, y_top=ax is a1)
        ax.grid(True, alpha=0.25)
    a1.set_title("Bar strain along the run, and how far the hub leaves its plane", fontsize=11, pad=16)
    fig.tight_layout()
    draw3d.save_small(fig, out / "strain_hub.png", 90)
    plt.close(fig)


def fold_measures(M, res, track, out):
    """How far the sail has folded, against path length: fold-line angles
    to the hub plane, x-y radius and height."""
    plt = pyplot()
    l = np.array(track.l)
    X = np.array(track.coords)
    ang = np.array([fold_angles(x, M.segments) for x in X])  # (n, loops, n_sides)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(11, 6.0), sharex=True)
    styles = [("C3", "-"), ("C3", "--"), ("C0", "-"), ("C0", "--")]
    letters = ["V", "A", "B", "C", "D"]
    for q in range(ang.shape[1]):
        for par, k in (("even", 0), ("odd", 1)):
            col, ls = styles[(2 * q + k) % 4]
            a1.plot(l, ang[:, q, k], color=col, ls=ls,
                    label=f"loop {q + 1}: fold segments\n{letters[q]}k-{letters[q + 1]}k, k {par}")
    a1.set_ylabel("angle to the hub plane (deg)")
    a1.set_yticks([-90, -45, 0, 45, 90])
    a1.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    a2.plot(l, np.hypot(X[:, :, 0], X[:, :, 1]).max(axis=1), color="C2",
            label="x-y extent: largest distance\nof a joint from the hub axis")
    a2.plot(l, X[:, :, 2].max(axis=1) - X[:, :, 2].min(axis=1), color="C4", label="height: z-extent\nof the sail")
    a2.set_ylabel(f"length ({UNIT})")
    a2.set_xlabel(f"path length travelled ({UNIT})")
    a2.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    for ax in (a1, a2):
        _event_marks(ax, res, y_top=ax is a1)
        ax.grid(True, alpha=0.25)
    a1.set_title("How far the sail has folded along the run", fontsize=11, pad=16)
    fig.tight_layout()
    draw3d.save_small(fig, out / "fold_measures.png", 90)
    plt.close(fig)


def _short_label(names):
    """'X5, X5', X6, X6'' -> 'X5, X6 (+ mirrors)'; keeps R^ names first."""
    names = sorted(set(names), key=lambda s: (not s.startswith("R"), len(s.rstrip("'")), s))
    base = [n for n in names if not n.endswith("'")]
    mirrored = all(b + "'" in names for b in base) and len(base) * 2 == len(names)
    if mirrored:
        return ", ".join(tex(b) for b in base) + (" (+')" if base else "")
    return ", ".join(tex(n) for n in names)


# how the path map draws a node of each kind (the atlas's kinds, libkin.atlas.model):
# only a bifurcation is a filled marker; a bifurcation the follower located
# only to a coarser v_r is filled in another colour; every point that is not
# a bifurcation is hollow
MAP_STYLE = {  # key: (marker, filled, colour, legend)
    "bifurcation": ("o", True, "C0", "bifurcation (m >= 2, s >= 1), located to v_r <= 1e-10 v_max"),
    "relaxed": ("D", True, "C1", "bifurcation located only to v_r <= 1e-8 .. 1e-7 v_max "
                "(m, s counted at 10 x that)"),
    "near_miss": ("o", False, "C2", "near-miss (m = 1): a dip of v_r, regular"),
    "regular": ("s", False, "0.4", "regular point (m = 1): path-length budget"),
    "multi_dof": ("^", False, "C4", "several freedoms (m >= 2, s = 0)"),
    "rigid": ("v", False, "k", "rigid (m = 0)"),
    "failure": ("X", False, "C5", "following failed"),
}
ROUTE = ("R^A", "R^B", "R^C")


def _map_style(smap, n):
    return "relaxed" if smap.relaxed(n) else n.kind


def path_map(smap, out):
    """The path map of the explorer's atlas (sailmap.SailMap): nodes at
    (x-y extent, m), their kind by the marker (MAP_STYLE); a node and its
    mirror image (same place) drawn once; line width grows with the number
    of directed paths; the fold route R^A - R^B - R^C in red. Labels are
    placed where they overlap no other label or node (leader lines when
    moved away)."""
    plt = pyplot()
    from matplotlib.lines import Line2D
    nodes, names = smap.nodes, smap.names()
    # nodes of one kind at the same (x-y extent, m) share a marker; where
    # several kinds meet, the bifurcation keeps the place and the others
    # are drawn a little above it
    place, label, style, kinds_at = {}, {}, {}, {}
    base_of = {n.id: (round(smap.measures(n)["xy_extent"], 3), max(n.m, 1)) for n in nodes}
    for n in nodes:
        kinds_at.setdefault(base_of[n.id], set()).add(_map_style(smap, n))
    for n in nodes:
        base, st = base_of[n.id], _map_style(smap, n)
        rank = [k for k in MAP_STYLE if k in kinds_at[base]].index(st)
        key = (base[0], base[1] * 1.09 ** rank)
        place[n.id] = key
        label.setdefault(key, []).append(names[n.id])
        style[key] = st
    fig, ax = plt.subplots(figsize=(11, 7.2))
    agg = {}
    for e in smap.atlas.edges:
        if place[e.source] != place[e.target]:
            k = (place[e.source], place[e.target])
            agg[k] = agg.get(k, 0) + 1
    key_of = {nm: place[i] for i, nm in names.items()}
    # a run's point and its mirror image share a place: the route is drawn
    # to whichever of them the atlas holds
    at_ = {r: key_of.get(r, key_of.get(r + "'")) for r in ROUTE}
    route = {(at_["R^A"], at_["R^B"]), (at_["R^B"], at_["R^C"])}
    for (p, q), cnt in agg.items():
        on_route = (p, q) in route
        ax.annotate("", xy=q, xytext=p,
                    arrowprops=dict(arrowstyle="->", color="C3" if on_route else "0.6",
                                    lw=(2.4 if on_route else 0.6 + 0.3 * cnt), shrinkA=7, shrinkB=7,
                                    connectionstyle="arc3,rad=0.15", alpha=1.0 if on_route else 0.8),
                    zorder=2 if on_route else 1)
    for key, nm in label.items():
        main = any(n.rstrip("'") in ROUTE for n in nm)
        marker, filled, colour, _ = MAP_STYLE[style[key]]
        colour = "C3" if main and style[key] == "bifurcation" else colour
        ax.plot(*key, marker, mfc=colour if filled else "white", mec=colour, mew=1.0 if filled else 1.8,
                ms=11 if main else 7, ls="", zorder=3)
    handles = [Line2D([], [], ls="", marker=MAP_STYLE[k][0], ms=7, mec=MAP_STYLE[k][2],
                      mfc=MAP_STYLE[k][2] if MAP_STYLE[k][1] else "white", mew=1.0 if MAP_STYLE[k][1] else 1.8,
                      label=MAP_STYLE[k][3]) for k in MAP_STYLE if k in set(style.values())]
    handles.append(Line2D([], [], color="C3", lw=2.4, label="the run's fold $R^A$ - $R^B$ - $R^C$"))
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, frameon=False)
    ax.invert_xaxis()
    ms = sorted({round(k[1]) for k in label})
    ax.set_yscale("log")
    ax.set_yticks(ms)
    ax.set_yticklabels([str(m) for m in ms])
    ax.minorticks_off()
    ax.set_ylim(min(ms) * 0.8, max(ms) * 1.35)
    xs = [k[0] for k in label]
    ax.set_xlim(max(xs) + 0.12, min(xs) - 0.12)
    ax.set_xlabel(f"x-y extent of the sail (largest distance of a joint from the hub axis, {UNIT}): "
                  "unfolded (left) -> folded (right)")
    ax.set_ylabel("internal mechanisms m at the node")
    ax.set_title("Path map: the points reached along symmetric paths (the explorer's atlas)\nred: the run's fold "
                 "$R^A$ - $R^B$ - $R^C$; ' = mirror image z -> -z, (+') = each with its mirror image", fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    # labels: try offsets near the node until the text box hits no other
    # label and no node marker
    fig.canvas.draw()
    rend = fig.canvas.get_renderer()
    taken = []
    for key in label:
        px, py = ax.transData.transform(key)
        taken.append((px - 7, py - 7, px + 7, py + 7))
    cands = [(0, 11), (0, -13), (0, 24), (0, -26), (0, 37), (0, -39), (0, 50), (0, -52), (35, 11), (-35, 11),
             (35, -13), (-35, -13), (0, 63), (0, -65)]
    for key in sorted(label, key=lambda k: (-k[1], -k[0])):
        nm = label[key]
        main = any(n.rstrip("'") in ROUTE for n in nm)
        text = _short_label(nm)
        for dx, dy in cands:
            t = ax.annotate(text, key, xytext=(dx, dy), textcoords="offset points", ha="center",
                            va="bottom" if dy > 0 else "top", fontsize=8.5 if main else 7.5,
                            fontweight="bold" if main else "normal", zorder=4,
                            bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85))
            bb = t.get_window_extent(rend)
            box = (bb.x0, bb.y0, bb.x1, bb.y1)
            clash = any(not (box[2] < o[0] or box[0] > o[2] or box[3] < o[1] or box[1] > o[3]) for o in taken)
            inside = ax.get_window_extent(rend)
            fits = inside.x0 <= box[0] and box[2] <= inside.x1 and inside.y0 <= box[1] and box[3] <= inside.y1
            if not clash and fits:
                if abs(dy) > 14 or dx:
                    t.remove()
                    t = ax.annotate(text, key, xytext=(dx, dy), textcoords="offset points", ha="center",
                                    va="bottom" if dy > 0 else "top", fontsize=8.5 if main else 7.5,
                                    fontweight="bold" if main else "normal", zorder=4,
                                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85),
                                    arrowprops=dict(arrowstyle="-", color="0.4", lw=0.6, shrinkA=0, shrinkB=4))
                taken.append(box)
                break
            t.remove()
        else:
            ax.annotate(text, key, xytext=(0, 11), textcoords="offset points", ha="center", fontsize=7.5)
    draw3d.save_small(fig, out / "path_map.png", 95)
    plt.close(fig)


def branch_grid(M, name, snap, base, out, fname):
    """Small multiples: the configuration a short way along every directed
    path leaving the bifurcation `name`."""
    pyplot()  # the Agg backend, before pyplot is touched
    from matplotlib.lines import Line2D
    colours = {"chosen": "C3", "straight on": "C2", "back to R^A": "C1", "back to R^B": "C1"}
    panels = []
    for p in snap["paths"]:
        sign = "+" if p["sign"] > 0 else "-"
        title = f"{sign}b{p['beta']}"
        if p.get("to"):
            title += f" -> {tex(p['to'])}"
        elif p["tag"]:
            title += " (the run)" if p["tag"] == "chosen" else f" ({tex(p['tag'])})"
        if not p["symmetric"]:
            title += " (asym.)"
        panels.append({"coords": p["coords"], "title": title, "color": colours.get(p["tag"], "k")})
    legend = [Line2D([], [], color="C3", lw=3, label="the path the run takes")]
    tags = {p["tag"] for p in snap["paths"]}
    if "straight on" in tags:
        legend.append(Line2D([], [], color="C2", lw=3, label="the arrival path, continued"))
    if any(t.startswith("back") for t in tags):
        legend.append(Line2D([], [], color="C1", lw=3, label="the arrival path, retraced"))
    n_sym = sum(p["symmetric"] for p in snap["paths"])
    what = "symmetric directed paths" if n_sym == len(snap["paths"]) else "directed paths"
    return draw3d.small_multiples(panels, M.bars, M.kinds, M.fixed, out / fname,
                                  f"The {len(panels)} {what} out of {tex(name)}, seen from above at path length "
                                  f"{snap['length']} {UNIT} from it\n('+b3' = second-order solution 3, + sense; "
                                  "-> the next bifurcation it reaches)", base, cols=8, legend=legend)


def animation(M, res, track, out, n_frames=48):
    """GIF of the fold and back, at one scale and camera."""
    l = np.array(track.l)
    idx = np.unique(np.round(np.linspace(0, len(l) - 1, n_frames)).astype(int))
    marks = [(0.0, "R^A")] + [(v["l_total"], k.split("_")[0].replace("R", "R^"))
                              for k, v in res["events"].items() if v and "l_total" in v]
    titles = []
    for i in idx:
        prev = max((m for m in marks if m[0] <= l[i] + 1e-9), key=lambda m: m[0])
        nxt = [m for m in marks if m[0] > l[i] + 1e-9]
        where = (f"at {prev[1]}" if abs(l[i] - prev[0]) < 1e-6 or not nxt else f"{prev[1]} -> {nxt[0][1]}")
        x = track.coords[i]
        titles.append(f"{tex(where)}   l = {l[i]:.2f} {UNIT}, x-y extent {np.hypot(x[:, 0], x[:, 1]).max():.2f} {UNIT}")
    frames = [track.coords[i] for i in idx]
    # the bare membrane (contactstudy.py: every bar triangle and the hub as
    # panels) on every frame: the two closest parts that share no joint,
    # where they touch or pass through each other
    highlight, note = None, None
    if "interference" in res:
        from .sailmeasure import TOUCH, sail_panels
        model = M.a.clone()
        panels = sail_panels(M.a)
        model.panels = panels
        highlight = []
        for x in frames:
            c = model.clearance(x)
            highlight.append([list(M.bars[i]) if kind == "bar" else list(panels[i]) for kind, i in c.parts]
                             if c.value <= TOUCH else [])
        if any(highlight):
            note = "magenta: two parts of the membrane that touch or pass through each other (zero thickness)"
    draw3d.animate3d(frames, M.bars, M.kinds, M.fixed, out / "fold_animation.gif", titles, highlight=highlight,
                     note=note)
    return len(frames)
