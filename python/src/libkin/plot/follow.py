"""The pictures of `libkin follow`: a followed path as a GIF that explains
itself (bars, joints, supports, a legend saying what the frame counter and
the path length are; a 3D model drawn in 3D in one box fitted to the whole
path, a planar one in 2D), and the singular values along the path with a
legend naming each curve. `path_picture` builds the figure of one frame and
returns its artists, so what is drawn can be checked without pixels."""
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..atomic import replacing
from .draw2d import pyplot
from .draw3d import equal_limits

# per support kind: (marker, legend label); a joint with every coordinate
# fixed is pinned, one with only some fixed slides (a roller)
SUPPORT_STYLE = {
    "pinned": ("^", "supports: joint fixed (every coordinate)"),
    "partial": ("s", "supports: some coordinates fixed (roller)"),
}
FRAME_NOTE = "frame k of n: the k-th step along the path; l: path length from the start (model length units)"


def _supports(fixed: Any, njoints: int) -> Dict[str, List[int]]:
    """Joint indices per support kind; `fixed` per joint or (njoints, dim)."""
    if fixed is None:
        return {}
    f = np.asarray(fixed, dtype=bool).reshape(njoints, -1)
    pinned = f.all(axis=1)
    partial = f.any(axis=1) & ~pinned
    return {k: np.flatnonzero(m).tolist() for k, m in (("pinned", pinned), ("partial", partial)) if m.any()}


class PathPicture:
    """One figure for every frame of a path: `show(k)` moves the artists to
    frame k and sets the title. Attributes: fig, ax (3D for a 3D model),
    artists (label -> artist: 'bars', 'joints' and one per support kind,
    labelled 'supports: ...'), legend."""

    def __init__(self, frames: Sequence[Any], bars: Any, fixed: Any = None, lengths: Optional[Sequence[float]] = None,
                 name: str = "", view: Tuple[float, float] = (24, -62), size: Tuple[float, float] = (5.6, 5.2)):
        from matplotlib.lines import Line2D
        plt = pyplot()
        self.frames = [np.asarray(f, dtype=float) for f in frames]
        self.bars = np.asarray(bars, dtype=int).reshape(-1, 2)
        self.lengths = list(lengths) if lengths is not None else None
        self.name = name
        x = self.frames[0]
        self.dim = x.shape[1]
        allp = np.concatenate(self.frames)
        self.fig = plt.figure(figsize=size)
        self.artists: Dict[str, Any] = {}
        self._support_idx = _supports(fixed, len(x))
        if self.dim == 3:
            from mpl_toolkits.mplot3d.art3d import Line3DCollection
            self.ax = self.fig.add_subplot(111, projection="3d")
            bars_art = Line3DCollection(self._segments(x), colors="C0", linewidths=1.3)
            self.ax.add_collection3d(bars_art)
            self.artists["joints"] = self.ax.scatter(*x.T, s=10, color="0.2", depthshade=False)
            for kind, idx in self._support_idx.items():
                marker, label = SUPPORT_STYLE[kind]
                self.artists[label] = self.ax.scatter(*x[idx].T, marker=marker, s=60, color="k", depthshade=False)
            # one box for the whole path, one scale on every axis: nothing leaves the frame
            equal_limits(self.ax, allp, pad=0.05, zoom=1.25)
            self.ax.view_init(*view)
            self.ax.set_xlabel("x")
            self.ax.set_ylabel("y")
            self.ax.set_zlabel("z")
            self.ax.tick_params(labelsize=7)
        else:
            from matplotlib.collections import LineCollection
            self.ax = self.fig.add_subplot(111)
            bars_art = LineCollection(self._segments(x), colors="C0", linewidths=1.3)
            self.ax.add_collection(bars_art)
            self.artists["joints"] = self.ax.scatter(x[:, 0], x[:, 1], s=10, color="0.2", zorder=3)
            for kind, idx in self._support_idx.items():
                marker, label = SUPPORT_STYLE[kind]
                self.artists[label] = self.ax.scatter(x[idx, 0], x[idx, 1], marker=marker, s=60, color="k", zorder=4)
            lo, hi = allp.min(axis=0), allp.max(axis=0)
            pad = 0.08 * max(float((hi - lo).max()), 1e-9)
            self.ax.set_xlim(lo[0] - pad, hi[0] + pad)
            self.ax.set_ylim(lo[1] - pad, hi[1] + pad)
            self.ax.set_aspect("equal")
            self.ax.set_xlabel("x")
            self.ax.set_ylabel("y")
        self.artists["bars"] = bars_art
        bars_art.set_label("bars")
        self.artists["joints"].set_label("joints")
        for label in self.artists:
            if label.startswith("supports"):
                self.artists[label].set_label(label)
        handles = [Line2D([], [], color="C0", lw=1.3, label="bars"),
                   Line2D([], [], ls="", marker="o", color="0.2", ms=3, label="joints")]
        for kind in self._support_idx:
            marker, label = SUPPORT_STYLE[kind]
            handles.append(Line2D([], [], ls="", marker=marker, color="k", ms=7, label=label))
        handles.append(Line2D([], [], ls="", label=FRAME_NOTE))
        self.legend = self.fig.legend(handles=handles, loc="lower center", fontsize=7, ncol=1, frameon=False,
                                      handlelength=1.5)
        if self.dim == 3:
            self.fig.subplots_adjust(left=0.0, right=0.96, top=0.92, bottom=0.16)
        else:
            self.fig.subplots_adjust(left=0.13, right=0.95, top=0.93, bottom=0.24)
        self.title = self.ax.set_title("", fontsize=9, pad=2 if self.dim == 3 else 6)
        self.show(0)

    def _segments(self, x: np.ndarray) -> List[np.ndarray]:
        return [x[[p, q]] for p, q in self.bars.tolist()]

    def show(self, k: int) -> "PathPicture":
        """Move the drawing to frame k (title: frame k of n, path length)."""
        x = self.frames[k]
        self.artists["bars"].set_segments(self._segments(x))
        if self.dim == 3:
            self.artists["joints"]._offsets3d = tuple(x.T)
        else:
            self.artists["joints"].set_offsets(x)
        for kind, idx in self._support_idx.items():
            art = self.artists[SUPPORT_STYLE[kind][1]]
            if self.dim == 3:
                art._offsets3d = tuple(x[idx].T)
            else:
                art.set_offsets(x[idx])
        text = f"frame {k} of {len(self.frames) - 1}"
        if self.lengths is not None:
            text += f", path length l = {self.lengths[k]:.4g}"
        self.title.set_text(f"{self.name}: {text}" if self.name else text)
        return self


def path_picture(frames: Sequence[Any], bars: Any, fixed: Any = None, lengths: Optional[Sequence[float]] = None,
                 name: str = "", frame: int = 0) -> PathPicture:
    """The picture of a path at `frame` (see PathPicture)."""
    return PathPicture(frames, bars, fixed, lengths, name).show(frame)


def animate_path(frames: Sequence[Any], bars: Any, path: str, fixed: Any = None,
                 lengths: Optional[Sequence[float]] = None, name: str = "", fps: int = 10) -> str:
    """Write a GIF of a path, one PathPicture frame per configuration
    (frames drawn by matplotlib, written by Pillow with one shared palette)."""
    plt = pyplot()
    from PIL import Image
    pic = PathPicture(frames, bars, fixed, lengths, name)
    images = []
    for k in range(len(pic.frames)):
        pic.show(k)
        pic.fig.canvas.draw()
        images.append(Image.fromarray(np.asarray(pic.fig.canvas.buffer_rgba())[:, :, :3].copy()))
    plt.close(pic.fig)
    palette = images[len(images) // 2].quantize(64)
    pal = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    with replacing(path) as tmp:  # whole or not at all
        pal[0].save(tmp, format="GIF", save_all=True, append_images=pal[1:], duration=int(1000 / fps), loop=0,
                    optimize=True)
    return path


def path_singular_values(lengths: Sequence[float], svs: Any, v_r: Any, v_max: Any, count: int = 15,
                         passed: Sequence[Tuple[int, float, float]] = (), path: Optional[str] = None,
                         title: str = "singular values of H along the path"):
    """The `count` lowest singular values of H (grey; H holds the bars'
    direction cosines, so they are dimensionless), v_r and v_max against
    path length, the bifurcations crossed (`passed`: (k, l from, l to)) as
    shaded spans; a legend names each. Returns the Figure."""
    plt = pyplot()
    ls = np.asarray(lengths, dtype=float)
    sv = np.asarray(svs, dtype=float)[:, -count:]
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    floor = 1e-17  # zeros drawn at the floor of the log scale
    grey = f"the {sv.shape[1]} lowest singular values of H (the lowest is v_r)"
    for c in range(sv.shape[1]):
        ax.semilogy(ls, np.maximum(sv[:, c], floor), color="0.6", lw=0.8, label=grey if c == 0 else "_nolegend_")
    ax.semilogy(ls, np.maximum(np.asarray(v_max, float), floor), color="C0", lw=1.8, ls="--",
                label="v_max: largest singular value")
    ax.semilogy(ls, np.maximum(np.asarray(v_r, float), floor), color="C3", lw=1.8,
                label="v_r: lowest non-zero singular value (the library's)")
    for n, (_, l0, l1) in enumerate(passed):
        ax.axvspan(l0, l1 if l1 > l0 else l0 + 1e-9, color="C2", alpha=0.35, lw=1.5, ec="C2",
                   label="bifurcation crossed (between these frames, by the detector)" if n == 0
                   else "_nolegend_")
    ax.set_xlabel("path length l from the start (model length units)")
    ax.set_ylabel("singular value of H (dimensionless)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    fig.tight_layout()
    if path:
        with replacing(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=110, format="png")
    return fig
