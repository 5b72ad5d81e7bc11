"""Markdown reports and figures of the sail studies (see sailstudy.py)."""
import numpy as np

from libkin.atomic import write_text
from libkin.plot import draw, pyplot

from .common import branch_words
from .readingsreport import model_md, paper_rc_steps, reading_md



def _undecided_words(und):
    """The wrap test's undecided candidates (studies/margin.py), with their
    numbers; nothing where there are none."""
    if not und:
        return ""
    parts = [f"solution {c['beta']} sign {c['sign']:+d} (offset {c['loop1_xy']:.2g} +- "
             f"{c['loop1_xy_uncertainty']:.1g})" for c in und]
    return (f", and {len(und)} undecided (x-y offset within a factor 10 of the 1e-5 test at the accuracy "
            f"their node was located to, counted neither way): " + "; ".join(parts))

def _fmt(v, nd=3):
    return f"{v:.{nd}g}" if isinstance(v, float) else str(v)


def _event_row(name, ev, paper):
    if not ev:
        return f"| {name} | not reached | | | | | | | | {paper} |"
    pm = ev.get("paper_method", {})
    if "factorizations" in pm:
        pcol = f"{pm['factorizations']} ({pm['forward']} forward), {pm['v_r_rel']:.0e}"
    else:
        pcol = "gave up" if pm else ""
    return (f"| {name} | {ev.get('l', float('nan')):.4f} | {ev['m']} / {ev['s']} | {ev['steps']} | "
            f"{ev['factorizations']} ({ev['forward']} forward) | {ev['method']} | {ev['v_r_rel']:.1e} | "
            f"{ev['hub_out_of_plane']:.3f} | {pcol} | {paper} |")


def hexagonal(res, track, stages, out, smap=None, snaps=None, progress=None):
    """Every figure (studyfigures.py) and report.md; res["seconds_figures"]
    is the time the figures took (report.md's run time includes it).
    progress: a line on stderr as each figure starts and as it is done
    (common.say), so the minutes of drawing are not silent."""
    import time
    t0 = time.perf_counter()
    from . import studyfigures as F
    from .common import say
    M = F.Model(res["n_sides"], res["n_loops"])
    figs = {}
    steps = [("the model", lambda: F.model_figure(M, out)),
             ("the stages in 2D", lambda: F.stages_2d(M, stages, out)),
             ("the stages in 3D", lambda: F.stages_3d(M, stages, out)),
             ("the singular values", lambda: figs.__setitem__("sv_groups", F.singular_values(res, track, out))),
             ("bar strain and hub planarity", lambda: F.strain_hub(res, track, out)),
             ("the fold measures", lambda: F.fold_measures(M, res, track, out))]
    if smap is not None and smap.nodes:
        steps.append(("the path map", lambda: F.path_map(smap, out)))
    if smap is not None and smap.contact_atlas is not None:
        def contact_map():
            from libkin.atlas.plot import draw_map
            draw_map(smap.contact_atlas, out / "contact_map.png",
                     title=f"The path map with contact as an event (t/a = {res['contact_map']['thickness']:g})")
            figs["contact_map"] = "contact_map.png"
        steps.append(("the path map with contact", contact_map))
    figs["grids"] = []
    for name, snap in (snaps or {}).items():
        def grid(name=name, snap=snap):
            fname = f"branches_{name.replace('^', '')}.png"
            factor = F.branch_grid(M, name, snap, snap["base"], out, fname)
            figs["grids"].append((name, fname, snap, factor))
        steps.append((f"the branches at {name}", grid))
    steps.append(("the animation", lambda: figs.__setitem__("gif_frames", F.animation(M, res, track, out))))

    def fold():
        # the run for origami software: every accepted step a FOLD frame
        from libkin.io.fold import write_fold
        doc = write_fold(out / "fold_run.fold", M.a, path_coords=track.coords, faces="triangles",
                         title=f"libkin: {res['model']}, fold R^A-R^B-R^C and back",
                         description="Lengths in units of the hub side a. One frame per accepted path step.")
        figs["fold_frames"] = 1 + len(doc.get("file_frames", []))
    steps.append(("the FOLD file of the run", fold))
    for k, (what, draw) in enumerate(steps):
        say(progress, f"[figures] {k + 1}/{len(steps)}: {what} ...")
        t = time.perf_counter()
        draw()
        say(progress, f"[figures] {what}: {time.perf_counter() - t:.1f} s")
    res["seconds_figures"] = round(time.perf_counter() - t0, 1)
    _write_hex_md(res, out, M, figs)


def _nz(v, nd):
    """v rounded to nd decimals, without a minus sign on zero."""
    return round(v, nd) + 0.0


def _where_row(name, m, l_total, l_prev, mn):
    fe, fo = m["fold_angle_even"], m["fold_angle_odd"]
    folds = " ; ".join(f"{_nz(e, 1):+.1f} / {_nz(o, 1):+.1f}" for e, o in zip(fe, fo))
    lp = "" if l_prev is None else f"{l_prev:.4f}"
    return (f"| {name} | {l_total:.4f} | {lp} | {mn} | {m['xy_extent']:.3f} | {m['z_extent']:.3f} | "
            f"{_nz(m['z_min'], 3):+.3f} .. {_nz(m['z_max'], 3):+.3f} | {m['hub_out_of_plane']:.3f} | {folds} |")


_FOLD_WORDS = {2: "two", 3: "three", 4: "four", 5: "five", 6: "six"}


def _write_hex_md(res, out, M, figs):
    n = res["n_sides"]
    nfold = f"{_FOLD_WORDS.get(n // 2, str(n // 2))}-fold"
    even = ", ".join(str(k) for k in range(0, n, 2))
    odd = ", ".join(str(k) for k in range(1, n, 2))
    ev = res["events"]
    flat = res["flat"]
    L = []
    L.append(f"# Folding and deployment of the solar sail ({res['model']})\n")
    L.append("Generated by `libkin study` (python/src/libkin/studies/sailstudy.py); numbers in summary.json. "
             "All lengths in units of the hub side a (below).\n")
    if "failed" in res:
        L.append(f"**The run stopped early: {res['failed']}.**\n")
    L.append("![fold animation](fold_animation.gif)\n")
    L.append(f"*The run, animated ({figs.get('gif_frames', 0)} frames): from the flat state R^A the sail folds "
             "to R^B (loop 1 wrapped against the hub), on to R^C, and deploys back along the same path. "
             "Colours as in Figure 1.*\n")
    if figs.get("fold_frames"):
        L.append(f"The whole run is also in `fold_run.fold` ({figs['fold_frames']} frames, one per accepted step; "
                 "the FOLD format of origami software, faces = the sail's bar triangles, supports in "
                 "`vertices_libkin:fixed`; docs/fold.md).\n")
    L += model_md(res, M)
    L.append("## The flat state R^A\n")
    L.append(f"H is {flat['nfree']} x {flat['nbars']}; m = {flat['m']} internal mechanisms, s = {flat['s']} "
             "self-stresses.")
    if "complete" in flat:
        c = flat["complete"]
        L.append(f" Complete solver over all {c['paths']} homotopy paths: {c['real']} real endpoints "
                 f"({c['real_distinct']} distinct), {c['nonreal']} complex, {c['singular']} singular, "
                 f"{c['failed']} failed, in {c['seconds']} s.")
        if "proven_real" in c:
            L.append(f" Proven by interval certificates (docs/branches.md): {c['proven_real']} real and "
                     f"{c['proven_nonreal']} non-real solutions, {c['unproven']} unproven"
                     + (f", all {c['paths']} of them: there are no others." if c.get("proven_all") else "."))
        if c.get("orbits", c["paths"]) < c["paths"]:
            L.append(f" By the sail's symmetry ({c['group']} rotations) {c['orbits']} of the paths were tracked, "
                     "one per orbit of start roots; the others' endpoints are theirs rotated, each refined "
                     "and certified on its own.")
        if (c["singular"] == 0 and c["failed"] == 0 and c.get("duplicates", 1) == 0 and c.get("unpaired", 1) == 0
                and c["real"] == c["real_distinct"]):
            L.append(" Every endpoint is a certified simple root reached by one path, and the complex ones pair "
                     "up with their conjugates: these are all the solutions (docs/branches.md).")
    sym = flat["symmetric"]
    L.append(f"\n\nRestricted to motions that keep the hub's {res['model'].split()[1]} supports' rotational "
             f"symmetry: {sym['k']} mechanisms, {sym['s']} equations, {sym['accounting']['real_distinct']} real "
             f"solutions of {sym['accounting']['paths']} paths.\n")
    if "chosen" in flat:
        ch = flat["chosen"]
        L.append("**Choice of the folding branch (automatic).** Criterion: the path keeps the rotational "
                 "symmetry and its first bifurcation has every loop-1 node directly above or below its hub "
                 "vertex, alternately up and down (loop 1 wrapped, as in the paper's Figure 13(c)); of "
                 "those, the shortest. "
                 f"{flat['candidates']} symmetric directed candidates were followed: "
                 f"{flat['candidates_reaching_bifurcation']} reach a bifurcation, "
                 f"{flat['candidates_wrapping_loop1']} wrap loop 1"
                 + _undecided_words(flat.get("candidates_wrap_undecided", []))
                 + f". Chosen: solution {ch['beta']}, sign "
                 f"{ch['sign']:+d}, reaching R^B at l = {ch['reached']:.4f} a.\n")
    L.append("## Where the bifurcations are\n")
    L.append("Each point placed by what can be measured on the structure, as well as by path length: the "
             "x-y extent (largest distance of a joint from the hub's axis: the radius of the folded "
             "package), the height (z-extent of the sail), how far the free hub vertices leave the hub "
             "plane, and the angle of each fold line to the hub plane (fold segments Vk-Ak of loop 1 and "
             f"Ak-Bk of loop 2; the motion keeps the {nfold} symmetry, so the folds k = {even} are alike "
             f"and so are k = {odd}: the column gives 'even / odd', positive = rising towards +z).\n")
    L.append("| point | l from R^A along the run (a) | l from previous (a) | m / s | x-y extent (a) | height "
             "(a) | z range (a) | hub out of plane (a) | fold angles to the hub plane (deg): loop 1 even / odd ; "
             "loop 2 even / odd |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    L.append(_where_row("R^A (start, flat)", flat["measures"], 0.0, None, f"{flat['m']} / {flat['s']}"))
    for key, name in (("RB_fold", "R^B (folding)"), ("RC_fold", "R^C (folding)"), ("RB_deploy", "R^B (deploying)"),
                      ("RA_deploy", "R^A (deploying)")):
        e = ev.get(key)
        if e and "measures" in e:
            L.append(_where_row(name, e["measures"], e["l_total"], e["l"], f"{e['m']} / {e['s']}"))
    if "most_compact_on_run" in res:
        mc = res["most_compact_on_run"]
        L.append(f"\nThe most compact configuration met on the run is not a bifurcation: between R^B and R^C the "
                 f"x-y extent falls to {mc['xy_extent']:.3f} a (at l = {mc['l_total']:.2f} a from R^A, height "
                 f"{mc['height']:.3f} a, the nearest accepted step) and grows again to R^C's value (Figure 2).")
    L.append("\n![fold measures](fold_measures.png)\n")
    L.append("*Figure 2. How far the sail has folded along the run: top, the angle of each fold line to the "
             "hub plane (red loop 1, blue loop 2; solid folds k even, dashed k odd); bottom, the sail's x-y "
             "extent and height. Dotted lines: the bifurcations. The run is symmetric about R^C because the "
             "deployment retraces the fold.*\n")
    L.append("## Locating the bifurcations\n")
    L.append("| point | l from previous (a) | m / s | steps | factorizations to locate | method | v_r / v_max "
             "| hub max abs z (a) | paper's method here (tol 1e-6): factorizations, v_r | paper (steps) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    L.append(_event_row("R^B (folding)", ev.get("RB_fold"), 35))
    L.append(_event_row("R^C (folding)", ev.get("RC_fold"), paper_rc_steps(ev.get("RC_fold"))))
    L.append(_event_row("R^B (deploying)", ev.get("RB_deploy"), 58))
    L.append(_event_row("R^A (deploying)", ev.get("RA_deploy"), 149))
    L.append("\nEach leg is followed by the library's follower (kin_follow_event, the explorer's): 'steps' "
             "are its path steps from the previous bifurcation until the bifurcation was detected (the "
             "first steps off a bifurcation are short, 1e-3 of a full step growing tenfold); the "
             "factorizations (SVDs, QR and LU factorizations) are those of locating after that, to "
             "v_r / v_max <= 1e-10 for every singular value that vanishes there, by the fast method "
             "(Hermite interpolation, docs/locate.md). The paper's method was run for comparison at the "
             "paper's own tolerance from the last point recorded before the bifurcation (about two full "
             "steps before it); the paper's counts are its locator steps at 1e-6, each at least one "
             "factorization.\n")
    for key, name in (("RB", "R^B"), ("RC", "R^C")):
        if key in res:
            r = res[key]
            L.append(f"At {name}: {branch_words({k: v for k, v in r.items() if k != 'seconds'})}.")
            if "chosen" in r:
                ch = r["chosen"]
                L.append(f" Onward folding path chosen: symmetric, not the arrival path, smallest x-y extent "
                         f"after l = 0.5 a ({ch['xy_extent_at_0.5']:.4f} a); cos with the arrival chord "
                         f"{ch['cos_with_arrival']:.3f}; the centre node moves {'down' if ch['centre_dz'] < 0 else 'up'}"
                         f" (the paper's two axisymmetric folding motions: node 1 up or down).")
            L.append("\n")
    if figs.get("grids"):
        L.append("## The paths leaving each bifurcation\n")
        fig_no = 3
        for name, fname, snap, factor in figs["grids"]:
            n = len(snap["paths"])
            sym = sum(p["symmetric"] for p in snap["paths"])
            which = (f"every symmetric directed path (the run's choice is among them; the 2^{res['flat']['s']} "
                     f"others break the {nfold} symmetry)" if name == "R^A" else
                     f"every directed path the complete solver finds ({sym} of them keep the {nfold} symmetry)")
            L.append(f"![branches at {name}]({fname})\n")
            L.append(f"*Figure {fig_no}. Out of {name}: {which}, {n} drawings, each the configuration at path "
                     f"length {snap['length']} a from {name}, seen from above over {name} itself (grey)"
                     + (f", movements drawn {factor:.1f} times their size (colours true)" if factor > 1.05 else "")
                     + "; joint colour: how far it moved up (red) or down (blue). Titles: "
                     "'+b3' is second-order solution 3 followed in the + sense; '-> X' the next bifurcation "
                     "it reaches (R^A: names as in the path map); red: the path the run takes; orange: back "
                     "the way the run came; green: the arrival path continued; '(asym.)': breaks the "
                     "symmetry.*\n")
            fig_no += 1
    else:
        fig_no = 3
    if "map" in res:
        L += _map_md(res, nfold)
        L.append("![path map](path_map.png)\n")
        L.append(f"*Figure {fig_no}. The path map. Each marker is a node of the atlas, placed by how compact "
                 "the sail is there (x-y extent, folded to the right) and how many internal mechanisms it has; "
                 "filled markers are bifurcations (orange diamonds: located only to a coarser v_r, so m and s "
                 "are counted at a relaxed rank tolerance), hollow markers points that are not bifurcations "
                 "(near-misses, regular points); arrows are symmetric paths between them (thicker: more "
                 "directed paths). A node and its mirror image z -> -z share a marker.*\n")
        fig_no += 1
    if "contact_map" in res:
        from .contactreport import contact_map_md
        L += contact_map_md(res["contact_map"], res.get("map", {}).get("atlas", {}).get("edges"),
                            figs.get("contact_map"))
    L += reading_md(res.get("reading"))
    L.append("## The paper's three questions\n")
    cont = "failed" not in res
    L.append(f"1. **Continuous strain-free motion from open to folded?** "
             f"{'Yes' if cont else 'Not shown'}: the run went R^A -> R^B -> R^C and back to R^A with a "
             f"largest bar strain of {res.get('max_strain', float('nan')):.1e} at any accepted step "
             f"({res.get('steps_total', 0)} steps, total path length {res.get('path_length_total', 0):.3f} a); "
             f"closure error on return to the flat state {res.get('closure', float('nan')):.1e} a.")
    pts = []
    for k, v in ev.items():
        if v and "l_total" in v and "measures" in v:
            m = v["measures"]
            pts.append(f"{k.split('_')[0].replace('R', 'R^')} at l = {v['l_total']:.4f} a (m = {v['m']}, "
                       f"s = {v['s']}): x-y extent {m['xy_extent']:.3f} a, height {m['z_extent']:.3f} a, "
                       f"loop-1 folds at {m['fold_angle_even'][0]:+.1f} / {m['fold_angle_odd'][0]:+.1f} deg to "
                       "the hub plane")
    L.append("2. **Where are the bifurcations?** " + "; ".join(pts) + ". At each the sail can leave the "
             "intended path (the counts of distinct paths, and their drawings, are above), so the deployment "
             "can go astray there.")
    L.append(f"3. **Does the hub stay planar?** No: the largest out-of-plane displacement of a hub node is "
             f"{res.get('max_hub_out_of_plane', float('nan')):.3f} a, i.e. {res.get('max_hub_out_of_plane', 0):.1%}"
             " of the hub side (strain_hub.png).\n")
    L.append("## Figures of the run\n")
    L.append("![stages 3D](stages_3d.png)\n")
    L.append(f"*Figure {fig_no}. The folding stages in 3D, one scale on x, y and z: (a) flat R^A, (b) halfway "
             "to R^B, (c) R^B with loop 1 wrapped (each Ak above or below Vk), (d) halfway to R^C, (e) R^C.*\n")
    L.append("![stages](fig13_stages.png)\n")
    L.append(f"*Figure {fig_no + 1}. The same stages projected, as the paper's Figure 13: from above (x-y, "
             "top) and from the side (x-z, bottom).*\n")
    g = figs.get("sv_groups", {})
    desc = "; ".join(f"{len(cols)} vanish at {', '.join(w)}" for w, cols in g.items())
    L.append("![singular values](fig14_singular_values.png)\n")
    L.append(f"*Figure {fig_no + 2}. The 15 lowest singular values of H along the run (Figure 14's "
             f"counterpart), sigma_1 the lowest, coloured by where they vanish: {desc}. Each curve is the "
             "k-th lowest value at each point, so curves may exchange the modes they follow where they "
             "cross.*\n")
    L.append("![strain and hub](strain_hub.png)\n")
    L.append(f"*Figure {fig_no + 3}. Top: the largest bar strain at every accepted step (the corrector "
             "stops at 1e-12). Bottom: how far the free hub vertices leave the hub plane, in a.*\n")
    if "interference" in res:
        from .contactreport import contact_figure, interference_chart, interference_md
        study = {"thicknesses": [c["t"] for c in res["interference"]["contacts"]], "members": [res["interference"]]}
        interference_chart(study, out / "interference.png")
        L.append(interference_md(study))
        if contact_figure(res["interference"], out / "contact_first.png"):
            L.append("![first contact](contact_first.png)\n")
            L.append("*The configuration at the first contact, bare and at the largest thickness: the two parts "
                     "that touch in red and orange, their closest points in black.*\n")
        L.append("All eight members (hexagonal and octagonal hubs, 1 to 4 loops): `libkin study --interference` "
                 "(stored run and findings: examples/interference/report.md, docs/contact.md).\n")
    figs_s = res.get("seconds_figures", 0.0)
    L.append(f"Run time {res['seconds'] + figs_s:.1f} s: the study {res['seconds']} s, the figures and files "
             f"{figs_s} s.\n")
    write_text(out / "report.md", "\n".join(L))


_KIND_WORDS = {"bifurcation": "bifurcation", "near_miss": "near-miss (m = 1)", "regular": "regular point (m = 1)",
               "multi_dof": "several freedoms (s = 0)", "rigid": "rigid (m = 0)", "failure": "following failed",
               "undecided": "undecided (v_r near its floor, or tangent branches)"}
_EVENT_WORDS = {"bifurcation": "bifurcation", "near_miss": "near-miss (m = 1)", "loop": "closed loop",
                "budget": "length budget", "failure": "failure"}


def _kind_word(n):
    if n["kind"] == "bifurcation" and n["located_tol"] > 1e-10:
        return f"bifurcation, located only to {n['located_tol']:.0e} (m, s at 10 x that)"
    return _KIND_WORDS.get(n["kind"], n["kind"])


def _relaxed_words(nodes):
    """What the default rank tolerance says at the coarsely located bifurcations."""
    out = []
    for n in nodes:
        if "m_default" in n and not n["name"].endswith("'"):
            sv = n["lowest_sv_rel"]
            out.append(f"at {n['name']} the lowest singular values are {', '.join(f'{v:.0e}' for v in sv)} "
                       f"of v_max, so the default rank tolerance (1e-9) counts m = {n['m_default']}, "
                       f"s = {n['s_default']}")
    return ("; ".join(out) + ".") if out else ""


def _map_md(res, nfold):
    """The path map's tables: the directed paths, then the nodes by kind."""
    mp = res["map"]
    at = mp["atlas"]
    kinds = ", ".join(f"{v} {_KIND_WORDS.get(k, k)}" for k, v in sorted(at["node_kinds"].items()))
    events = ", ".join(f"{v} {_EVENT_WORDS.get(k, k)}" for k, v in sorted(at["edge_events"].items()))
    relaxed = sum(1 for n in mp["nodes"] if n["kind"] == "bifurcation" and n["located_tol"] > 1e-10)
    L = ["## Path map (symmetric paths)\n"]
    L.append(f"The explorer's atlas (`libkin.explore`, docs/atlas.md; `atlas.json` here"
             + ("; [atlas.html](atlas.html) to walk it in a browser, offline: a click on a node shows it in 3D, on a "
                "path moves the sail along it" if res.get("map_html") else "") + ") in symmetric mode: "
             f"every directed path out of R^A that keeps the {nfold} symmetry, followed to its next event, and "
             f"(depth {at['depth']}) every such path out of each bifurcation reached, R^B and R^C among them. "
             f"{at['nodes']} nodes ({kinds}), {at['edges']} directed paths (ending at: {events}); "
             f"{at['seconds']:.1f} s. A node's kind comes from the analysis at its point, not from how the "
             "path got there: a point that is not a bifurcation is never listed as one. "
             + (f"{at['identity']} " if at.get("identity") else "")
             + (f"{relaxed} of the bifurcations were located only to a coarser v_r ('located only to' in the "
                "node table), so their m and s are counted at ten times that rank tolerance and points reached "
                "along different paths are one node when they agree to 10 sqrt(tolerance) x the model size; "
                f"{_relaxed_words(mp['nodes'])} Whether they are true bifurcations or near-misses is not "
                "settled here. " if relaxed else "")
             + "A prime marks the image of a node under the mirror z -> -z. Path lengths in a:\n")
    L.append("| from | to | ends at | directed paths | path lengths (a) |")
    L.append("|---|---|---|---|---|")
    edges = mp["edges"]
    done = set()
    for i, e in enumerate(edges):
        if i in done:
            continue
        to = e["to"]
        both = False
        # a path and its mirror image: one row
        for j in range(i + 1, len(edges)):
            f = edges[j]
            if (j not in done and f["from"] == e["from"] and f["l"] == e["l"] and f["paths"] == e["paths"]
                    and f["event"] == e["event"] and f["to"] != e["to"]
                    and f["to"].rstrip("'") == e["to"].rstrip("'")):
                to = f"{e['to']} and {f['to']} (mirror)"
                both = True
                done.add(j)
                break
        L.append(f"| {e['from']} | {to} | {_EVENT_WORDS.get(e['event'], e['event'])} | "
                 f"{e['paths']}{' each' if both else ''} | {', '.join(f'{v:.4f}' for v in e['l'])} |")
    L.append("\n| node | kind | m / s | x-y extent (a) | height (a) | symmetric branches out |")
    L.append("|---|---|---|---|---|---|")
    rows = {}
    for n in mp["nodes"]:
        base = n["name"].rstrip("'")
        rows.setdefault(base, []).append(n)
    for base, ns in rows.items():
        n = ns[0]
        out = n["symmetric_branches"]
        if n["kind"] != "bifurcation":
            out = f"none: not a bifurcation ({n['status']})"
        elif out is None:
            out = "not expanded (depth reached)"
        else:
            out = f"{2 * out} directed" if out else f"none ({n['status']})"
        L.append(f"| {', '.join(x['name'] for x in ns)} | {_kind_word(n)} | {n['m']} / {n['s']} | "
                 f"{n['xy_extent']:.4f} | {n['height']:.4f} | {out} |")
    if "RC" in res and "onward" in res["RC"]:
        rc = res["RC"]
        ends = ", ".join(f"{o['to']} (l = {o['l']:.4f} a)" if o["to"] else "none" for o in rc["onward"])
        ext = f" (R^C's x-y extent: {rc['xy_extent']:.4f} a)" if "xy_extent" in rc else ""
        verdict = ("every one of them ends at a less compact state" if rc.get("onward_less_compact") else
                   "at least one ends at a state at least as compact") + ext
        more = rc.get("more_compact", [])
        if more:
            least = [m["name"] for m in more if m["xy_extent"] <= more[0]["xy_extent"] + 1e-9]
            verdict += (f". Yet R^C is not the most compact symmetric state mapped: {len(more)} nodes of the table "
                        f"are more compact, the most compact {', '.join(least)} at {more[0]['xy_extent']:.4f} a")
        elif "more_compact" in rc:
            verdict += ", and no node of the table is more compact: R^C is the most compact symmetric state mapped"
        L.append(f"\n**Onward from R^C.** Its symmetric directed paths lead to {ends}: {verdict}.\n")
    elif "RC" in res and "map" in res["RC"]:
        L.append(f"\n**Onward from R^C.** R^C is {res['RC']['map']} (`libkin study --map-depth` "
                 f"{at['depth'] + 1} maps them).\n")
    return L


def square(res, a, br, out):
    plt = pyplot()
    ok = [(i, p) for i, p in enumerate(br.paths) if p.exists and p.tangent_ok]
    cols = 8
    rows = max(1, (len(ok) + cols - 1) // cols)
    fig, axs = plt.subplots(rows, cols, figsize=(2.2 * cols, 2.3 * rows), squeeze=False)
    # red: the paths that reach the compact state (same m, s as the flat one)
    folded = {f["path"] for f in res["fully_folded_paths"] if f.get("m") == res["flat"]["m"]}
    for k, ax in enumerate(axs.flat):
        if k >= len(ok):
            ax.axis("off")
            continue
        i, p = ok[k]
        draw(p.final_coords, a.bars, ax=ax, plane="xy", fixed=a.fixed.all(axis=1),
             color="C3" if i in folded else "C0", title=f"path {i} ({'+' if p.sign > 0 else '-'}b{p.beta})")
        ax.set_xlim(-1.8, 1.8)
        ax.set_ylim(-1.8, 1.8)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_xlabel("")
        ax.set_ylabel("")
    fig.suptitle("Figure 11-like: x-y projections at l = 1.75 a of every path out of the flat state "
                 "(red: to the fully folded state; black triangles: pinned V0, V2; lengths in hub sides a)")
    fig.tight_layout()
    from libkin.plot.draw3d import save_small
    save_small(fig, out / "fig11_paths.png", 80)
    plt.close(fig)
    acc = res["accounting"]
    L = ["# Square-hub solar sail: every path out of the flat state\n",
         "Lengths in units of the hub side a (the model has a = 1): hub vertices V0..V3 at (+-a/2, +-a/2), "
         "outer nodes O0..O3 at distance a from them along the folds; V0 and V2 pinned.\n",
         f"Flat state: m = {res['flat']['m']} internal + {res['flat']['m_rigid']} rigid mechanisms, "
         f"s = {res['flat']['s']}.\n",
         f"Complete solver: {acc['paths']} homotopy paths, {acc['real']} real ({acc['real_distinct']} distinct), "
         f"{acc['nonreal']} complex, {acc['singular']} singular, {acc['failed']} failed. "
         f"The paper's root scan found 15 of the 16.\n",
         f"{res['directed_paths_ok']} directed paths (both signs of each solution) reach l = 1.75 with the "
         f"right tangent; {res['distinct_paths']} are distinct.\n",
         "## Paths to the fully folded state\n"]
    L.append("Criterion: the path keeps the two-fold symmetry (rotation by 180 degrees about z, which maps the "
             "supports V0, V2 onto each other) and moves V1, V3 to one side and O0, O2 to the other; each such "
             "path is followed on until the next bifurcation.\n")
    L.append("| path | pattern | next bifurcation at l | m / s there | z of V0..V3, O0..O3 there | hub fold |")
    L.append("|---|---|---|---|---|---|")
    for f in res["fully_folded_paths"]:
        if "m" in f:
            L.append(f"| {f['path']} | {f['pattern']} | {f['ends_at_l']:.4f} | {f['m']} / {f['s']} | "
                     f"{', '.join(f'{v:.3f}' for v in f['end_z'])} | {f['hub_fold_deg']:.1f} deg |")
        else:
            L.append(f"| {f['path']} | {f['pattern']} | not reached | | | |")
    L.append("\nBoth directions of travel reach the compact state in which the hub is folded by 90 degrees "
             "about its diagonal V0-V2 (V1, V3 at z = -+0.707) and the sail is stacked: two distinct paths lead "
             "to it and two to its mirror image. The paper reports one path (its path 12: nodes 2, 4 = V1, V3 "
             "down, 5, 7 = O0, O2 up) and the mirror that its scan missed; the complete solver finds both of "
             "those and a second pair.\n")
    L.append("## Symmetry relations between paths\n")
    if res["symmetry_relations"]:
        for r in res["symmetry_relations"]:
            L.append(f"- path {r['other']} = {r['by']}(path {r['path']})")
    else:
        L.append("none found")
    L.append("\n![paths](fig11_paths.png)\n")
    L.append("*Every directed path out of the flat state, drawn from above at path length 1.75 a: 'path i "
             "(+bk)' is second-order solution k followed in the + sense; red: the paths that go on to the "
             "compact state with the hub folded 90 degrees.*\n")
    write_text(out / "report.md", "\n".join(L))
