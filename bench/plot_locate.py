"""Chart for bench_locate: final v_r against factorizations after detection,
both methods. usage: python bench/plot_locate.py CSV_DIR OUT_DIR"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, out):
    rows = list(csv.DictReader(open(f"{src}/bench_locate.csv")))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    markers = {"three-bar R^C (P1)": "o", "three-bar R^B (J2 at S1)": "s", "hex sail R^B": "^"}
    for ax, xkey, xlabel in [(axes[0], "factorizations", "factorizations after detection"),
                             (axes[1], "seconds", "seconds (whole call)")]:
        for method, color in [("paper", "C1"), ("fast", "C0")]:
            for case, mk in markers.items():
                rs = [r for r in rows if r["method"] == method and r["case"] == case]
                ax.scatter([float(r[xkey]) for r in rs], [max(float(r["vr_rel"]), 1e-17) for r in rs],
                           marker=mk, color=color, label=f"{method}: {case}", alpha=0.8)
        ax.axhline(1e-10, ls=":", color="k", lw=1)
        ax.set_yscale("log")
        if xkey == "seconds":
            ax.set_xscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("final v_r / v_max")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title("accuracy against factorizations (step sizes 0.02-0.4)")
    axes[1].set_title("accuracy against time")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{out}/locate_chart.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
