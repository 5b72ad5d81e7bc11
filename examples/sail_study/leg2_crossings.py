"""Which parts of the hexagonal two-loop sail pass through each other along
its fold (docs/sail_study.md, "Where the paper holds and where it does not").

The fold is the interference study's (studies/sequential.py: R^A -> R^B ->
R^C); the membrane its panels (studies/sailmeasure.sail_panels). Every bar
and bar triangle that share no joint are tested with a Moller-Trumbore
segment-triangle test in numpy (independent of libkin's clearance), at every
recorded point; where the set of crossing pairs changes, the change is
located by bisection on the path between the two recorded points.

  LIBKIN_LIBRARY=build/libkin.so PYTHONPATH=python/src python examples/sail_study/leg2_crossings.py
"""
import numpy as np

from libkin.studies.sailmeasure import sail_panels
from libkin.studies.sequential import sequential_fold

EPS = 1e-12  # a crossing lies inside both the segment and the triangle by this


def crosses(p, q, a, b, c):
    d, e1, e2 = q - p, b - a, c - a
    h = np.cross(d, e2)
    det = e1 @ h
    if abs(det) < 1e-14:  # parallel: coplanar touching is contact, not a crossing
        return False
    s = p - a
    u = (s @ h) / det
    if not EPS < u < 1 - EPS:
        return False
    qv = np.cross(s, e1)
    v = (d @ qv) / det
    if v < EPS or u + v > 1 - EPS:
        return False
    t = (e2 @ qv) / det
    return EPS < t < 1 - EPS


def crossings(x, bars, tris, labels):
    out = set()
    for i, j in bars:
        for tri in tris:
            if i in tri or j in tri:
                continue
            if crosses(x[i], x[j], *x[list(tri)]):
                out.add(f"{labels[i]}-{labels[j]} through " + "-".join(labels[k] for k in tri))
    return out


def main():
    fold = sequential_fold(6, 2, keep_states=True)
    a, samples = fold["assembly"], fold["samples"]
    labels = list(a.labels)
    bars = [(int(i), int(j)) for i, j in a.bars if labels[i] != "C" and labels[j] != "C"]
    tris = [p for p in sail_panels(a) if len(p) == 3]
    L = list(samples.l)

    def at(k, h):
        """The configuration h past recorded point k, and its path length."""
        c = samples.states[k].clone()
        if h > 0:
            if k in samples.leave_dir:
                c.set_direction(samples.leave_dir[k])
            c.step(h)
        return c.coords, L[k] + abs(c.path_length - samples.states[k].path_length)

    print("legs:", ", ".join(f"{g['l_start']:.4f} to {g['l_end']:.4f}" for g in fold["legs"]))
    prev = crossings(samples.coords[0], bars, tris, labels)
    for k in range(1, len(L)):
        now = crossings(samples.coords[k], bars, tris, labels)
        for pair in sorted(now - prev):
            lo, hi = 0.0, L[k] - L[k - 1]
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                if pair in crossings(at(k - 1, mid)[0], bars, tris, labels):
                    hi = mid
                else:
                    lo = mid
            print(f"from l = {at(k - 1, hi)[1]:.4f}: {pair}")
        for pair in sorted(prev - now):
            print(f"by l = {L[k]:.4f} no longer: {pair}")
        prev = now
    print(f"at the end of the fold (l = {L[-1]:.4f}): {len(prev)} pairs pass through each other")


if __name__ == "__main__":
    main()
