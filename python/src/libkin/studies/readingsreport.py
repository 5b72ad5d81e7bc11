"""The readings of the paper's hexagonal sail as Markdown (readings.py):
the side-by-side table, one reading's statements with what was measured,
and `libkin study --reading NAME|all`'s report; and the study report's model
section (model_md)."""
import json
import pathlib
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from libkin.atomic import staged_folder, write_text

from .readings import MAIN_READING, PAPER_STEPS, READINGS, STATEMENTS, best_reading

_MARK = {True: "yes", False: "**no**", None: "not reached"}


def _ms(d: Optional[Dict[str, Any]]) -> str:
    return "" if not d or "m" not in d else f"{d['m']} / {d['s']}"


def measured(row: Dict[str, Any]) -> Dict[str, str]:
    """What was measured for each statement of STATEMENTS, in words."""
    rb, rc, leg1 = row.get("RB", {}), row.get("RC") or {}, row.get("leg1", {})
    ret = rc.get("return") or {}
    planar = [c for c in row.get("RC_candidates", []) if c["hub_out"] < 1e-6 and (c["m"], c["s"]) == (4, 3)]
    steps = row.get("steps", {})
    return {
        "H": f"{row['H'][0]} x {row['H'][1]}",
        "RA": f"m = {row['RA']['m']}, s = {row['RA']['s']}",
        "general": f"m = {row['general']['m']}, s = {row['general']['s']} halfway along leg 1" if "general" in row
        else "no leg 1",
        "RB_exists": (f"strain {rb['strain']:.0e}" if rb.get("exists") else
                      "loop 1 cannot fold flat onto the hub about this diagonal"),
        "RB_ms": f"m = {rb['m']}, s = {rb['s']}" + (f" ({rb['s_without_fixed_bars']} without the zero columns)"
                                                     if "s_without_fixed_bars" in rb else "") if "m" in rb else "",
        "RB_8": (f"{rb['real_solutions']} real of {rb['homotopy_paths']} ({rb['singular']} singular)"
                 if "real_solutions" in rb else rb.get("branches", "")),
        "RB_axisym": (f"{rb['axisym_folding']} axisymmetric paths fold on (centre node "
                      + (", ".join("up" if c > 0 else "down" for c in rb["axisym_folding_centre"]) or "-") + ")"
                      if "axisym_folding" in rb else ""),
        "leg1_hub": f"hub z up to {leg1['hub_out_max_mid']:.3f} a halfway along leg 1" if leg1 else "",
        "RC_paper": (f"R^C at l = {rc['l']:.4f} from R^B: m = {rc['m']}, s = {rc['s']}, hub z {rc['hub_out']:.3f} a; "
                     f"{len(planar)} hub-planar m = 4, s = 3 bifurcations next after R^B"
                     + (" (l = " + ", ".join(f"{c['l']:.3f}" for c in planar) + ")" if planar else "")
                     if rc else ""),
        "fig14": ("the return from R^C retraces to R^B" if ret.get("back_at_RB") else
                  f"the return from R^C ends elsewhere (l = {ret['l']:.3f})" if "l" in ret else ""),
        "steps": ", ".join("-" if steps.get(k) is None else str(steps[k]) for k in PAPER_STEPS),
    }


def statements_md(row: Dict[str, Any]) -> List[str]:
    """One reading's statements as a table: the paper's, measured, verdict."""
    v, m = row["verdicts"], measured(row)
    L = ["| the paper says | measured | holds |", "|---|---|---|"]
    L += [f"| {text} | {m[key]} | {_MARK[v[key]]} |" for text, key in STATEMENTS]
    return L


def missed(row: Dict[str, Any]) -> List[str]:
    """The paper's statements this reading does not reproduce."""
    return [text for text, key in STATEMENTS if not row["verdicts"][key]]


def _cells(row: Dict[str, Any]) -> List[str]:
    rb, rc, leg1 = row.get("RB", {}), row.get("RC") or {}, row.get("leg1", {})
    ret = rc.get("return") or {}
    planar = [c for c in row.get("RC_candidates", []) if c["hub_out"] < 1e-6 and (c["m"], c["s"]) == (4, 3)]
    steps = row.get("steps", {})
    ax = rb.get("axisym_folding")
    return [
        f"{row['H'][0]} x {row['H'][1]}", _ms(row["RA"]), _ms(row.get("general")),
        _ms(rb) if rb.get("exists") else "not strain-free",
        f"{rb['real_solutions']} of {rb['homotopy_paths']}" if "real_solutions" in rb else
        ("not isolated (m > s + 1)" if "branches" in rb else ""),
        "" if ax is None else f"{ax} (" + "/".join("up" if c > 0 else "down" for c in rb["axisym_folding_centre"]) + ")"
        if ax else "0",
        f"{leg1['l']:.3f}" if leg1 else "",
        f"{rc['l']:.3f}, {rc['m']} / {rc['s']}, {rc['hub_out']:.3f}" if rc else "",
        (", ".join(f"{c['l']:.2f}" for c in planar) or "none") if "RC_candidates" in row else "",
        "" if not ret else ("yes" if ret.get("back_at_RB") else "no"),
        " / ".join("-" if steps.get(k) is None else str(steps[k]) for k in PAPER_STEPS),
        f"{row['score']} of {len(STATEMENTS)}",
    ]


def table_md(rows: Sequence[Dict[str, Any]]) -> List[str]:
    """The readings side by side; readings whose every cell agrees are one row."""
    head = ("| reading | H | R^A m / s | general m / s | R^B m / s | R^B real solutions of 2^s | axisymmetric "
            "folding paths out of R^B (centre node) | leg 1 l | R^C: l from R^B, m / s, hub z | hub-planar "
            "m = 4, s = 3 bifurcations next after R^B (l) | return retraces R^C - R^B | steps (paper 35 / 26 / "
            "58 / 149) | statements met |")
    L = [head, "|" + "---|" * 13]
    groups: Dict[Tuple[str, ...], List[str]] = {}
    for r in rows:
        groups.setdefault(tuple(_cells(r)), []).append(r["reading"])
    for cells, names in groups.items():
        L.append(f"| {', '.join(names)} | " + " | ".join(cells) + " |")
    return L


def readings_md(rows: Sequence[Dict[str, Any]]) -> str:
    """`libkin study --reading ...`'s report.md."""
    best = best_reading(rows) if len(rows) > 1 else None
    L = ["# Readings of the paper's hexagonal sail (Section 6.2)\n",
         "Each reading is a model the paper's text allows (python/src/libkin/studies/readings.py, "
         "docs/sail_study.md 'Readings'); every entry is measured by libkin: the flat state and R^B as the "
         "text describes it (hub planar, A_k over V_k alternately up and down), R^B's paths by the complete "
         "solver, each followed to its next event. Lengths in hub sides a.\n",
         "\n".join(table_md(rows)), ""]
    for r in rows:
        L += [f"## {r['reading']}\n", f"{r['what']}.\n", "\n".join(statements_md(r)), ""]
    if best:
        L.append(f"The reading that satisfies the most statements: **{best}** (the main job's is {MAIN_READING}).")
    return "\n".join(L) + "\n"


def write_readings(rows: Sequence[Dict[str, Any]], out: Any) -> None:
    """report.md and readings.json into the folder `out`, committed whole."""
    out = pathlib.Path(out)
    with staged_folder(out) as stage:
        write_text(stage / "readings.json", json.dumps(list(rows), indent=1) + "\n")
        write_text(stage / "report.md", readings_md(rows))


def reading_names() -> List[str]:
    return list(READINGS) + ["all"]


def paper_rc_steps(ev: Optional[Dict[str, Any]]) -> str:
    """The paper's 26 steps to R^C, said as what they are when this R^C is
    not the paper's (hub planar, three values vanishing: m = 4, s = 3)."""
    if ev and ev["hub_out_of_plane"] < 1e-6 and (ev["m"], ev["s"]) == (4, 3):
        return "26"
    return "26, to its own R^C (hub planar, m = 4, s = 3): not this point"


def reading_md(rec: Optional[Dict[str, Any]]) -> List[str]:
    """The main job's section: which model it runs and which of the paper's
    statements that model reproduces and misses."""
    if not rec:
        return []
    L = ["## The model and the paper's statements\n",
         f"The paper's Figure 12 is missing and its text allows several models (docs/sail_study.md, "
         f"'Readings'; `libkin study --reading all` measures all {len(READINGS)} side by side). This run is "
         f"reading **{rec['reading']}**: {rec['what']}. It reproduces {rec['score']} of the paper's "
         f"{rec['of']} statements, the most of any reading:\n",
         "\n".join(statements_md(rec)), ""]
    if rec["missed"]:
        L.append("It misses: " + "; ".join(rec["missed"]) + "."
                 + ("" if rec["verdicts"]["RC_paper"] else
                    " So this run's R^C is not the paper's R^C: the paper's has the hub planar and three singular "
                    "values vanishing; this run's, the next bifurcation after R^B along the fold, does not, and "
                    "nothing measured at it (the step count above included) is a measurement of the paper's.")
                 + "\n")
    return L


def model_md(res: Dict[str, Any], M: Any) -> List[str]:
    """The study report's model section (studyreport.py): unit, joints, bars,
    supports, free coordinates; M: the model's labels, kinds, bars, fixed
    flags and free map (studyreport's model drawing data)."""
    from collections import Counter
    n = res["n_sides"]
    L = ["## The model\n"]
    L.append("**Units.** Lengths (coordinates, bar lengths, path length l, extents) are in units of the hub "
             "side **a**: the model is built with a = 1, so a sail with a 2 m hub side has every length here "
             "times 2 m. Path length l is the Euclidean length of the path in the space of free coordinates, "
             "so it is a length too. Angles are in degrees; strains and singular values of H (whose entries "
             "are direction cosines) have no unit.\n")
    kinds = Counter(M.kinds)
    sk = ["pinned" if r.all() else "partial" if r.any() else "" for r in M.fixed]
    pinned = [M.labels[i] for i, s in enumerate(sk) if s == "pinned"]
    partial = [(M.labels[i], "".join(c for c, f in zip("xyz", M.fixed[i]) if f)) for i, s in enumerate(sk)
               if s == "partial"]
    L.append(f"{len(M.labels)} joints, {len(M.bars)} bars ("
             + ", ".join(f"{kinds[k]} {k}s" for k in ("hub edge", "spoke", "fold", "ring", "diagonal") if kinds[k])
             + f"). Joint names: C the hub centre, V0..V{n - 1} the hub vertices (counter-clockwise, "
             f"V0-V1 the bottom edge), A0..A{n - 1} loop 1 and B0..B{n - 1} loop 2, Ak and Bk on the fold line "
             f"that starts at Vk perpendicular to the hub edge V(k-1)-Vk. "
             f"Supports: {', '.join(pinned)} pinned (x, y, z fixed)"
             + "".join(f"; {lab} held in {c} (free in "
                       f"{''.join(ch for ch in 'xyz' if ch not in c)})" for lab, c in partial)
             + f". Free coordinates: {int((M.fmap >= 0).sum())} (the rows of H); every other joint is free "
             f"in x, y and z. The hub is a regular {n}-gon of side a in the plane z = 0; the fold lines are "
             f"divided into loops of width a tan(pi/{n}) = {np.tan(np.pi / n):.4f} a.\n")
    L.append("![model](model.png)\n")
    L.append("*Figure 1. The model, flat, seen from above. Each joint is marked 'index: label (free "
             "coordinates)'; bar colours give the bar kinds; black triangles are pinned supports, the black "
             "square the centre node, held in x and y.*\n")
    return L
