"""Charts for bench_step: step cost in SVD-equivalents against problem size,
and the speed/accuracy trade-off of step size and corrector tolerance.

usage: python bench/plot_step.py CSV_DIR OUT_DIR
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(src, out):
    scal = read(f"{src}/bench_step_scaling.csv")
    par = read(f"{src}/bench_step_pareto.csv")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    nf = [int(r["nfree"]) for r in scal]
    ax1.loglog(nf, [float(r["step_s"]) for r in scal], "o-", label="one step (predictor + corrector + SVD)")
    ax1.loglog(nf, [float(r["svd_s"]) for r in scal], "s--", label="one dgesdd of H")
    ax1.set_xlabel("free coordinates")
    ax1.set_ylabel("seconds")
    ax1.set_title("step cost against one SVD (sail family)")
    for r in scal:
        ax1.annotate(f"{float(r['ratio']):.2f}", (int(r["nfree"]), float(r["step_s"])),
                     textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax1.legend(fontsize=8)
    ax1.grid(True, which="both", alpha=0.3)
    for tol in sorted({r["corrector_tol"] for r in par}, key=float):
        rows = [r for r in par if r["corrector_tol"] == tol]
        ax2.loglog([float(r["seconds_per_length"]) for r in rows],
                   [max(float(r["closure"]), 1e-16) for r in rows], "o-", label=f"corrector tol {float(tol):.0e}")
        for r in rows:
            ax2.annotate(r["step_fraction"], (float(r["seconds_per_length"]), max(float(r["closure"]), 1e-16)),
                         textcoords="offset points", xytext=(4, -10), fontsize=7)
    ax2.set_xlabel("seconds per unit path length")
    ax2.set_ylabel("closure error after out-and-back (max |dx|)")
    ax2.set_title("hexagonal sail: accuracy against time (labels: step fraction)")
    ax2.legend(fontsize=8)
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/step_cost.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
