"""Charts for bench_step (see docs/performance.md).

step_scaling.png  seconds per step in both factorization modes, one dgesdd and
                  one dgetrf of the same size against free coordinates
                  (log-log, fitted growth exponents), and the step cost in
                  dgesdd-equivalents (mean step and regular steps, with the
                  range over rounds) against the goal of 2.
step_pareto.png   out-and-back runs: closure error and max bar strain against
                  seconds per unit path length, both modes, every step
                  fraction and corrector tolerance, for each sail measured.

usage: python bench/plot_step.py CSV_DIR OUT_DIR
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402

def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def slope(xs, ys, xmin=100):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x >= xmin and y > 0 and math.isfinite(y)]
    if len(pts) < 2:
        return float("nan")
    n = len(pts)
    sx = sum(p[0] for p in pts)
    sy = sum(p[1] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts)
    sxy = sum(p[0] * p[1] for p in pts)
    return (n * sxy - sx * sy) / (n * sxx - sx * sx)


def fnum(r, k):
    try:
        return float(r[k])
    except (KeyError, ValueError):
        return float("nan")


def _log_axes(ax):
    ax.set_xscale("log")
    ax.set_yscale("log")
    # label 1, 2, 5 times powers of ten on x: the ranges are narrow
    ax.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0), numticks=30))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="both", alpha=0.3)


def scaling_chart(rows, out):
    nf = [int(r["nfree"]) for r in rows]
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(19, 5.8), gridspec_kw={"width_ratios": [1.15, 1.15, 0.8]})
    series = [
        ("svd_step_s", "C0", "o-", "step, SVD mode (mean)"),
        ("lu_step_s", "C3", "s-", "step, LU mode (mean)"),
        ("dgesdd_s", "k", "^--", "one dgesdd of H (jobz 'A')"),
        ("dgetrf_s", "0.5", "v--", "one dgetrf of the bordered matrix"),
    ]
    for key, color, style, label in series:
        ys = [fnum(r, key) for r in rows]
        ax1.plot(nf, ys, style, color=color, label=f"{label}: p = {slope(nf, ys):.2f}", ms=5)
    # regular steps (one factorization, no halving): seconds = ratio * dgesdd
    for mode, color in (("svd", "C0"), ("lu", "C3")):
        ys = [fnum(r, f"reg_ratio_{mode}") * fnum(r, "dgesdd_s") for r in rows]
        ax1.plot(nf, ys, ".:", color=color, label=f"regular step, {mode.upper()} mode: p = {slope(nf, ys):.2f}")
    _log_axes(ax1)
    ax1.set_xlabel("free coordinates (sail members, hub n = 6..24, 1..20 loops)")
    ax1.set_ylabel("seconds (best of the rounds, 1 BLAS thread)")
    ax1.set_title("time per step and per factorization\n(p: least-squares slope of log time for nfree >= 100)")
    ax1.legend(fontsize=8, loc="upper left")

    for mode, color, marker in (("svd", "C0", "o"), ("lu", "C3", "s")):
        mean = [fnum(r, f"ratio_{mode}") for r in rows]
        lo = [max(m - fnum(r, f"ratio_{mode}_min"), 0.0) for m, r in zip(mean, rows)]
        hi = [max(fnum(r, f"ratio_{mode}_max") - m, 0.0) for m, r in zip(mean, rows)]
        ax2.errorbar(nf, mean, yerr=[lo, hi], fmt=marker + "-", color=color, capsize=3, ms=5,
                     label=f"{mode.upper()} mode, mean step (bars: range of per-round ratios)")
        ax2.plot(nf, [fnum(r, f"reg_ratio_{mode}") for r in rows], marker + ":", color=color, mfc="none", ms=6,
                 label=f"{mode.upper()} mode, regular steps (1 factorization, no halving)")
    ax2.axhline(2.0, color="k", lw=1, ls="--")
    ax2.text(nf[0], 2.12, "goal: 2 SVD-equivalents", fontsize=8)
    _log_axes(ax2)
    ax2.set_xlabel("free coordinates")
    ax2.set_ylabel("seconds per step / seconds of one dgesdd (same round)")
    ax2.set_title("step cost in SVD-equivalents")
    ax2.legend(fontsize=8, loc="upper left")

    ax3.plot(nf, [fnum(r, "fact_svd") for r in rows], "o-", color="C0", label="factorizations per step, SVD mode")
    ax3.plot(nf, [fnum(r, "fact_lu") for r in rows], "s:", color="C3", mfc="none", ms=7,
             label="factorizations per step, LU mode")
    ax3.plot(nf, [max(fnum(r, "halvings_svd"), 1e-2) for r in rows], "x--", color="0.4",
             label="halvings per step (both modes; 0 drawn at 0.01)")
    _log_axes(ax3)
    ax3.set_xlabel("free coordinates")
    ax3.set_ylabel("per step (mean over the timed steps)")
    ax3.set_title("what a step did: failed attempts cost up to\n8 Newton factorizations each")
    ax3.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(f"{out}/step_scaling.png", dpi=100)
    plt.close(fig)


TOL_MARKER = {"1.0e-06": "^", "1.0e-09": "s", "1.0e-12": "o"}
MODE_COLOR = {"SVD": "C0", "LU": "C3"}


def pareto_front(pts):
    """non-dominated points (x, y), both to be minimised, sorted by x"""
    front, best = [], float("inf")
    for x, y in sorted(pts):
        if y < best:
            front.append((x, y))
            best = y
    return front


def pareto_chart(rows, out):
    models = list(dict.fromkeys(r["model"] for r in rows))
    fig, axes = plt.subplots(len(models), 2, figsize=(15, 5.4 * len(models)), squeeze=False)
    for row, model in enumerate(models):
        rs = [r for r in rows if r["model"] == model]
        nfree = rs[0]["nfree"]
        for col, key, ylabel in ((0, "closure", "closure error after out and back (max |dx|)"),
                                 (1, "max_strain", "max bar strain |L - L0| / L0 on the way")):
            ax = axes[row][col]
            for mode, color in MODE_COLOR.items():
                pts = []
                for tol, marker in TOL_MARKER.items():
                    sel = [r for r in rs if r["mode"] == mode and r["corrector_tol"] == tol]
                    xs = [float(r["seconds_per_length"]) for r in sel]
                    ys = [max(float(r[key]), 1e-17) for r in sel]
                    ax.scatter(xs, ys, marker=marker, color=color, s=34, alpha=0.85,
                               label=f"{mode} mode, corrector tol {float(tol):.0e}")
                    for r, x, y in zip(sel, xs, ys):
                        ax.annotate(r["step_fraction"].rstrip("0"), (x, y), textcoords="offset points",
                                    xytext=(4, 2), fontsize=7, color=color)
                    pts += list(zip(xs, ys))
                fx, fy = zip(*pareto_front(pts))
                ax.step(fx, fy, where="post", color=color, lw=1, alpha=0.6, label=f"{mode} mode: Pareto front")
            _log_axes(ax)
            ax.set_xlabel("seconds per unit path length (best of the runs, 1 BLAS thread)")
            ax.set_ylabel(ylabel)
            ax.set_title(f"sail {model} ({nfree} free coordinates): {key.replace('_', ' ')} against time "
                         "(labels: step fraction)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=9)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(f"{out}/step_pareto.png", dpi=100)
    plt.close(fig)


def main(src, out):
    try:
        scaling_chart(read(f"{src}/bench_step_scaling.csv"), out)
    except FileNotFoundError:
        print("no bench_step_scaling.csv")
    try:
        pareto_chart(read(f"{src}/bench_step_pareto.csv"), out)
    except FileNotFoundError:
        print("no bench_step_pareto.csv")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
