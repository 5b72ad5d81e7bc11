"""The complete solver's interval certificates (issue 38) against an
independent count in exact rational arithmetic.

For small systems (s <= 5: random quadrics, the paper's Figure 5(b), the
square sail's flat state) every endpoint of the solver (kin_quadrics_homotopy
_range over all paths) is proven again here with Python's Fractions: the
same Krawczyk test (docs/branches.md "What certified means": eta + rho r +
L r^2 < r with r = 2 eta / (1 - rho), the complex modulus bounded by
|re| + |im|), evaluated exactly on the exact doubles of Q and of the centre,
with Y the floating inverse of J. Real where the centre is real, non-real
where the box misses the reals; the proven boxes are shown pairwise
disjoint exactly. The exact counts must equal the C library's proven
counts (solve_quadrics' accounting), and reach 2^s where the library says
all are proven. Fractions are slow: s <= 5 keeps this to seconds.
"""
from fractions import Fraction as F

import numpy as np
import pytest

import pathlib
import sys

from libkin.assembly import solve_quadrics

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from homotopy_systems import FIG5B, endpoints, random_system, square_sail  # noqa: E402


def _cabs(z):
    """an upper bound of |z| for z = (re, im) Fractions"""
    return abs(z[0]) + abs(z[1])


def _cmul(a, b):
    return (a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0])


def _prove(Q, zr, zi, want_real):
    """(kind, chart, centre, r) of one endpoint, kind None if not proven"""
    s, m = Q.shape[0], Q.shape[1]
    k = int(np.argmax(zr * zr + zi * zi))
    z = zr + 1j * zi
    y = z / z[k]
    y[k] = 1.0
    if want_real:
        y = y.real + 0j
    c = [(F(float(v.real)), F(float(v.imag))) for v in y]
    free = [i for i in range(m) if i != k]
    Qf = [[[F(float(Q[j, a, b])) for b in range(m)] for a in range(m)] for j in range(s)]
    u = [[(sum(Qf[j][a][b] * c[b][0] for b in range(m)), sum(Qf[j][a][b] * c[b][1] for b in range(m)))
          for a in range(m)] for j in range(s)]
    f = []
    for j in range(s):
        acc = (F(0), F(0))
        for a in range(m):
            t = _cmul(c[a], u[j][a])
            acc = (acc[0] + t[0], acc[1] + t[1])
        f.append(acc)
    J = [[(2 * u[j][i][0], 2 * u[j][i][1]) for i in free] for j in range(s)]
    Jn = np.array([[float(e[0]) + 1j * float(e[1]) for e in row] for row in J])
    Yn = np.linalg.inv(Jn)
    Y = [[(F(float(v.real)), F(float(v.imag))) for v in row] for row in Yn]
    S = [sum(abs(Qf[j][a][b]) for a in range(m) for b in range(m)) for j in range(s)]
    eta = rho = L = F(0)
    for a in range(s):
        g = (F(0), F(0))
        for j in range(s):
            t = _cmul(Y[a][j], f[j])
            g = (g[0] + t[0], g[1] + t[1])
        eta = max(eta, _cabs(g))
        row = F(0)
        for i in range(s):
            e = (F(1 if a == i else 0), F(0))
            for j in range(s):
                t = _cmul(Y[a][j], J[j][i])
                e = (e[0] - t[0], e[1] - t[1])
            row += _cabs(e)
        rho = max(rho, row)
        L = max(L, 2 * sum(_cabs(Y[a][j]) * S[j] for j in range(s)))
    if rho >= 1:
        return None, k, c, None
    r = 2 * max(eta, F(1, 2 ** 1000)) / (1 - rho)
    if not eta + rho * r + L * r * r < r:
        return None, k, c, None
    if want_real:
        return "real", k, c, r
    if any(abs(c[i][1]) > r for i in free):
        return "nonreal", k, c, r
    return None, k, c, r


def _disjoint(p, q):
    """boxes p, q = (kind, chart, centre, r) shown disjoint: q's box taken to
    p's chart (x_c / x_k, with |x_k| bounded below) against p's box"""
    _, kp, cp, rp = p
    _, kq, cq, rq = q
    if kp == kq:
        return any(max(abs(cp[i][0] - cq[i][0]), abs(cp[i][1] - cq[i][1])) > rp + rq for i in range(len(cp)))
    d = cq[kp]
    dlo = max(abs(d[0]), abs(d[1])) - rq  # <= |x_kp| on q's box
    if dlo <= 0:
        return False
    n2 = d[0] * d[0] + d[1] * d[1]
    for i in range(len(cp)):
        if i == kp:
            continue
        w = ((cq[i][0] * d[0] + cq[i][1] * d[1]) / n2, (cq[i][1] * d[0] - cq[i][0] * d[1]) / n2)  # cq_i / d
        # |x_i / x_kp - cq_i / d| <= (r |d| + |cq_i| r) / (|d| dlo)
        rad = rq * (_cabs(d) + _cabs(cq[i])) / (max(abs(d[0]), abs(d[1])) * dlo)
        if max(abs(w[0] - cp[i][0]), abs(w[1] - cp[i][1])) > rp + rad:
            return True
    return False


def _exact_counts(Q):
    z, kinds = endpoints(Q)
    boxes = []
    for p in range(len(z)):
        if kinds[p] > 1:  # singular or lost: nothing to prove here
            continue
        kind, k, c, r = _prove(Q, z[p].real, z[p].imag, kinds[p] == 0)
        if kind is None and kinds[p] == 1:
            kind, k, c, r = _prove(Q, z[p].real, z[p].imag, True)
        if kind is not None:
            boxes.append((kind, k, c, r))
    clash = set()
    for a in range(len(boxes)):
        for b in range(a + 1, len(boxes)):
            if not _disjoint(boxes[a], boxes[b]) or not _disjoint(boxes[b], boxes[a]):
                clash.update((a, b))
    real = sum(1 for i, b in enumerate(boxes) if i not in clash and b[0] == "real")
    nonreal = sum(1 for i, b in enumerate(boxes) if i not in clash and b[0] == "nonreal")
    return real, nonreal


@pytest.mark.parametrize("name", ["fig5b", "random3", "random4", "random5", "square_sail"])
def test_proven_counts_equal_exact_rational_proofs(name):
    if name == "fig5b":
        Q = FIG5B
    elif name == "square_sail":
        Q = square_sail()
    else:
        Q = random_system(int(name[-1]), 17)
    s = Q.shape[0]
    _, acc = solve_quadrics(Q, "homotopy", seed=1, threads=1)
    real, nonreal = _exact_counts(Q)
    assert (acc["proven_real"], acc["proven_nonreal"]) == (real, nonreal), (acc, real, nonreal)
    assert acc["proven_real"] == acc["real_distinct"] and acc["proven_nonreal"] == acc["nonreal"]
    assert acc["proven_all"] == 1 and real + nonreal == 2 ** s
    if name == "fig5b":
        assert (real, nonreal) == (2, 2)  # x1 = +-x0, x2^2 = +-x0^2: known in closed form
    if name == "square_sail":
        assert (real, nonreal) == (16, 0)
