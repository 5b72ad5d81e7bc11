"""Readings of the paper's hexagonal sail (Section 6.2), side by side.

The paper's Figure 12 is missing; its text fixes "nodes 2, 3 and 4" of the
hub, ties "the other three" to node 1 (moving in z only) by bars, and gives
H as 46 x 45. Several models fit those words. Each reading below is built
from the built-in sail (Assembly.sail: same joints, labels and geometry) by
changing only what the text leaves open: which hub vertices are fixed, which
hub bars there are, and which way the diagonals run. evaluate() checks one
reading against every statement the paper makes about the model and its
fold; readings_table() does all of them.

The loop-1 width is not a free choice: R^B ("nodes 8-13 directly above or
below the hub nodes", hub planar) is strain-free only when the loop-1
trapezium folds flat about its diagonal onto the hub side, which forces
w = a tan(pi/6) (rb_width_residual() measures it for other widths).

Each reading's fold is found from R^B, which the text describes exactly and
which is the same configuration for every reading (the hub lies where it is
fixed): R^B is built, its 2^s paths solved and each followed to its next
event (kin_follow_event). The path that reaches the flat state is leg 1
(R^A - R^B) and its reverse the deployment's last leg; the other paths'
bifurcations are the R^C candidates.
"""
import dataclasses
import itertools
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from libkin.assembly import Assembly
from libkin.errors import KinError

W = math.tan(math.pi / 6)
# the paper's statements, in the order of the table's columns
PAPER_STEPS = {"RB_fold": 35, "RC_fold": 26, "RB_deploy": 58, "RA_deploy": 149}
# a configuration is axisymmetric / a hub planar / a state flat to this (hub sides)
GEOM_TOL = 1e-6
# two located points are one configuration to this (hub sides)
SAME_TOL = 1e-5


@dataclasses.dataclass(frozen=True)
class Reading:
    """One model compatible with Section 6.2's text."""
    name: str
    fixed: Tuple[int, ...]                 # hub vertices fully fixed (V indices)
    hub_bars: Tuple[Tuple[int, int], ...]  # bars between hub vertices (V indices)
    diagonal: str = "forward"
    spokes: bool = True                    # the free vertices tied to the centre node C
    what: str = ""


_EDGES = tuple((k, (k + 1) % 6) for k in range(6))
# consecutive supports V0, V1, V2: the hub edges that reach a free vertex, and
# the bars between hub vertices that could be the two more the count needs
_FREE_EDGES = ((2, 3), (3, 4), (4, 5), (5, 0))
_HUB_CHORDS = ((0, 3), (0, 4), (1, 3), (1, 4), (1, 5), (2, 4), (2, 5), (3, 5))


def _consecutive(pair: Tuple[Tuple[int, int], ...]) -> Reading:
    names = "-".join(f"V{i}V{j}" for i, j in pair)
    return Reading(f"consecutive-{names}", (0, 1, 2), _FREE_EDGES + tuple(pair),
                   what=f"V0, V1, V2 fixed, spokes C-V3, C-V4, C-V5, hub edges V2-V3 to V5-V0, hub bars "
                        f"{' and '.join(f'V{i}-V{j}' for i, j in pair)}")


READINGS: Dict[str, Reading] = {r.name: r for r in (
    Reading("alternating", (0, 2, 4), _EDGES,
            what="V0, V2, V4 fixed, spokes C-V1, C-V3, C-V5, six hub edges, forward diagonals (libkin's "
                 "built-in sail)"),
    Reading("alternating-backward", (0, 2, 4), _EDGES, diagonal="backward",
            what="as alternating with the other diagonal of every trapezium (any support: R^B needs the "
                 "forward one)"),
    Reading("consecutive-zero", (0, 1, 2), _EDGES,
            what="V0, V1, V2 fixed (the paper's nodes 2, 3, 4), spokes C-V3, C-V4, C-V5, all six hub edges: "
                 "V0-V1 and V1-V2 join fixed nodes (two zero columns of H)"),
    *(_consecutive(p) for p in itertools.combinations(_HUB_CHORDS, 2)),
)}
MAIN_READING = "alternating"


def build(reading: Reading) -> Assembly:
    """The flat sail of this reading (joints C, V0..V5, A0..A5, B0..B5)."""
    base = Assembly.sail(6, 2, diagonal=reading.diagonal)
    x, labels = base.coords, base.labels
    V = {k: 1 + k for k in range(6)}  # joint index of V_k (C is joint 0)
    fixed = np.zeros_like(x, dtype=bool)
    fixed[0, :2] = True  # C moves in z only
    for k in reading.fixed:
        fixed[V[k]] = True
    free_v = [k for k in range(6) if k not in reading.fixed]
    bars = [(0, V[k]) for k in free_v] if reading.spokes else []
    bars += [(V[i], V[j]) for i, j in reading.hub_bars]
    loop_bars = [tuple(b) for b in base.bars if b[0] > 6 or b[1] > 6]
    bars += loop_bars
    return Assembly(x, bars, fixed=fixed, labels=labels, name=f"sail_6x2_{reading.name}")


def rb_coords(a: Assembly, width: float = W) -> Optional[np.ndarray]:
    """R^B as the text describes it: hub in its flat place, A_k = V_k +- w e_z
    alternating, loop 2 relaxed to its rest lengths with only the B nodes
    free. None when loop 2 has no strain-free place. `width`: the height w
    of A_k over V_k (the loop-1 width when the trapezia fold flat)."""
    x = a.coords.copy()
    for k in range(6):
        sg = 1.0 if k % 2 == 0 else -1.0
        x[7 + k] = [x[1 + k, 0], x[1 + k, 1], sg * width]
        x[13 + k, 2] = sg * width
    fixed = np.ones_like(x, dtype=bool)
    fixed[13:] = False
    loop2 = Assembly(x, a.bars, fixed=fixed, lengths=a.rest_lengths)
    try:
        loop2.relax(200)
    except KinError:
        return None
    return loop2.coords


def rb_width_residual(width: float) -> float:
    """Largest relative strain of the loop-1 bars when A_k stands at height
    `width` over V_k on a sail with loop widths `width`: 0 only for the
    width a tan(pi/6)."""
    a = Assembly.sail(6, 1, widths=[width])
    x = a.coords.copy()
    for k in range(6):
        x[7 + k] = [x[1 + k, 0], x[1 + k, 1], (1.0 if k % 2 == 0 else -1.0) * width]
    d = np.linalg.norm(x[a.bars[:, 0]] - x[a.bars[:, 1]], axis=1)
    return float(np.max(np.abs(d / a.rest_lengths - 1.0)))


def hub_out_of_plane(x: np.ndarray) -> float:
    """Largest distance of a hub vertex from the plane z = 0 of the fixed
    ones (three of them, in every reading), as the main job measures it."""
    return float(np.abs(x[1:7, 2]).max())


def axisymmetry(x: np.ndarray) -> float:
    """How far x is from three-fold symmetry: the largest joint distance
    between x and its image under V_k, A_k, B_k -> V_k+2, A_k+2, B_k+2 (C
    kept), after the best rigid fit (Kabsch)."""
    perm = [0] + [1 + 6 * q + (k + 2) % 6 for q in range(3) for k in range(6)]
    p, q = x[perm], x
    pc, qc = p - p.mean(axis=0), q - q.mean(axis=0)
    u, _, vt = np.linalg.svd(pc.T @ qc)
    dsign = np.sign(np.linalg.det(u @ vt)) or 1.0
    r = u @ np.diag([1.0, 1.0, dsign]) @ vt
    return float(np.linalg.norm(pc @ r - qc, axis=1).max())


def _analysis(a: Assembly) -> Dict[str, int]:
    an = a.analyse()
    return {"r": int(an.rank), "m": int(an.m_internal), "m_rigid": int(an.m_rigid), "s": int(an.s)}


def _follow(start: Assembly, d: np.ndarray, max_length: float = 0.0) -> Tuple[Assembly, Any]:
    c = start.clone()
    fe = c.follow_event(d, max_steps=800, max_length=max_length)
    return c, fe


def _mech_direction(a: Assembly, v: np.ndarray) -> np.ndarray:
    U = a.analyse().internal_mechanisms
    return U @ (U.T @ v)


def _paths_from_rb(rb: Assembly, flat: np.ndarray, threads: int) -> Tuple[Any, List[Dict[str, Any]]]:
    """Every directed path out of R^B followed to its next event."""
    br = rb.branches(solver="homotopy", length=0.5, threads=threads)
    out = []
    for p in br.paths:
        if not (p.exists and p.tangent_ok):
            continue
        d = br.directions[p.beta] * p.sign
        end, fe = _follow(rb, d)
        rec: Dict[str, Any] = {"beta": int(p.beta), "sign": int(p.sign), "d": d, "event": fe.event, "l": float(fe.length),
               "steps": int(fe.steps), "axisym": axisymmetry(p.final_coords) < GEOM_TOL,
               "centre_dz": float(p.final_coords[0, 2] - rb.coords[0, 2]), "end": end,
               "xy_at_half": float(np.hypot(p.final_coords[:, 0], p.final_coords[:, 1]).max())}
        if fe.event == "bifurcation":
            x = end.coords
            rec.update(_analysis(end))
            rec["flat"] = bool(np.abs(x - flat).max() < SAME_TOL)
            rec["hub_out"] = hub_out_of_plane(x)
            rec["xy_extent"] = float(np.hypot(x[:, 0], x[:, 1]).max())
        out.append(rec)
    return br, out


def _return_steps(rc: Assembly, arrival_from: Assembly, d_in: np.ndarray, l_in: float, rb: Assembly,
                  threads: int) -> Dict[str, Any]:
    """From R^C back along the arrival path: the R^C path most nearly
    opposite to the arrival chord, followed to its next event."""
    pre, _ = _follow(arrival_from, d_in, max_length=max(l_in - 0.05, 0.5 * l_in))
    chord = rc.coords[rc.free_map() >= 0] - pre.coords[pre.free_map() >= 0]
    try:
        br = rc.branches(solver="homotopy", length=0.3, threads=threads)
    except KinError as exc:
        return {"stopped": str(exc)}
    dirs = [br.directions[p.beta] * p.sign for p in br.paths if p.exists and p.tangent_ok]
    if not dirs:
        return {"stopped": "no path out of R^C"}
    cos = [float(v @ chord) / (np.linalg.norm(v) * np.linalg.norm(chord)) for v in dirs]
    out: Dict[str, Any] = {"real_solutions": len(br.betas), "back_at_RB": False}
    # the arrival path is among the paths nearly opposite to the arrival
    # chord; where several are, the first (most opposite) back at R^B
    for i in sorted(range(len(dirs)), key=lambda i: cos[i]):
        if out.get("steps") is not None and cos[i] > -0.99:
            break
        end, fe = _follow(rc, dirs[i])
        back = fe.event == "bifurcation" and _distance(end.coords, rb.coords) < SAME_TOL
        if out.get("steps") is None or back:
            out.update({"steps": int(fe.steps), "event": fe.event, "l": float(fe.length), "cos": cos[i],
                        "back_at_RB": bool(back), "retraces": bool(cos[i] < -0.99)})
        if back:
            break
    return out


def _distance(x: np.ndarray, y: np.ndarray) -> float:
    """Largest joint distance between x and y or y's mirror image z -> -z
    (a state and its mirror image are one state of the sail)."""
    m = y.copy()
    m[:, 2] *= -1.0
    return float(min(np.abs(x - y).max(), np.abs(x - m).max()))


def evaluate(reading: Reading, threads: int = 2) -> Dict[str, Any]:
    """Every statement of Section 6.2, measured on this reading."""
    full = build(reading)
    flat = full.coords
    row: Dict[str, Any] = {"reading": reading.name, "what": reading.what, "H": [full.nfree, full.nbars],
                           "RA": _analysis(full)}
    x = rb_coords(full)
    if x is None:
        row["RB"] = {"exists": False}
        return row
    rb = full.clone()
    rb.coords = x
    row["RB"] = dict(_analysis(rb), exists=bool(rb.max_strain < 1e-10), strain=float(rb.max_strain),
                     hub_out=hub_out_of_plane(x), axisym=axisymmetry(x) < GEOM_TOL)
    an = rb.analyse()
    if an.s_trivial:
        # bars between fixed joints (consecutive-zero): their self-stresses
        # constrain nothing and the second order leaves them out
        row["RB"]["s_without_fixed_bars"] = int(an.s - an.s_trivial)
    try:
        br, paths = _paths_from_rb(rb, flat, threads)
    except KinError as exc:  # e.g. m > s + 1: the paths out of R^B are not isolated
        row["RB"]["branches"] = str(exc)
        return row
    row["RB"]["real_solutions"] = len(br.betas)
    row["RB"]["homotopy_paths"] = int(br.accounting["paths"])
    row["RB"]["singular"] = int(br.accounting["singular"])
    row["RB"]["directed_paths"] = len(paths)
    to_flat = [p for p in paths if p.get("flat")]
    folds = [p for p in paths if p["event"] == "bifurcation" and not p.get("flat")]
    row["RB"]["paths_to_flat"] = len(to_flat)
    row["RB"]["axisym_paths"] = sum(p["axisym"] for p in paths)
    ax_fold = [p for p in folds if p["axisym"]]
    row["RB"]["axisym_folding"] = len(ax_fold)
    row["RB"]["axisym_folding_centre"] = sorted({int(np.sign(p["centre_dz"])) for p in ax_fold})
    row["RC_candidates"] = [{k: p[k] for k in ("l", "m", "s", "hub_out", "xy_extent", "axisym", "steps")}
                            for p in sorted(folds, key=lambda p: (p["l"], p["beta"], p["sign"]))]
    row["RC_planar_s3"] = sum(1 for p in folds if p["hub_out"] < GEOM_TOL and p["s"] == 3 and p["m"] == 4)
    if to_flat:
        leg1 = min(to_flat, key=lambda p: (p["l"], p["beta"], p["sign"]))
        row["leg1"] = {"l": leg1["l"], "steps_RB_to_RA": leg1["steps"]}
        mid, _ = _follow(rb, leg1["d"], max_length=0.5 * leg1["l"])
        row["general"] = _analysis(mid)
        row["leg1"]["hub_out_max_mid"] = hub_out_of_plane(mid.coords)
        # R^A to R^B: the flat state's path towards R^B (the chord of its last
        # stretch, as a mechanism at R^A), followed to its next event
        pre, _ = _follow(rb, leg1["d"], max_length=leg1["l"] - 0.05)
        ra = full.clone()
        d = _mech_direction(ra, pre.coords[full.free_map() >= 0] - flat[full.free_map() >= 0])
        end, fe = _follow(ra, d)
        row["leg1"]["steps_RA_to_RB"] = int(fe.steps)
        row["leg1"]["reaches_RB"] = bool(fe.event == "bifurcation" and _distance(end.coords, x) < SAME_TOL)
    # the arrival path continued straight through R^B is not a change of
    # path; the main job leaves it out too
    if to_flat:
        onward = [p for p in folds if not (p["beta"] == leg1["beta"] and p["sign"] == -leg1["sign"])]
        row["RB"]["straight_on"] = [{k: p[k] for k in ("l", "m", "s", "hub_out")} for p in folds if p not in onward]
        folds = onward or folds
    rc = _pick_rc(folds)
    if rc is not None:
        row["RC"] = {k: rc[k] for k in ("l", "m", "s", "r", "hub_out", "xy_extent", "axisym", "steps", "centre_dz")}
        row["RC"]["return"] = _return_steps(rc["end"], rb, rc["d"], rc["l"], rb, threads)
    return row


def _pick_rc(folds: Sequence[Dict[str, Any]]) -> Optional[Dict[str, Any]]:
    """The reading's R^C: of the paths out of R^B that reach a bifurcation
    other than the flat state, an axisymmetric one with the paper's R^C
    (hub planar, three values vanishing) if any, else an axisymmetric one,
    else any; of those, the one that leaves the sail most compact (x-y
    extent at l = 0.5 from R^B), the main job's choice."""
    def paper(p: Dict[str, Any]) -> bool:
        return p["hub_out"] < GEOM_TOL and p["m"] == 4 and p["s"] == 3
    rules: List[Any] = [lambda p: p["axisym"] and paper(p), paper, lambda p: p["axisym"], lambda p: True]
    for keep in rules:
        c = [p for p in folds if keep(p)]
        if c:
            return min(c, key=lambda p: round(p["xy_at_half"], 9))  # the first on ties, as the main job
    return None


# ---- the statements, each a yes/no on a row --------------------------------------------
STATEMENTS: List[Tuple[str, str]] = [
    ("H 46 x 45", "H"),
    ("R^A: m = 16, s = 15", "RA"),
    ("one finite internal mechanism in a general state", "general"),
    ("R^B (A_k over V_k, hub planar) strain-free", "RB_exists"),
    ("R^B: m = 4, s = 3", "RB_ms"),
    ("R^B: 8 real solutions (2^3 paths)", "RB_8"),
    ("R^B: two axisymmetric paths (C up / down) fold on", "RB_axisym"),
    ("R^A to R^B: hub out of plane on the way", "leg1_hub"),
    ("R^C: hub planar, m = 4, s = 3 (three values vanish)", "RC_paper"),
    ("Figure 14 symmetric: the return retraces R^C - R^B", "fig14"),
    ("steps 35, 26, 58, 149", "steps"),
]


def judge(row: Dict[str, Any]) -> Dict[str, Optional[bool]]:
    """Each statement of STATEMENTS on one evaluated row (None: not reached)."""
    rb, rc = row.get("RB", {}), row.get("RC")
    ret = (rc or {}).get("return", {})
    steps = _steps(row)
    return {
        "H": row["H"] == [46, 45],
        "RA": (row["RA"]["m"], row["RA"]["s"]) == (16, 15),
        "general": None if "general" not in row else (row["general"]["m"], row["general"]["s"]) == (1, 0),
        "RB_exists": bool(rb.get("exists")),
        "RB_ms": None if not rb.get("exists") else (rb["m"], rb["s"]) == (4, 3),
        "RB_8": None if "real_solutions" not in rb else rb["real_solutions"] == 8,
        "RB_axisym": None if "axisym_folding" not in rb else (rb["axisym_folding"] == 2
                                                              and rb["axisym_folding_centre"] == [-1, 1]),
        "leg1_hub": None if "leg1" not in row else row["leg1"]["hub_out_max_mid"] > GEOM_TOL,
        "RC_paper": None if rc is None else (rc["hub_out"] < GEOM_TOL and (rc["m"], rc["s"]) == (4, 3)),
        "fig14": None if not ret else bool(ret.get("back_at_RB") and ret.get("retraces")),
        "steps": None if None in steps.values() else steps == PAPER_STEPS,
    }


def _steps(row: Dict[str, Any]) -> Dict[str, Optional[int]]:
    leg1, rc = row.get("leg1", {}), row.get("RC") or {}
    return {"RB_fold": leg1.get("steps_RA_to_RB") if leg1.get("reaches_RB") else None, "RC_fold": rc.get("steps"),
            "RB_deploy": (rc.get("return") or {}).get("steps"), "RA_deploy": leg1.get("steps_RB_to_RA")}


def score(row: Dict[str, Any]) -> int:
    return sum(1 for v in judge(row).values() if v)


def readings_table(names: Optional[Sequence[str]] = None, threads: int = 2) -> List[Dict[str, Any]]:
    """Every reading (or `names`) evaluated, with its verdicts and score."""
    rows = []
    for name in names or list(READINGS):
        row = evaluate(READINGS[name], threads=threads)
        row["verdicts"] = judge(row)
        row["steps"] = _steps(row)
        row["score"] = score(row)
        rows.append(row)
    return rows


def best_reading(rows: Sequence[Dict[str, Any]]) -> str:
    """The reading that satisfies the most statements (ties: the order of READINGS)."""
    order = list(READINGS)
    return max(rows, key=lambda r: (r["score"], -order.index(r["reading"])))["reading"]


def reading_record(name: str = MAIN_READING, threads: int = 2) -> Dict[str, Any]:
    """One reading for a study's summary: its measurements, each statement's
    verdict and the statements it misses."""
    row = readings_table([name], threads=threads)[0]
    row["of"] = len(STATEMENTS)
    row["missed"] = [text for text, key in STATEMENTS if not row["verdicts"][key]]
    return row
