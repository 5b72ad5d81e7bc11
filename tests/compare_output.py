"""Run an example and compare its output with the expected output stored
beside it: the words must match exactly; numbers within a relative tolerance
(or an absolute one for values at rounding level, e.g. strains of 1e-13).

usage: compare_output.py EXPECTED_FILE COMMAND [ARGS...]"""
import re
import subprocess
import sys

NUM = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
REL_TOL = 1e-6   # printed digits of path data
ABS_TOL = 1e-11  # rounding-level values (strains ~1e-13, zeros printed as -0.000000)


def split(text):
    return NUM.sub("#", text), [float(x) for x in NUM.findall(text)]


def main():
    expected = open(sys.argv[1]).read()
    got = subprocess.run(sys.argv[2:], capture_output=True, text=True, check=True).stdout
    ew, en = split(expected)
    gw, gn = split(got)
    bad = []
    if ew.replace("-#", "#") != gw.replace("-#", "#"):
        bad.append("the text differs:\n" + got)
    elif len(en) != len(gn):
        bad.append("number count differs")
    else:
        for i, (e, g) in enumerate(zip(en, gn)):
            if abs(e - g) > max(ABS_TOL, REL_TOL * abs(e)):
                bad.append(f"number {i}: expected {e!r}, got {g!r}")
    if bad:
        print("\n".join(bad[:20]))
        return 1
    print(f"{sys.argv[2]}: output matches {sys.argv[1]} ({len(en)} numbers)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
