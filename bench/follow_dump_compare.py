"""Compare two BENCH_FOLLOW_DUMP files of bench_follow_atlas (two builds of
the follower on the same branches): events, located accuracy, m, s, steps,
and the end distance against the atlas's identification tolerance
(scale x max(1e-6, 10 sqrt(vr_tol_used)), as the bench's own comparison).
Usage: python3 follow_dump_compare.py BEFORE AFTER [scale]"""
import math
import sys


def load(path):
    rows = {}
    with open(path) as f:
        for line in f:
            v = line.split()
            rows[int(v[0])] = (int(v[1]), int(v[2]), float(v[3]), float(v[4]), int(v[5]), int(v[6]), int(v[7]),
                               [float(x) for x in v[8:]])
    return rows


def main():
    a, b = load(sys.argv[1]), load(sys.argv[2])
    scale = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
    same_ev = same_acc = same_steps = ends = same_end = 0
    worst = 0.0
    for k in sorted(a):
        if k not in b:
            print(f"branch {k}: missing in {sys.argv[2]}")
            continue
        x, y = a[k], b[k]
        ev = x[0] == y[0] and x[1] == y[1]
        bif = x[0] == 1 and y[0] == 1
        acc = not bif or (y[2] <= x[2] and x[4] == y[4] and x[5] == y[5])
        dist = max(abs(p - q) for p, q in zip(x[7], y[7]))
        tol = scale * max(1e-6, 10.0 * math.sqrt(max(x[2], y[2])))
        same_ev += ev
        same_acc += acc
        same_steps += x[6] == y[6]
        if bif:
            ends += 1
            same_end += dist <= tol
            worst = max(worst, dist / tol)
        if not ev or not acc or (bif and dist > tol):
            print(f"branch {k} differs: {x[:7]} vs {y[:7]}, end distance {dist:.3g} (tolerance {tol:.3g})")
    n = len(a)
    print(f"same event {same_ev} / {n}; same end node {same_end} / {ends} (worst {worst:.2g} of the tolerance); "
          f"same accuracy, m, s {same_acc} / {n}; same steps {same_steps} / {n}")


if __name__ == "__main__":
    main()
