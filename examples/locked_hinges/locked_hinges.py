"""Folds that cannot pass through (issue 37 items 2 and 3): on each sail
member's radially sequential fold (libkin.studies.sequential, the study's
path), where a hinge (two membrane panels on one fold line) first closes,
where the fold would first carry a hinge through flat-folded, and what the
membrane can do at the first closure with the closed hinges locked (a bar
between each closed hinge's two far corners at their closed distance: the
two panels as one).

    LIBKIN_LIBRARY=build/libkin.so PYTHONPATH=python/src \\
        python examples/locked_hinges/locked_hinges.py [--members 6:1,6:2,...] [--out DIR]

Writes DIR/report.md, DIR/summary.json and per member closure_N_L.png and
through_N_L.png. Long: minutes per member (the folds and complete solves).
"""
from __future__ import annotations

import argparse
import json
import os
import time
from typing import Any, Dict, List, Optional

import numpy as np

import libkin
from libkin.studies.sailmeasure import part_name, sail_panels
from libkin.studies.sequential import sequential_fold

CLOSED = 1e-6   # a hinge's dihedral angle (radians) below which it is closed
THICKNESSES = (0.001, 0.003, 0.01, 0.03)


def dihedral(X: np.ndarray, J: np.ndarray) -> np.ndarray:
    """The angle between each hinge's panels (0 closed, pi flat) and the
    sign of its signed volume, at configuration X."""
    xi, xj, xa, xb = (X[J[:, q]] for q in range(4))
    e = xj - xi
    na, nb = np.cross(e, xa - xi), np.cross(e, xb - xi)
    d = np.arctan2(np.linalg.norm(np.cross(na, nb), axis=1), np.einsum("ij,ij->i", na, nb))
    vol = np.einsum("ij,ij->i", np.cross(xa - xi, xb - xi), e)
    return d, np.sign(vol)


def first_closure_and_through(X: np.ndarray, L: np.ndarray, J: np.ndarray):
    """Along the fold's samples (X, lengths L): the first sample where a
    hinge is closed, and the first pair of samples between which a hinge
    passes through flat-folded (its fold side, tracked while the dihedral is
    below 90 degrees, changes). Each: (sample index, [hinges]) or None."""
    side = np.zeros(len(J))
    closure = through = None
    for k in range(len(X)):
        d, s = dihedral(X[k], J)
        shut = np.flatnonzero(d < CLOSED)
        if closure is None and len(shut):
            closure = (k, shut.tolist())
        flip = np.flatnonzero((d < np.pi / 2) & (d >= CLOSED) & (side != 0) & (s != side))
        if through is None and len(flip):
            through = (k, flip.tolist())
        open_ = d >= CLOSED
        side = np.where(d >= np.pi / 2, 0, np.where(open_ & (side == 0), s, side))
        if closure is not None and through is not None:
            break
    return closure, through


def draw(path: str, a: Any, X: np.ndarray, panels: List[List[int]], hinge_panels: List[int], title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    fig = plt.figure(figsize=(6.4, 5.6))
    ax = fig.add_subplot(projection="3d")
    for i, j in np.asarray(a.bars):
        ax.plot(*X[[i, j]].T, color="0.55", lw=0.7)
    light = [X[f] for q, f in enumerate(panels) if q not in hinge_panels]
    ax.add_collection3d(Poly3DCollection(light, facecolor="0.85", edgecolor="none", alpha=0.25))
    colours = ["tab:red", "tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown"]
    for q, p in enumerate(hinge_panels):
        ax.add_collection3d(Poly3DCollection([X[panels[p]]], facecolor=colours[(q // 2) % len(colours)],
                                             edgecolor="k", alpha=0.55))
    lo, hi = X.min(0), X.max(0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r), ax.set_ylim(c[1] - r, c[1] + r), ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def locked_at(a: Any, X: np.ndarray, J: np.ndarray, shut: List[int]) -> Any:
    """The model at X with every hinge in `shut` locked: a bar between its
    two far corners at their distance (marked as devices)."""
    bars = np.asarray(a.bars)
    locks = np.array([[J[h, 2], J[h, 3]] for h in shut])
    L0 = np.concatenate([a.rest_lengths, np.linalg.norm(X[locks[:, 0]] - X[locks[:, 1]], axis=1)])
    b = libkin.Assembly(X, np.vstack([bars, locks]), fixed=a.fixed, lengths=L0, labels=list(a.labels))
    b.device_bars = list(a.device_bars) + list(range(len(bars), len(bars) + len(locks)))
    return b


def second_order_min_residual(Q: np.ndarray, starts: int = 4000, seed: int = 1) -> float:
    """min over unit beta of sqrt(sum_j (beta^T Q_j beta)^2): from `starts`
    random points on the sphere, each refined by least squares (scipy).
    The solvers need m = s + 1; with more equations than that (an
    overdetermined system) a path leaves only where this is 0."""
    from scipy.optimize import least_squares
    rng = np.random.default_rng(seed)
    m = Q.shape[1]

    def res(b: np.ndarray) -> np.ndarray:
        u = b / np.linalg.norm(b)
        return np.einsum("i,jik,k->j", u, Q, u)

    B = rng.normal(size=(starts, m))
    B /= np.linalg.norm(B, axis=1)[:, None]
    r0 = np.linalg.norm(np.einsum("ni,jik,nk->nj", B, Q, B), axis=1)
    best = float(r0.min())
    for b in B[np.argsort(r0)[:40]]:
        best = min(best, float(np.linalg.norm(res(least_squares(res, b, xtol=1e-15, ftol=1e-15).x))))
    return best


def member(n: int, loops: int, out: str) -> Dict[str, Any]:
    t0 = time.perf_counter()
    res = sequential_fold(n, loops, keep_states=True)
    S = res["samples"]
    a = res["assembly"].clone()
    panels = sail_panels(a)
    a.panels = panels
    J, P = a.hinges()
    labels = list(a.labels)
    X, L = np.array(S.coords), np.array(S.l)
    hub = [i for i, lab in enumerate(labels) if lab.startswith("V")]
    rec: Dict[str, Any] = {"member": f"{n}:{loops}", "fold_length": float(L[-1]),
                           "bifurcations": res["bifurcations"], "legs": [], "hinges": int(len(J))}
    for leg in res["legs"]:
        k0 = int(np.searchsorted(L, leg["l_start"] - 1e-12))
        k1 = int(np.searchsorted(L, leg["l_end"] - 1e-12))
        rec["legs"].append({"l_start": leg["l_start"], "l_end": leg["l_end"], "event": leg["event"],
                            "hub_out_of_plane_max": float(np.abs(X[k0:k1 + 1][:, hub, 2]).max())})
    closure, through = first_closure_and_through(X, L, J)
    name = lambda h: "-".join(labels[q] for q in J[h][:2])  # noqa: E731
    if closure:
        k, hs = closure
        rec["first_closure"] = {"l": float(L[k]), "fraction": float(L[k] / L[-1]), "hinges": [name(h) for h in hs]}
        draw(os.path.join(out, f"closure_{n}_{loops}.png"), a, X[k], panels,
             [int(p) for h in hs for p in P[h]],
             f"sail {n}:{loops}: first hinges closed at l = {L[k]:.3f} ({100 * L[k] / L[-1]:.1f} % of the fold)\n"
             + ", ".join(name(h) for h in hs))
    if through:
        k, hs = through
        rec["first_through"] = {"l_before": float(L[k - 1]), "l_after": float(L[k]), "hinges": [name(h) for h in hs]}
        draw(os.path.join(out, f"through_{n}_{loops}.png"), a, X[k], panels,
             [int(p) for h in hs for p in P[h]],
             f"sail {n}:{loops}: hinges through flat-folded between l = {L[k - 1]:.3f} and {L[k]:.3f}\n"
             + ", ".join(name(h) for h in hs))
    # the contact event along leg 1, then along leg 2 from its start with leg 1's sides
    ev = a.clone()
    ev.set_contact_events(True, 1e-9)
    fe = ev.follow_event(S.leave_dir[0], max_steps=800)
    c = ev.last_contact() if fe.event == "contact" else None
    rec["leg1_event"] = {"event": fe.event, "l": fe.length,
                         "parts": [part_name(ev, panels, kd, i) for kd, i in c.parts] if c else []}
    # the first contact with thickness t/a (hinges included: a hinge touches
    # once its panels' far sides come within t), along leg 1
    rec["first_contact"] = {}
    for t in THICKNESSES:
        th = a.clone()
        th.thickness = t
        th.set_contact_events(True, 1e-9)
        f = th.follow_event(S.leave_dir[0], max_steps=800)
        ct = th.last_contact() if f.event == "contact" else None
        rec["first_contact"][str(t)] = {"event": f.event, "l": f.length, "fraction": f.length / float(L[-1]),
                                        "parts": [part_name(th, panels, kd, i) for kd, i in ct.parts] if ct else []}
    starts = sorted(S.leave_dir)
    if len(starts) > 1 and fe.event == "contact":
        ev.coords = S.states[starts[1]].coords
        fe2 = ev.follow_event(S.leave_dir[starts[1]], max_steps=800)
        c2 = ev.last_contact() if fe2.event == "contact" else None
        rec["leg2_event"] = {"event": fe2.event, "l": fe2.length,
                             "parts": [part_name(ev, panels, kd, i) for kd, i in c2.parts] if c2 else []}
    # locked: the closed hinges at the first closure held closed
    if closure:
        k, hs = closure
        lk = locked_at(a, X[k], J, hs)
        an = lk.analyse()
        rec["locked"] = {"at_l": float(L[k]), "locks": len(hs), "m_internal": an.m_internal, "s": an.s}
        if an.m_internal >= 2 and an.s >= 1:
            # the second-order equations beta^T Q_j beta = 0 on the unit
            # sphere: their smallest residual (0 where a path leaves)
            Q = lk.second_order()
            rec["locked"]["second_order_equations"] = int(len(Q))
            rec["locked"]["min_residual"] = second_order_min_residual(Q)
        if an.m_internal > 0 and an.s <= 10 and an.m_internal == len(lk.second_order()) + 1:
            lk.panels = panels
            lk.set_contact_events(True, 1e-9)
            br = lk.branches(solver="homotopy", length=0.3)
            ends: Dict[str, int] = {}
            for p in br.paths:
                if not (p.exists and p.tangent_ok):
                    continue
                b = lk.clone()
                f = b.follow_event(br.directions[p.beta] * p.sign, max_steps=800)
                tag = f.event
                if f.event == "contact":
                    cc = b.last_contact()
                    tag += ": hinge" if [kd for kd, _ in cc.parts] == ["panel", "panel"] else ": parts"
                ends[tag] = ends.get(tag, 0) + 1
            rec["locked"]["onward"] = ends
    rec["seconds"] = round(time.perf_counter() - t0, 1)
    return rec


def main(argv: Optional[List[str]] = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", default="6:1,6:2,8:1,8:2,6:3,8:3,6:4,8:4")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__)))
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    recs = []
    for m in args.members.split(","):
        n, loops = (int(v) for v in m.split(":"))
        r = member(n, loops, args.out)
        print(json.dumps(r), flush=True)
        recs.append(r)
        with open(os.path.join(args.out, "summary.json"), "w") as f:
            json.dump({"libkin": libkin.__version__, "members": recs}, f, indent=1)


if __name__ == "__main__":
    main()
