"""The pictures of `libkin follow` explain themselves (issue 36 item 7): the
GIF's frames show supports and a legend, a 3D model is drawn in 3D in one
box that holds the whole path, a planar one in 2D; the singular-value plot
names its curves. Checked on the figure objects, not on pixels."""
import os

import numpy as np
import pytest

import libkin
from libkin import cli

pytest.importorskip("matplotlib")
from libkin.plot import follow as follow_pics  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
HEX = os.path.join(HERE, "..", "..", "examples", "models", "hex_sail.json")


def _legend_texts(fig):
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    return [t.get_text() for lg in legends for t in lg.get_texts()]


def _fixed_joints(a):
    return int(np.asarray(a.fixed, dtype=bool).reshape(len(a.coords), -1).any(axis=1).sum())


def _support_points(pic):
    n = 0
    for label, art in pic.artists.items():
        if label.startswith("supports"):
            assert art.get_label() == label
            n += len(art._offsets3d[0]) if pic.dim == 3 else len(art.get_offsets())
    return n


@pytest.fixture(scope="module")
def planar():
    args = cli._parser().parse_args(["follow", "threebar:RA", "--perturb", "0.3", "--quiet"])
    a, an = cli._regular_start(args)  # threebar:RA is a bifurcation: start near it
    assert a is not None and a.dim == 2
    return a, cli.follow_path(a, an, 12)


@pytest.fixture(scope="module")
def sail():
    """The hex sail lifted off its flat bifurcation onto a regular path, as
    `libkin follow --perturb` does."""
    args = cli._parser().parse_args(["follow", HEX, "--perturb", "0.3", "--quiet"])
    a, an = cli._regular_start(args)
    assert a is not None and a.dim == 3
    return a, cli.follow_path(a, an, 10)


def test_planar_frame_is_2d_with_supports_and_legend(planar):
    a, p = planar
    pic = follow_pics.path_picture(p.frames, a.bars, a.fixed, p.lengths, name=a.name, frame=3)
    assert pic.ax.name != "3d"
    assert _support_points(pic) == _fixed_joints(a) > 0
    texts = _legend_texts(pic.fig)
    assert "bars" in texts and "joints" in texts
    assert any(t.startswith("supports") for t in texts)
    assert any("frame k of n" in t and "path length" in t for t in texts)
    assert "frame 3 of" in pic.title.get_text() and "path length" in pic.title.get_text()
    assert len(pic.artists["bars"].get_segments()) == len(a.bars)


def test_3d_model_drawn_in_3d_in_a_box_holding_the_whole_path(sail):
    a, p = sail
    assert len(p.frames) > 2
    pic = follow_pics.path_picture(p.frames, a.bars, a.fixed, p.lengths, name=a.name)
    assert pic.ax.name == "3d"
    assert _support_points(pic) == _fixed_joints(a) > 0
    texts = _legend_texts(pic.fig)
    assert "bars" in texts and any(t.startswith("supports") for t in texts)
    lims = [pic.ax.get_xlim3d(), pic.ax.get_ylim3d(), pic.ax.get_zlim3d()]
    allp = np.concatenate(p.frames)
    for c, (lo, hi) in enumerate(lims):
        assert lo <= allp[:, c].min() and allp[:, c].max() <= hi
    last = pic.show(len(p.frames) - 1)
    assert [last.ax.get_xlim3d(), last.ax.get_ylim3d(), last.ax.get_zlim3d()] == lims  # a fixed box
    np.testing.assert_allclose(np.array(last.artists["joints"]._offsets3d).T, p.frames[-1])


def test_gif_written_from_the_pictures(planar, tmp_path):
    a, p = planar
    out = follow_pics.animate_path(p.frames[:4], a.bars, str(tmp_path / "p.gif"), fixed=a.fixed,
                                   lengths=p.lengths[:4], name=a.name)
    from PIL import Image
    with Image.open(out) as im:
        assert im.n_frames == 4


def test_singular_value_plot_names_its_curves(planar):
    a, p = planar
    passed = p.passed or [(2, p.lengths[1], p.lengths[2])]
    fig = follow_pics.path_singular_values(p.lengths, np.array(p.singular_values), p.v_r, p.v_max, count=3,
                                           passed=passed)
    ax = fig.axes[0]
    texts = _legend_texts(fig)
    assert any(t.startswith("v_r") for t in texts)
    assert any(t.startswith("v_max") for t in texts)
    assert any("lowest singular values" in t for t in texts)
    assert any("bifurcation" in t for t in texts)
    assert "path length" in ax.get_xlabel() and "units" in ax.get_xlabel()
    assert "singular value" in ax.get_ylabel() and "dimensionless" in ax.get_ylabel()


def test_cli_draws_supports_lengths_and_bifurcations(tmp_path, monkeypatch):
    """`libkin follow --gif --plot` gives the pictures the supports, the
    path lengths, v_r, v_max and the bifurcations crossed."""
    seen = {}
    monkeypatch.setattr(follow_pics, "animate_path", lambda frames, bars, path, **kw: seen.setdefault("gif", kw))
    real = follow_pics.path_singular_values
    monkeypatch.setattr(follow_pics, "path_singular_values",
                        lambda *a, **kw: seen.setdefault("sv", (a, kw)) and real(*a, **kw))
    rc = cli.main(["follow", "threebar:RA", "--perturb", "0.3", "--steps", "5", "--quiet",
                   "--gif", str(tmp_path / "p.gif"), "--plot", str(tmp_path / "sv.png")])
    assert rc == 0 and (tmp_path / "sv.png").exists()
    assert seen["gif"]["fixed"] is not None and len(seen["gif"]["lengths"]) == 6
    args, kw = seen["sv"]
    assert len(args) == 4 and "passed" in kw  # lengths, singular values, v_r, v_max
