#!/usr/bin/env python3
"""Compare the JSON results of one model run under several BLAS settings
(tools/check_blas_python.sh): the study's summary.json, an explorer's
atlas.json. What a user reads must be the same: every count, label, choice,
node and edge exactly; every number to the digits it is reported with.

  compare_runs.py A.json B.json [C.json ...]   exit 1 on a difference
  compare_runs.py A.md B.md [C.md ...]         the same for a report's text

A report (.md) is compared line by line with its times masked (a number
followed by s, ms or min) and the bifurcation table's work counts masked
("6 (1 forward)": factorizations to locate, which like the JSON's
`factorizations` depend on where a converging iteration crosses its
tolerance), and every other number in it to the same 1e-5 as the JSON's, so
it says the same words, candidates, choice and map.

Left out, with the reason:
- wall and CPU times, load averages (the machine);
- work counts that depend on rounding inside a converging iteration
  (refinement steps, factorizations) while the point they reach agrees;
- which of several parts touching at clearance 0 (within rounding) is named
  as the first contact at zero thickness: a tie at R^B, where the
  membrane's panels meet along whole edges (docs/sail_study.md);
- an edge's `beta`: its second-order solution in the coordinates of its
  node's mechanism basis, which is an SVD's choice (the edge's solution
  number, sign, event, length and target, which are compared, come from the
  physical direction U beta; docs/branches.md); storing U beta instead is
  open (issue 35);
- the path of the run's store (each run has its own folder);
- why an unproven endpoint is unproven (`unproven_nopoint`: Newton did not
  converge to a point to test, or `unproven_refused`: the test refused the
  point): at a double root split by rounding that depends on where the
  converging iteration stops; how many are unproven, and every proven count,
  are compared.
Numbers are compared as |a - b| <= 1e-5 max(1, |a|, |b|): relative above 1,
absolute below, as the reports print lengths and angles to 4-6 digits. So
numbers below 1e-5 are not compared: singular values at rounding level, and
the located v_r of points where several singular values vanish together,
which still differs between kernels (e.g. 2e-11 against 2e-12 of v_max at
one m = 4 node of the study's map; issue 35 item 3, open).
"""
import json
import math
import re
import sys

SKIP = re.compile(r"(seconds|wall|load|cpu|refinement_steps|factorizations|_steps_taken|time)"
                  r"|^/interference/contacts\[0\]/(parts|part_ids)|^/stats/store/path|/unproven_(nopoint|refused)$")


def same(a, b):
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
        return a == b
    if isinstance(a, int) and isinstance(b, int):
        return a == b
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= 1e-5 * max(1.0, abs(a), abs(b))


def walk(a, b, path, out):
    if SKIP.search(path):
        return
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                if not SKIP.search(f"{path}/{k}"):
                    out.append(f"{path}/{k}: only in one run")
                continue
            walk(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} against {len(b)} entries")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out)
    elif isinstance(a, str) and isinstance(b, str) and a != b:
        i = next(k for k in range(min(len(a), len(b)) + 1) if k == min(len(a), len(b)) or a[k] != b[k])
        lo = max(0, i - 30)
        out.append(f"{path}: ...{a[lo:i + 40]}... against ...{b[lo:i + 40]}...")
    elif not same(a, b):
        out.append(f"{path}: {str(a)[:60]} against {str(b)[:60]}")


TIME = re.compile(r"\b[0-9]+(\.[0-9]+)? ?(s|ms|min)\b")
WORK = re.compile(r"\b[0-9]+ \([0-9]+ forward\)")
NUMBER = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")


def report_lines(text):
    """A report as [(words, numbers)] per line: times masked, numbers apart
    (so they are compared as numbers, to the digits printed)."""
    out = []
    for line in text.splitlines():
        line = WORK.sub("<work>", TIME.sub("<time>", line))
        nums = [float(x) if any(c in x for c in ".eE") else int(x) for x in NUMBER.findall(line)]
        out.append({"words": NUMBER.sub("#", line), "numbers": nums})
    return out


def load(p):
    with open(p) as fh:
        return report_lines(fh.read()) if p.endswith(".md") else json.load(fh)


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    runs = [load(p) for p in argv]
    bad = 0
    for p, r in zip(argv[1:], runs[1:]):
        out = []
        walk(runs[0], r, "", out)
        for line in out[:20]:
            print(f"compare_runs: {argv[0]} / {p}: {line}")
        if len(out) > 20:
            print(f"compare_runs: ... {len(out) - 20} more")
        bad += bool(out)
    print(f"compare_runs: {len(argv)} runs, {'all the same' if not bad else f'{bad} differ from the first'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
