"""One tolerance scale for the rank and the rigid modes (issue 36 item 3).

Chains of n = 6..100 joints (a triangulated strip: bars (j, j+1), (j, j+2))
whose ends are pinned on a 3D line and whose other joints sit a small random
offset off it. Exactly (any offset != 0): rank 2n - 3, s = 0, one rigid mode
(the rotation about the line) and n - 4 internal mechanisms. Wherever the
rank counts the offset (rank 2n - 3), the rotation must be rigid, not an
internal mechanism. Before the fix the rigid test measured the rotation
against the RMS radius while the rank measures it against the bars: at
n = 48 and 100, offsets 3.2e-10 of the size, the rotation was dropped
(m_rigid 0, m_internal n - 3): 0, 0, 0, 1, 2 miscounts at n = 6, 12, 24, 48, 100.
"""
import numpy as np
import pytest

from libkin.assembly import Assembly

O = np.array([0.3, -0.2, 0.5])
D = np.array([0.267, 0.534, 0.802]) / np.linalg.norm([0.267, 0.534, 0.802])
N1 = np.cross(D, [1.0, 0.0, 0.0])
N1 /= np.linalg.norm(N1)
N2 = np.cross(D, N1)
SIZE = 4.0
OFFSETS = 10.0 ** np.linspace(-13, -7, 25)


def chain(n, eps, seed):
    rng = np.random.default_rng(seed)
    u = np.linspace(0, SIZE, n) + np.r_[0, rng.uniform(-0.2, 0.2, n - 2) * SIZE / (n - 1), 0]
    c = rng.uniform(-1, 1, (n, 2))
    c[0] = c[-1] = 0
    xyz = O + u[:, None] * D + eps * SIZE * (c[:, :1] * N1 + c[:, 1:] * N2)
    bars = np.array([[j, j + 1] for j in range(n - 1)] + [[j, j + 2] for j in range(n - 2)])
    fixed = np.zeros((n, 3), bool)
    fixed[0] = fixed[-1] = True
    return xyz, bars, fixed


@pytest.mark.parametrize("n", [6, 12, 24, 48, 100])
def test_rotation_about_the_line_is_rigid_where_the_rank_sees_the_offset(n):
    resolved, wrong = 0, []
    for eps in OFFSETS:
        for seed in (1, 2, 3):
            an = Assembly(*chain(n, eps, seed)).analyse()
            assert an.m_rigid + an.m_internal == an.m == 3 * n - 6 - an.rank
            if an.rank == 2 * n - 3:  # the rank counts the offset: the exact counts
                resolved += 1
                if (an.m_rigid, an.m_internal, an.s) != (1, n - 4, 0):
                    wrong.append((f"{eps:.2g}", seed, an.m_rigid, an.m_internal))
            else:  # below what the rank resolves: at most the rotation is rigid
                assert an.m_rigid in (0, 1)
    assert resolved >= 20  # the clearly-off cases and the window where it used to fail
    assert not wrong, wrong


def test_clearly_off_the_line_exact_counts():
    # a large offset: exact counts for every n (the construction's answer)
    for n in (6, 12, 24, 48, 100):
        an = Assembly(*chain(n, 1e-3, 1)).analyse()
        assert (an.rank, an.m_rigid, an.m_internal, an.s) == (2 * n - 3, 1, n - 4, 0)
