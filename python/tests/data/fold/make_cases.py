"""How the crease patterns of this folder were made (run from this folder:
`python make_cases.py`; the tests read the .fold files, not this script).

Each file's key frame is a flat crease pattern with 2-number coordinates
(what the FOLD spec allows and crease-pattern software writes); its
file_frames[0] is a folded state of the same sheet, 3D. Degrees of freedom
known by hand (no supports: 6 rigid-body motions on top):
  single_fold     two triangles, one crease: 1
  degree4_vertex  one vertex, four creases (sectors 80, 105, 80, 95 deg; not
                  flat-foldable): a spherical 4-bar, 1 (flat: 4 - 2 = 2 to
                  first order)
  miura_cell      2 x 2 parallelograms of Miura-ori (one degree-4 vertex): 1
  square_twist    central square, 4 pleats at 30 deg, 4 corners; 12 creases,
                  4 interior vertices: 12 - 3*4 = 0 by count, yet it folds
                  rigidly with 1 degree of freedom (overconstrained: one
                  self-stress along the motion); its folded frame is placed
                  off the axes and rounded to 6 decimals, as real files are.
Folded states: the single fold, vertex and cell by rotating panels about
creases by fold angles that close each vertex loop; the twist by solving the
four vertex loops (product of rotations about the flat crease vectors = I,
Belcastro & Hull) for the 11 other fold angles at a given central-crease angle.
"""
import json

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation


def rot2(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def R(u, r):
    u = np.array([u[0], u[1], 0.0])
    return Rotation.from_rotvec(u / np.linalg.norm(u) * r).as_matrix()


def edges_of(faces):
    edges, count = [], {}
    for f in faces:
        for k in range(len(f)):
            e = tuple(sorted((f[k], f[(k + 1) % len(f)])))
            count[e] = count.get(e, 0) + 1
            if list(e) not in edges:
                edges.append(list(e))
    return edges, ["B" if count[tuple(e)] == 1 else "U" for e in edges]


def vertex_loop(center, ends, faces_of, angles):
    """Fold a single vertex: panels k between crease k and k+1 (CCW), panel 0
    fixed; returns the rotation of each panel about `center` (a closed loop
    needs the product of all crease rotations = I)."""
    T = [np.eye(3)]
    for k in range(1, len(ends)):
        T.append(T[-1] @ R(ends[k] - center, angles[k]))
    return T


def fold_single_vertex(V, c, creases, faces_at, rho):
    """Folded coordinates of a one-vertex sheet: faces_at[k] lies between
    creases k and k+1 (CCW); rho[1:] are the fold angles of creases 1..n-1
    (crease 0 closes the loop)."""
    X = np.hstack([V, np.zeros((len(V), 1))])
    p = X[c]
    out = X.copy()
    M = np.eye(3)
    done = set(faces_at[0])
    for k in range(1, len(creases)):
        M = M @ R(V[creases[k]] - V[c], rho[k])
        for v in faces_at[k]:
            if v not in done:
                out[v] = p + M @ (X[v] - p)
                done.add(v)
    return out


def loop_residual(V, c, creases, rho):
    M = np.eye(3)
    for k in range(len(creases)):
        M = M @ R(V[creases[k]] - V[c], rho[k])
    return np.array([M[2, 1], M[0, 2], M[1, 0]])


def solve_vertex(V, c, creases, rho1, guess):
    f = lambda y: loop_residual(V, c, creases, np.concatenate([[y[0], rho1], y[1:]]))
    r = least_squares(f, guess, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.abs(r.fun).max() < 1e-12
    return np.concatenate([[r.x[0], rho1], r.x[1:]])


def single_fold():
    V = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    faces = [[0, 1, 2], [0, 2, 3]]
    a = np.radians(40)
    X = np.hstack([V, np.zeros((4, 1))])
    p = X[0]
    X[3] = p + R(V[2] - V[0], a) @ (X[3] - p)
    return V, faces, X


def degree4_vertex():
    ang = np.radians([0, 80, 185, 265])
    V = np.vstack([[0, 0], np.c_[np.cos(ang), np.sin(ang)]])
    faces = [[0, 1 + k, 1 + (k + 1) % 4] for k in range(4)]
    rho = solve_vertex(V, 0, [1, 2, 3, 4], np.radians(30), np.radians([-20.0, 30, -20]))
    faces_at = [[1, 2], [2, 3], [3, 4], [4, 1]]
    return V, faces, fold_single_vertex(V, 0, [1, 2, 3, 4], faces_at, rho)


def miura_cell():
    a, b, s = 1.0, 1.0, 0.4  # panel width, height, zigzag offset
    V = np.array([[i * a + (s if j == 1 else 0.0), j * b] for j in range(3) for i in range(3)])
    idx = lambda i, j: 3 * j + i
    faces = [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for j in range(2) for i in range(2)]
    c = idx(1, 1)
    creases = [idx(2, 1), idx(1, 2), idx(0, 1), idx(1, 0)]  # CCW from +x
    rho = solve_vertex(V, c, creases, np.radians(40), np.radians([-40.0, 40, 40]))
    faces_at = [[idx(2, 1), idx(2, 2), idx(1, 2)], [idx(1, 2), idx(0, 2), idx(0, 1)],
                [idx(0, 1), idx(0, 0), idx(1, 0)], [idx(1, 0), idx(2, 0), idx(2, 1)]]
    return V, faces, fold_single_vertex(V, c, creases, faces_at, rho)


def twist_geometry(theta):
    P = [np.array(p, float) for p in [(-.5, -.5), (.5, -.5), (.5, .5), (-.5, .5)]]
    d = [rot2(theta) @ rot2(np.pi / 2 * k) @ np.array([0., -1.]) for k in range(4)]
    return P, d


def twist_residual(rho, theta):
    P, d = twist_geometry(theta)
    S, a, b = rho[0:4], rho[4:8], rho[8:12]
    out = []
    for k in range(4):
        M = (R(P[(k + 1) % 4] - P[k], S[k]) @ R(P[(k - 1) % 4] - P[k], S[(k - 1) % 4])
             @ R(d[(k - 1) % 4], b[(k - 1) % 4]) @ R(d[k], a[k]))
        out += [M[2, 1], M[0, 2], M[1, 0]]
    return np.array(out)


def square_twist(theta=np.radians(30), s0=0.1267732437050385, ell=1.0):
    P, d = twist_geometry(theta)
    A = [P[k] + ell * d[k] for k in range(4)]
    B = [P[(k + 1) % 4] + ell * d[k] for k in range(4)]
    C = [P[k] + ell * (d[k - 1] + d[k]) for k in range(4)]
    V = np.array(P + A + B + C)  # P 0-3, A 4-7, B 8-11, C 12-15
    faces = [[0, 1, 2, 3]] + [[(k + 1) % 4, k, 4 + k, 8 + k] for k in range(4)] + \
            [[k, 8 + (k - 1) % 4, 12 + k, 4 + k] for k in range(4)]
    # one branch of the rigid folding (central creases S, pleats a, b)
    y = np.radians([-4.64, -17.19, 4.64, -4.64, 17.19, 4.64, -17.19, 4.64, -17.19, -4.64, 17.19])
    for s in np.linspace(0.3, s0, 20):
        r = least_squares(lambda z: twist_residual(np.concatenate([[s], z]), theta), y,
                          xtol=1e-15, ftol=1e-15, gtol=1e-15)
        assert np.abs(r.fun).max() < 1e-12
        y = r.x
    rho = np.concatenate([[s0], y])
    S, a, b = rho[0:4], rho[4:8], rho[8:12]
    X3 = np.hstack([V, np.zeros((16, 1))])

    def about(p, u, ang):
        M = R(u, ang)
        p3 = np.array([p[0], p[1], 0.0])
        return M, p3 - M @ p3

    def comp(T1, T2):
        return T1[0] @ T2[0], T1[0] @ T2[1] + T1[1]

    T = [(np.eye(3), np.zeros(3))]
    T += [about(P[k], P[(k + 1) % 4] - P[k], -S[k]) for k in range(4)]
    T += [comp(about(P[k], P[(k - 1) % 4] - P[k], S[(k - 1) % 4]), about(P[k], d[(k - 1) % 4], b[(k - 1) % 4]))
          for k in range(4)]
    X = np.full_like(X3, np.nan)
    for fi, f in enumerate(faces):
        y3 = X3[f] @ T[fi][0].T + T[fi][1]
        for v, p in zip(f, y3):
            assert np.isnan(X[v, 0]) or np.abs(X[v] - p).max() < 1e-9
            X[v] = p
    return V, faces, X


def place(X, deg, off):
    """A generic placement (rotated about z, moved off the axes), as a file
    drawn elsewhere would have: rounding then breaks every symmetry."""
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    M = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    return X @ M[:X.shape[1], :X.shape[1]].T + off[:X.shape[1]]


def write(name, title, V, faces, X, digits=6):
    edges, asg = edges_of(faces)
    coords = lambda Y: [[float(round(v, digits)) + 0.0 for v in p] for p in Y]
    doc = {"file_spec": 1.1, "file_creator": "libkin tests (python/tests/data/fold/make_cases.py)",
           "file_title": title, "file_classes": ["singleModel"], "frame_classes": ["creasePattern"],
           "vertices_coords": coords(V), "edges_vertices": edges, "edges_assignment": asg, "faces_vertices": faces,
           "file_frames": [{"frame_classes": ["foldedForm"], "frame_parent": 0, "frame_inherit": True,
                            "vertices_coords": coords(X)}]}
    with open(name, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    write("single_fold.fold", "Unit square, one diagonal crease", *single_fold())
    write("degree4_vertex.fold", "One degree-4 vertex (sectors 80, 105, 80, 95 deg)", *degree4_vertex())
    write("miura_cell.fold", "Miura-ori cell: 2 x 2 parallelograms", *miura_cell())
    V, faces, X = square_twist()
    off = np.array([0.4324788381589012, 2.8459483414117317, 0.0])
    deg = 85.54173266933418
    write("square_twist.fold", "Square twist (pleats at 30 deg), folded a little; 6 decimals",
          place(V, deg, off), faces, place(X, deg, off))
