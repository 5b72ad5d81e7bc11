"""3D drawings of bar assemblies with matplotlib's mplot3d: equal scale on
every axis, bars coloured by kind, supports marked; small multiples and
GIF animations built from them."""
import numpy as np

from ..atomic import replacing
from .draw2d import pyplot

# bar colours by kind (sailmeasure.BAR_KINDS); other kinds are drawn in C0
KIND_STYLE = {
    "hub edge": dict(color="k", lw=1.8),
    "spoke": dict(color="0.55", lw=0.9, ls="--"),
    "fold": dict(color="C3", lw=1.6),
    "ring": dict(color="C0", lw=1.2),
    "diagonal": dict(color="C9", lw=0.8),
}


def save_small(fig, path, dpi):
    """Save a figure as a 256-colour PNG (a third of the size of a full-colour
    one for line drawings; the report's stored runs stay small)."""
    import io

    from PIL import Image
    buf = io.BytesIO()
    fig.savefig(buf, dpi=dpi, format="png")
    buf.seek(0)
    with replacing(path) as tmp:  # whole or not at all
        Image.open(buf).convert("RGB").quantize(256).save(tmp, optimize=True)


def support_kinds(fixed):
    """Per joint: 'pinned' (every coordinate fixed), 'partial' (some) or ''."""
    f = np.asarray(fixed, dtype=bool)
    return ["pinned" if r.all() else "partial" if r.any() else "" for r in f]


def equal_limits(ax, pts, pad=0.05, zoom=1.0):
    """Axis limits with one scale on x, y and z (mplot3d stretches each axis
    to the box otherwise)."""
    pts = np.asarray(pts)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 1e-9)
    pad_abs = pad * span.max()
    lo, hi = lo - pad_abs, hi + pad_abs
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(hi - lo), zoom=zoom)


def _by_kind(bars, kinds):
    groups = {}
    for (p, q), k in zip(np.asarray(bars).tolist(), kinds or ["ring"] * len(bars)):
        groups.setdefault(k, []).append((p, q))
    return groups


def draw3d(ax, x, bars, kinds=None, fixed=None, joint_size=6, lw_scale=1.0, axes=True):
    """Bars (coloured by kind), joints, supports (black triangle: pinned;
    black square: some coordinates fixed) on a 3D axes. Returns the artists
    (update() moves them to new coordinates)."""
    from mpl_toolkits.mplot3d.art3d import Line3DCollection
    x = np.asarray(x)
    art = {"lines": [], "fixed": []}
    for k, pairs in _by_kind(bars, kinds).items():
        st = dict(KIND_STYLE.get(k, dict(color="C0", lw=1.0)))
        lc = Line3DCollection([x[[p, q]] for p, q in pairs], colors=st["color"], linewidths=st["lw"] * lw_scale,
                              linestyles=st.get("ls", "-"))
        ax.add_collection3d(lc)
        art["lines"].append((lc, pairs))
    art["joints"] = ax.scatter(*x.T, s=joint_size, color="0.2", depthshade=False)
    if fixed is not None:
        sk = support_kinds(fixed)
        for kind, marker in (("pinned", "^"), ("partial", "s")):
            idx = [i for i, v in enumerate(sk) if v == kind]
            if idx:
                sc = ax.scatter(*x[idx].T, marker=marker, s=6 * joint_size, color="k", depthshade=False, zorder=5)
                art["fixed"].append((sc, idx))
    if not axes:
        ax.set_axis_off()
    return art


def update(art, x):
    """Move the artists of draw3d() to configuration x."""
    for lc, pairs in art["lines"]:
        lc.set_segments([x[[p, q]] for p, q in pairs])
    art["joints"]._offsets3d = tuple(x.T)
    for sc, idx in art["fixed"]:
        sc._offsets3d = tuple(x[idx].T)


def small_multiples(panels, bars, kinds, fixed, path, suptitle, base, cols=8, size=1.6, legend=None,
                    show_move=0.25):
    """A grid of drawings from above (x-y), one per panel: dict(coords,
    title, color (title colour)), each over the start configuration `base`
    (light grey). Joints are coloured by how far they moved up or down from
    base (one colour scale for all panels, in a colour bar). When every
    panel's largest joint movement is below show_move, movements are drawn
    magnified (the same factor for all, stated in the title) so that they
    can be seen; the colours stay true. Returns the factor."""
    plt = pyplot()
    from matplotlib.collections import LineCollection
    n = len(panels)
    cols = min(cols, max(1, n))
    rows = (n + cols - 1) // cols
    base = np.asarray(base)
    move = max(1e-12, max(float(np.linalg.norm(p["coords"] - base, axis=1).max()) for p in panels))
    factor = max(1.0, show_move / move)
    shown = [base + factor * (p["coords"] - base) for p in panels]
    lim = max(float(np.hypot(x[:, 0], x[:, 1]).max()) for x in shown + [base]) + 0.15
    zmax = max(1e-9, max(float(np.abs(p["coords"][:, 2] - base[:, 2]).max()) for p in panels))
    height = size * rows + 1.7
    fig, axs = plt.subplots(rows, cols, figsize=(size * cols, height), squeeze=False)
    groups = _by_kind(bars, kinds)
    sk = support_kinds(fixed) if fixed is not None else []
    pinned = [i for i, v in enumerate(sk) if v == "pinned"]
    sc = None
    for k, ax in enumerate(axs.flat):
        ax.set_axis_off()
        if k >= n:
            continue
        p = panels[k]
        x = shown[k]
        ax.add_collection(LineCollection([base[[a, b], :2] for a, b in np.asarray(bars).tolist()], colors="0.82",
                                         linewidths=0.5))
        for kind, pairs in groups.items():
            st = KIND_STYLE.get(kind, dict(color="C0", lw=1.0))
            ax.add_collection(LineCollection([x[[a, b], :2] for a, b in pairs], colors=st["color"],
                                             linewidths=0.6 * st["lw"], linestyles=st.get("ls", "-"), alpha=0.7))
        sc = ax.scatter(x[:, 0], x[:, 1], c=p["coords"][:, 2] - base[:, 2], cmap="coolwarm", vmin=-zmax, vmax=zmax,
                        s=14,
                        edgecolors="k", linewidths=0.3, zorder=3)
        if pinned:
            ax.plot(x[pinned, 0], x[pinned, 1], "^", color="k", ms=4, zorder=4)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        col = p.get("color", "k")
        ax.set_title(p["title"], fontsize=7.5, color=col, pad=1, fontweight="bold" if col != "k" else "normal")
    if factor > 1.05:
        suptitle += f"; movements from the grey start drawn x{factor:.1f}"
    fig.suptitle(suptitle, fontsize=10)
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.85 / height, top=1 - 0.85 / height, wspace=0.04,
                        hspace=0.2)
    if sc is not None:
        cax = fig.add_axes([0.06, 0.5 / height, 0.35, 0.12 / height])
        cb = fig.colorbar(sc, cax=cax, orientation="horizontal")
        cb.set_label("joint moved up (+) or down (-) from the start, true size (hub sides a)", fontsize=8)
        cb.ax.tick_params(labelsize=7)
    if legend:
        fig.legend(handles=legend, loc="lower right", bbox_to_anchor=(0.99, 0.05 / height), ncol=1, fontsize=8,
                   frameon=False)
    save_small(fig, path, 86)
    plt.close(fig)
    return factor


def animate3d(frames, bars, kinds, fixed, path, titles, fps=10, view=(24, -62), size=(5.0, 4.2), dpi=100,
              highlight=None, note=None):
    """A GIF of configurations `frames` (list of (njoints, 3)) with a title
    per frame, at one fixed scale and camera. highlight: per frame a list
    of joint sequences (a bar's two joints, a panel's loop) drawn thick in
    magenta on that frame (the parts in contact); note: a line under the
    legend saying what they are."""
    plt = pyplot()
    allp = np.concatenate(frames)
    fig = plt.figure(figsize=size, dpi=dpi)
    ax = fig.add_subplot(111, projection="3d")
    art = draw3d(ax, frames[0], bars, kinds, fixed, joint_size=4)
    equal_limits(ax, allp, pad=0.0, zoom=1.15)
    ax.view_init(*view)
    ax.set_xticks([-2, 0, 2])
    ax.set_yticks([-2, 0, 2])
    ax.set_zticks([-1, 0, 1])
    ax.tick_params(labelsize=6, pad=0)
    title = ax.set_title(titles[0], fontsize=8)
    fig.text(0.5, 0.02, "black: hub; red: fold lines; blue: rings and diagonals; triangles: pinned supports; "
             "axes in hub sides a", ha="center", fontsize=6.5)
    if note:
        fig.text(0.5, 0.055, note, ha="center", fontsize=6.5, color="#c2188c")
    fig.subplots_adjust(left=0, right=0.97, bottom=0.05, top=0.95)
    # the highlighted parts: a few lines, redrawn on every frame
    marks = [ax.plot([], [], [], color="#e0199a", lw=3.0)[0] for _ in range(max((len(h) for h in highlight or [[]]),
                                                                              default=0))]
    # frames drawn by matplotlib, written by Pillow with one shared palette:
    # unchanged pixels then compress across frames (half the size of
    # matplotlib's PillowWriter, which palettes every frame on its own)
    from PIL import Image
    images = []
    for k in range(len(frames)):
        update(art, frames[k])
        title.set_text(titles[k])
        for j, line in enumerate(marks):
            seq = highlight[k][j] if highlight and j < len(highlight[k]) else []
            pts = frames[k][list(seq) + list(seq[:1] if len(seq) > 2 else [])] if len(seq) else np.zeros((0, 3))
            line.set_data_3d(pts[:, 0], pts[:, 1], pts[:, 2])
        fig.canvas.draw()
        images.append(Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy()))
    plt.close(fig)
    palette = images[len(images) // 2].quantize(64)
    pal = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    with replacing(path) as tmp:  # whole or not at all
        pal[0].save(tmp, save_all=True, append_images=pal[1:], duration=int(1000 / fps), loop=0, optimize=True)
    return path
