"""Plots with matplotlib (Agg): structures, singular values along a path,
and path animations. Each function returns the matplotlib Figure and, given
a path, writes the image there."""
import numpy as np

from ..atomic import replacing

_PLANES = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def pyplot():
    """matplotlib.pyplot on the Agg backend (ImportError naming the extra if
    matplotlib is missing)."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("libkin.plot needs matplotlib: pip install 'libkin[plot]' (or matplotlib pillow)") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


_plt = pyplot  # the name the package used before pyplot() was public


def draw(assembly_or_coords, bars=None, ax=None, plane="xy", fixed=None, labels=None, color="C0",
         path=None, title=None):
    """Draw bars and joints; 3D structures are projected on `plane`
    ('xy', 'xz' or 'yz', like the paper's Figures 11 and 13). `fixed` is
    per joint (pinned) or per coordinate, (njoints, dim): joints with every
    coordinate fixed are drawn as black triangles, those with only some
    (rollers) as open squares, with a legend."""
    plt = pyplot()
    if bars is None:
        a = assembly_or_coords
        coords, bars, fixed = a.coords, a.bars, a.fixed
        labels = labels if labels is not None else a.labels
        title = title or a.name
    else:
        coords = np.asarray(assembly_or_coords)
    if coords.shape[1] == 2:
        i, j = 0, 1
    else:
        if plane not in _PLANES:
            raise ValueError(f"plane must be one of {sorted(_PLANES)}")
        i, j = _PLANES[plane]
    fig = None
    if ax is None:
        fig, ax = plt.subplots(figsize=(5, 5))
    for p, q in bars:
        ax.plot([coords[p, i], coords[q, i]], [coords[p, j], coords[q, j]], "-", color=color, lw=1.2)
    ax.plot(coords[:, i], coords[:, j], "o", color=color, ms=3)
    if fixed is not None:
        f = np.asarray(fixed, dtype=bool)
        pinned = f if f.ndim == 1 else f.all(axis=1)
        partial = np.zeros_like(pinned) if f.ndim == 1 else f.any(axis=1) & ~pinned
        if pinned.any():
            ax.plot(coords[pinned, i], coords[pinned, j], "^", color="k", ms=7, label="pinned (all coordinates fixed)")
        if partial.any():
            ax.plot(coords[partial, i], coords[partial, j], "s", mfc="none", mec="k", ms=8, mew=1.2,
                    label="roller (some coordinates fixed)")
        if pinned.any() or partial.any():
            ax.legend(loc="best", fontsize=7)
    if labels:
        for k, lab in enumerate(labels):
            ax.annotate(lab, (coords[k, i], coords[k, j]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_aspect("equal")
    ax.set_xlabel("xyz"[i])
    ax.set_ylabel("xyz"[j])
    if title:
        ax.set_title(title)
    fig = fig or ax.figure
    if path:
        with replacing(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=110)
    return fig


def singular_values(l, sv, path=None, count=None, title="singular values along the path"):
    """Lowest singular values against path length (cf. the paper's Figures 8
    and 14): l (n,), sv (n, k) descending per row; the `count` smallest are drawn."""
    plt = pyplot()
    l = np.asarray(l)
    sv = np.asarray(sv)
    if count is not None:
        sv = sv[:, -count:]
    fig, ax = plt.subplots(figsize=(7, 4))
    for c in range(sv.shape[1]):
        ax.semilogy(l, np.maximum(sv[:, c], 1e-17), lw=1)
    ax.set_xlabel("path length l")
    ax.set_ylabel("singular value")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    if path:
        with replacing(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=110)
    return fig


def branch_directions(assembly, directions, path=None, plane="xy", scale=0.3):
    """Each candidate first-order motion (nfree vectors), one panel per
    direction: in-plane components as arrows, the out-of-plane component as
    discs (red = towards the viewer, blue = away, area ~ magnitude)."""
    plt = pyplot()
    directions = [np.asarray(d) for d in directions]
    n = max(1, len(directions))
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    fmap = assembly.free_map()
    coords = assembly.coords
    i, j = (0, 1) if assembly.dim == 2 else _PLANES[plane]
    for k, d in enumerate(directions):
        ax = axes[k // cols][k % cols]
        draw(assembly, ax=ax, plane=plane, title=f"direction {k}")
        disp = np.zeros_like(coords)
        mask = fmap >= 0
        disp[mask] = d[fmap[mask]]
        ax.quiver(coords[:, i], coords[:, j], disp[:, i], disp[:, j], angles="xy", scale_units="xy",
                  scale=1 / scale, color="C3", width=0.006)
        if assembly.dim == 3:
            # the out-of-plane component (e.g. z for 'xy', where a flat sail's
            # mechanisms live): red up, blue down, area ~ magnitude
            k = 3 - i - j
            out = disp[:, k]
            big = np.abs(out).max()
            if big > 0:
                ax.scatter(coords[:, i], coords[:, j], s=300 * np.abs(out) / big, c=np.sign(out), cmap="coolwarm",
                           vmin=-1, vmax=1, alpha=0.6, edgecolors="k", linewidths=0.5, zorder=3)
    for k in range(len(directions), rows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.tight_layout()
    if path:
        with replacing(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=110)
    return fig


def animate(frames, bars, path, plane="xy", fps=10):
    """Write a GIF of a path: frames is a list of (njoints, dim) coordinates."""
    plt = pyplot()
    from matplotlib.animation import FuncAnimation, PillowWriter
    frames = [np.asarray(f) for f in frames]
    allc = np.concatenate(frames)
    i, j = (0, 1) if allc.shape[1] == 2 else _PLANES[plane]
    fig, ax = plt.subplots(figsize=(5, 5))
    pad = 0.1 * (allc[:, [i, j]].max() - allc[:, [i, j]].min() + 1e-9)

    def update(k):
        ax.clear()
        draw(frames[k], bars, ax=ax, plane=plane, title=f"frame {k}")
        ax.set_xlim(allc[:, i].min() - pad, allc[:, i].max() + pad)
        ax.set_ylim(allc[:, j].min() - pad, allc[:, j].max() + pad)

    anim = FuncAnimation(fig, update, frames=len(frames))
    with replacing(path) as tmp:  # whole or not at all
        anim.save(tmp, writer=PillowWriter(fps=fps))
    plt.close(fig)
    return path
