"""Chart for bench_branches: distinct real solutions found by the root scan
against its time, per model. usage: python bench/plot_branches.py CSV_DIR OUT_DIR"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, out):
    rows = list(csv.DictReader(open(f"{src}/bench_branches.csv")))
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for model in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == model]
        s = int(rs[0]["s"])
        ax.loglog([float(r["seconds"]) for r in rs], [int(r["distinct"]) for r in rs], "o-",
                  label=f"{model} (s = {s}, Bezout bound {2 ** s})")
        ax.axhline(2 ** s, ls=":", color=ax.lines[-1].get_color(), lw=1)
        for r in rs[::2]:
            ax.annotate(r["starts"], (float(r["seconds"]), int(r["distinct"])), fontsize=7,
                        textcoords="offset points", xytext=(3, -10))
    ax.set_xlabel("scan time [s] (labels: starting points)")
    ax.set_ylabel("distinct real solutions found")
    ax.set_title("root scan: completeness against time")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/branches_scan.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
