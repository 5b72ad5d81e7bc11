"""Which branch the returns to the hexagonal sail's flat state come back along
(issue 36 item 2, docs/follow.md "Branch directions").

For chosen branches of the flat state (sail:6:2; their solution numbers in the
explorer's canonical enumeration, both senses) libkin's follower, given all of
the start's branch lines, is run with the largest step scaled by each of
--scales; the table gives its event and the branch it says the path came back
along. With --numpy an independent follower (NumPy only: fixed chords, Newton
on the bar lengths, the tangent from the SVD of the compatibility matrix)
follows the same branches back to the start, measures the arrival direction by
secants from points at 0.05, 0.1 and 0.2 RMS lengths (extrapolated to the
start) and finds, by its own Newton on the second-order equations (paper eq.
18, the Q_j from Assembly.second_order), the exact branch it arrives along:
a loop is a return along the branch's own line.

    python bench/bench_return_labels.py --solutions 27725 28741 29281 --numpy
    python bench/bench_return_labels.py --sample 200   # a spread of branches, libkin only
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

import libkin
from libkin.assembly import BranchLines
from libkin.atlas import explorer, tasks


def flat_state():
    """The flat state's assembly, the explorer's lines and solution numbers (sign +1), the item builder."""
    a = libkin.Assembly.sail(6, 2)
    ex = explorer._Explorer(a, False, None, None, 20.0, 1, 1, None, 2000, 0, None, True, False)
    an = a.analyse()
    ex.add_node(a.coords, "bifurcation", {"m": an.m_internal, "m_rigid": an.m_rigid, "s": an.s, "v_r_rel": 0.0}, 0)
    br, _ = ex.branches(ex.nodes[0])
    sols = [i for i, sg, _, _ in br if sg == 1]
    lines = np.array([d for _, sg, _, d in br if sg == 1])

    def item(d):
        return {"model": ex.text, "coords": ex.nodes[0].coords.tolist(), "rank_tol": 1e-9,
                "direction": list(map(float, d)), "max_length": ex.max_length, "max_steps": 2000, "samples": 0}
    return a, sols, lines, item


def libkin_follow(item, d, L, own, scale):
    """libkin's follow of one directed branch with the largest step scaled."""
    a = tasks.rebuild(item(d))
    o = a.options
    o.step_fraction *= scale
    a.options = o
    return a.follow_event(d, max_length=float(item(d)["max_length"]), max_steps=2000, branches=L, own_branch=own)


# ---- the independent follower (NumPy) ----

class Frame:
    """The bar framework in free coordinates, from the model's data alone."""

    def __init__(self, a):
        self.x0 = np.asarray(a.coords, dtype=float)
        self.fmap = a.free_map()
        self.bars = np.asarray(a.bars)
        self.L = np.asarray(a.rest_lengths)
        self.nf = int(self.fmap.max()) + 1
        self.scale = float(np.sqrt(np.mean(self.L ** 2)))

    def full(self, xf):
        x = self.x0.copy()
        m = self.fmap >= 0
        x[m] = xf[self.fmap[m]]
        return x

    def free(self, x):
        out = np.empty(self.nf)
        m = self.fmap >= 0
        out[self.fmap[m]] = x[m]
        return out

    def g_and_J(self, xf):
        """Bar length errors (|AB|^2 - L^2) / (2 L) and their Jacobian (the compatibility matrix)."""
        x = self.full(xf)
        A, B = self.bars[:, 0], self.bars[:, 1]
        dv = x[A] - x[B]
        g = (np.einsum("ij,ij->i", dv, dv) - self.L ** 2) / (2 * self.L)
        J = np.zeros((len(self.L), self.nf))
        rows = np.arange(len(self.L))
        for c in range(x.shape[1]):
            fa, fb = self.fmap[A, c], self.fmap[B, c]
            w = dv[:, c] / self.L
            ok = fa >= 0
            np.add.at(J, (rows[ok], fa[ok]), w[ok])
            ok = fb >= 0
            np.add.at(J, (rows[ok], fb[ok]), -w[ok])
        return g, J

    def correct(self, xp, t):
        """Newton from the predicted point xp on g = 0 with (x - xp).t = 0."""
        x = xp.copy()
        for _ in range(30):
            g, J = self.g_and_J(x)
            M = np.vstack([J, t])
            r = np.concatenate([-g, [-(x - xp) @ t]])
            dx = np.linalg.lstsq(M, r, rcond=None)[0]
            x += dx
            if np.linalg.norm(dx) <= 1e-13 * self.scale and np.abs(g).max() <= 1e-12 * self.scale:
                return x
        g, _ = self.g_and_J(x)
        if np.abs(g).max() > 1e-9 * self.scale:
            raise RuntimeError("NumPy corrector did not converge")
        return x

    def tangent(self, x, prev):
        _, J = self.g_and_J(x)
        _, sv, vt = np.linalg.svd(J)
        t = vt[-1]
        return t if t @ prev >= 0 else -t


def numpy_return(fr, d, h=0.02, back=0.05, max_length=20.0):
    """Follow from the start along d with chords of h RMS lengths until the
    path has come back within `back` RMS lengths of the start; the arrival
    direction: the secants from the start to the path's last crossings of
    0.1 and 0.2 RMS lengths, extrapolated linearly to the start. Returns (that
    direction, the path length) or (None, length) if it never came back."""
    xs = fr.free(fr.x0)
    t = d / np.linalg.norm(d)
    x, length, away = xs.copy(), 0.0, False
    pts = [xs.copy()]
    for hh in [1e-4, 1e-3] + [h] * int(max_length / h):
        xn = fr.correct(x + hh * fr.scale * t, t)
        t = fr.tangent(xn, xn - x)
        length += np.linalg.norm(xn - x) / fr.scale
        x = xn
        pts.append(x.copy())
        r = np.linalg.norm(x - xs) / fr.scale
        away = away or r > 0.5
        if away and r <= back:
            break
    else:
        return None, length
    P = np.array(pts)
    dist = np.linalg.norm(P - xs, axis=1) / fr.scale
    sec = []
    for rad in (0.1, 0.2):
        k = max(i for i in range(1, len(P)) if dist[i - 1] >= rad > dist[i])  # the last crossing, arriving
        w = (dist[k - 1] - rad) / (dist[k - 1] - dist[k])
        p = P[k - 1] + w * (P[k] - P[k - 1])
        sec.append((p - xs) / (rad * fr.scale))
    return 2 * sec[0] - sec[1], length


def newton_root(Q, beta):
    """Newton on beta^T Q_j beta = 0, |beta| = 1 (m = s + 1) from beta; None if not converged."""
    b = beta / np.linalg.norm(beta)
    for _ in range(50):
        F = np.concatenate([np.einsum("i,jik,k->j", b, Q, b), [0.5 * (b @ b - 1)]])
        J = np.vstack([2 * np.einsum("jik,k->ji", Q, b), b])
        db = np.linalg.solve(J, -F)
        b = b + db
        if np.linalg.norm(db) <= 1e-13:
            return b if np.abs(F).max() <= 1e-10 else None
    return None


def line_angles(lines, v):
    c = np.abs(lines @ v) / (np.linalg.norm(lines, axis=1) * np.linalg.norm(v))
    return np.arccos(np.minimum(c, 1.0))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--solutions", type=int, nargs="*", default=[])
    ap.add_argument("--sample", type=int, default=0, help="also this many branches spread over the start's")
    ap.add_argument("--scales", type=float, nargs="*", default=[0.9, 1.0, 1.1])
    ap.add_argument("--numpy", action="store_true", help="the independent NumPy follow of the same branches")
    ap.add_argument("--one-sense", action="store_true", help="each branch in its + sense only")
    args = ap.parse_args()
    t0 = time.time()
    a, sols, lines, item = flat_state()
    L = BranchLines(lines)
    index = {s: k for k, s in enumerate(sols)}
    print(f"flat state: {len(sols)} branch lines x {lines.shape[1]}, {time.time() - t0:.1f} s")
    chosen = [index[s] for s in args.solutions]
    if args.sample:
        chosen += [int(k) for k in np.linspace(0, len(sols) - 1, args.sample).astype(int)]
    rows = []
    senses = (1,) if args.one_sense else (1, -1)
    for k in chosen:
        for sg in senses:
            d = sg * lines[k]
            out = []
            for sc in args.scales:
                ev = libkin_follow(item, d, L, k, sc)
                rb = ev.return_branch
                lab = sols[rb] if rb >= 0 else ("undecided" if rb == -2 else "-")
                out.append((ev.event, bool(ev.at_start), lab, ev.return_angle, ev.return_gap))
            rows.append((sols[k], sg, out))
            print(f"solution {sols[k]:6d} sign {sg:+d}: " + " | ".join(
                f"x{sc:g} {e}{' at start' if st else ''} back along {lab} ({ang:.3g} rad, gap {gap:.3g})"
                for sc, (e, st, lab, ang, gap) in zip(args.scales, out)), flush=True)
    if args.numpy:
        fr = Frame(a)
        U = a.analyse().internal_mechanisms
        Q = a.second_order()
        print("independent NumPy follow (chords 0.02 RMS lengths, arrival by secants at 0.1 and 0.2):")
        agree = {True: 0, False: 0}
        for k in dict.fromkeys(chosen):
            for sg in senses:
                t0, length = numpy_return(fr, sg * lines[k])
                if t0 is None:
                    print(f"solution {sols[k]:6d} sign {sg:+d}: no return within length {length:.2f}")
                    continue
                ang = line_angles(lines, t0)
                near = np.argsort(ang)[:2]
                r = newton_root(Q, U.T @ t0)
                root = None if r is None else line_angles(lines, U @ r)
                j = None if root is None else int(np.argmin(root))
                named = next((r[2][len(r[2]) // 2][2] for r in rows if r[0] == sols[k] and r[1] == sg), None)
                agree[j is not None and named == sols[j]] += 1
                print(f"solution {sols[k]:6d} sign {sg:+d}: back at length {length:.3f}; arrival nearest "
                      f"{sols[near[0]]} ({ang[near[0]]:.3g} rad, next {ang[near[1]]:.3g}), own {ang[k]:.3g} rad; "
                      f"Newton's root: " + ("none" if j is None else f"{sols[j]} ({root[j]:.2g} rad)")
                      + (" -> LOOP" if j == k else " -> a return along another branch"), flush=True)
    if args.numpy:
        print(f"libkin's return branch (middle scale) = the NumPy follow's: {agree[True]} of "
              f"{agree[True] + agree[False]} returns")
    loops = {sc: sum(r[2][i][0] == "closed-loop" for r in rows) for i, sc in enumerate(args.scales)}
    same = sum(len({o[2] for o in r[2]}) == 1 for r in rows)
    print(f"loops by step scale: {loops}; directed branches with the same return label at every scale: "
          f"{same} of {len(rows)}")
    print(f"libkin {libkin.__version__}; BLAS kernel: OPENBLAS_CORETYPE={os.environ.get('OPENBLAS_CORETYPE', 'auto')}")


if __name__ == "__main__":
    main()
