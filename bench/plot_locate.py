"""Chart for bench_locate: accuracy (final v_r / v_max) against cost
(factorizations after detection, and seconds of locating) for every method,
case and step size. usage: python bench/plot_locate.py CSV_DIR OUT_DIR"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METHODS = [("fast", "C0", "fast (Hermite), tol 1e-10"), ("illinois", "C2", "Illinois on tau, tol 1e-10"),
           ("paper", "C3", "paper's quadratic, tol 1e-10"), ("paper@1e-6", "C1", "paper's quadratic, tol 1e-6")]
MARKERS = ["o", "s", "^", "D", "v"]


def main(src, out):
    rows = list(csv.DictReader(open(f"{src}/bench_locate.csv")))
    cases = list(dict.fromkeys(r["case"] for r in rows))
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), sharey=True)
    for ax, key, label in [(axes[0], "factorizations", "factorizations after detection (log)"),
                           (axes[1], "seconds", "seconds of locating (log)")]:
        for method, color, mlabel in METHODS:
            for case, mk in zip(cases, MARKERS):
                rs = [r for r in rows if r["method"] == method and r["case"] == case]
                xs = [max(float(r[key]), 1e-5 if key == "seconds" else 0.8) for r in rs]
                ys = [max(float(r["vr_rel"]), 1e-17) for r in rs]
                filled = [r["ok"] == "1" for r in rs]
                ax.scatter([x for x, f in zip(xs, filled) if f], [y for y, f in zip(ys, filled) if f], marker=mk,
                           color=color, alpha=0.85, s=36)
                ax.scatter([x for x, f in zip(xs, filled) if not f], [y for y, f in zip(ys, filled) if not f],
                           marker=mk, facecolors="none", edgecolors=color, alpha=0.85, s=36)
        ax.axhline(1e-10, ls=":", color="k", lw=1)
        ax.axhline(1e-6, ls=":", color="C1", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("final v_r / v_max (all vanishing singular values)")
    axes[0].set_title("accuracy against factorizations (steps 0.01 - 0.4)")
    axes[1].set_title("accuracy against time (best of 3)")
    # legends: colour = method, marker = case, hollow = not located
    from matplotlib.lines import Line2D
    h1 = [Line2D([], [], color=c, marker="o", ls="", label=l) for _, c, l in METHODS]
    h2 = [Line2D([], [], color="grey", marker=m, ls="", label=c) for c, m in zip(cases, MARKERS)]
    h2.append(Line2D([], [], color="grey", marker="o", ls="", markerfacecolor="none", label="hollow: gave up"))
    axes[0].legend(handles=h1, fontsize=8, loc="upper left")
    axes[1].legend(handles=h2, fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(f"{out}/locate_chart.png", dpi=110)


def table(src):
    """Markdown summary: per case and method, factorizations (min-max) and
    the worst final v_r over the step sizes, and how many located."""
    rows = list(csv.DictReader(open(f"{src}/bench_locate.csv")))
    cases = list(dict.fromkeys(r["case"] for r in rows))
    out = ["| case | steps | " + " | ".join(m for m, _, _ in METHODS) + " |",
           "|---|---|" + "---|" * len(METHODS)]
    for case in cases:
        deltas = sorted({abs(float(r["delta"])) for r in rows if r["case"] == case})
        cells = []
        for method, _, _ in METHODS:
            rs = [r for r in rows if r["case"] == case and r["method"] == method]
            f = [int(r["factorizations"]) for r in rs]
            ok = sum(r["ok"] == "1" for r in rs)
            worst = max(float(r["vr_rel"]) for r in rs)
            cells.append(f"{min(f)}-{max(f)} f, worst {worst:.0e}, {ok}/{len(rs)} located")
        out.append(f"| {case} | {deltas[0]:g}-{deltas[-1]:g} | " + " | ".join(cells) + " |")
    return "\n".join(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
    print(table(sys.argv[1]))
