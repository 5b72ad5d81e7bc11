"""Charts for bench_homotopy.

homotopy_completeness.png: the fraction of the real second-order solutions
found against the time spent, for the paper's root scan (one point per number
of starting points, 2^6 .. 2^14) and the complete solver (one point: all
2^s paths), on the square sail's flat state, the hexagonal sail's R^B and its
flat state. homotopy_random.png: the complete solver on random systems,
s = 2 .. 15: time and steps per path, and the 2^s paths split by class.

usage: python bench/plot_homotopy.py CSV_DIR OUT_DIR
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"square flat": "tab:blue", "hex R^B": "tab:green", "hex flat": "tab:red"}
LABELS = {"square flat": "square sail, flat (s = 4)", "hex R^B": "hexagonal sail, R^B (s = 3)",
          "hex flat": "hexagonal sail, flat (s = 15)"}


def completeness(rows, out):
    fig, ax = plt.subplots(figsize=(8, 5))
    for model in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == model]
        col = COLOURS.get(model, None)
        scan = [r for r in rs if r["solver"] == "scan"]
        hom = [r for r in rs if r["solver"] == "homotopy"]
        truth = int(rs[0]["truth"])
        # times below the clock's resolution are drawn at 0.1 ms
        t = [max(float(r["seconds"]), 1e-4) for r in scan]
        f = [int(r["found"]) / truth for r in scan]
        ax.plot(t, f, "o-", color=col, ms=4, label=f"root scan: {LABELS.get(model, model)}")
        for r, ti, fi in zip(scan, t, f):
            if int(r["starts"]) in (64, 1024, 16384):
                ax.annotate(r["starts"], (ti, fi), fontsize=7, color=col, textcoords="offset points",
                            xytext=(4, -11 if fi > 0.9 else 4))
        for r in hom:
            ax.plot([max(float(r["seconds"]), 1e-4)], [int(r["found"]) / truth], "*", color=col, ms=15,
                    mec="black", label=f"complete solver: {LABELS.get(model, model)}, "
                                       f"{truth} of {r['starts']} paths real")
    ax.set_xscale("log")
    ax.set_ylim(-0.03, 1.08)
    ax.set_xlabel("time [s], 2 threads for the complete solver, 1 for the scan (log scale)")
    ax.set_ylabel("fraction of the real solutions found")
    ax.set_title("Second-order solutions: root scan (labels: starting points) vs complete solver")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc="center right")
    fig.tight_layout()
    fig.savefig(f"{out}/homotopy_completeness.png", dpi=110)


def random_systems(rows, out):
    rs = [r for r in rows if r["system"] == "random"]
    s = [int(r["s"]) for r in rs]
    paths = [int(r["paths"]) for r in rs]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    a1.semilogy(s, [float(r["seconds"]) for r in rs], "o-", label="wall time [s] (2 threads)")
    a1.semilogy(s, [float(r["cpu_seconds"]) for r in rs], "s--", label="CPU time [s], all threads")
    a1.semilogy(s, [2 ** k * 1e-3 for k in s], ":", color="gray", label="2^s x 1 ms")
    ax2 = a1.twinx()
    ax2.plot(s, [int(r["steps"]) / p for r, p in zip(rs, paths)], "^-", color="tab:purple",
             label="steps per path (right)")
    ax2.set_ylabel("accepted steps per path")
    ax2.set_ylim(0, None)
    a1.set_xlabel("s (equations; m = s + 1 unknowns, 2^s paths)")
    a1.set_ylabel("time [s] (log scale)")
    a1.set_title("complete solver on random systems: cost")
    h1, l1 = a1.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    a1.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper left")
    a1.grid(True, which="both", alpha=0.3)
    real = [int(r["real"]) / p for r, p in zip(rs, paths)]
    nonreal = [int(r["nonreal"]) / p for r, p in zip(rs, paths)]
    other = [(int(r["singular"]) + int(r["failed"])) / p for r, p in zip(rs, paths)]
    a2.bar(s, real, label="real", color="tab:blue")
    a2.bar(s, nonreal, bottom=real, label="non-real (conjugate pairs)", color="tab:orange")
    a2.bar(s, other, bottom=[a + b for a, b in zip(real, nonreal)], label="singular or failed", color="tab:red")
    for k, r in zip(s, rs):
        a2.annotate(r["real_distinct"], (k, int(r["real"]) / int(r["paths"])), ha="center", fontsize=7,
                    textcoords="offset points", xytext=(0, 2))
    hexr = [r for r in rows if r["system"] == "hex_flat"][:1]
    if hexr:  # the hexagonal sail's flat state beside them, for contrast
        r, x = hexr[0], max(s) + 2
        p = int(r["paths"])
        fr, fn = int(r["real"]) / p, int(r["nonreal"]) / p
        a2.bar([x], [fr], color="tab:blue")
        a2.bar([x], [fn], bottom=[fr], color="tab:orange")
        a2.bar([x], [(int(r["singular"]) + int(r["failed"])) / p], bottom=[fr + fn], color="tab:red")
        a2.annotate(r["real_distinct"], (x, fr), ha="center", fontsize=7, textcoords="offset points", xytext=(0, 2))
        a2.set_xticks(list(range(2, max(s) + 1, 2)) + [x])
        a2.set_xticklabels([str(k) for k in range(2, max(s) + 1, 2)] + ["hex\nflat"])
    a2.set_xlabel("s (random systems), and the hexagonal sail's flat state (s = 15)")
    a2.set_ylabel("fraction of the 2^s paths")
    a2.set_ylim(0, 1.0)
    a2.set_title("where the paths end (labels: distinct real solutions)")
    a2.legend(fontsize=8, loc="center right")
    fig.tight_layout()
    fig.savefig(f"{out}/homotopy_random.png", dpi=110)


def main(src, out):
    completeness(list(csv.DictReader(open(f"{src}/bench_completeness.csv"))), out)
    random_systems(list(csv.DictReader(open(f"{src}/bench_homotopy.csv"))), out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
