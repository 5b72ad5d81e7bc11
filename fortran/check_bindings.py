"""The Fortran module cannot drift from the C headers silently: every KIN_API
function of include/libkin/*.h must have a bind(C) interface in libkin.f90
(and every bind(C) name must still exist in C), and every status code of the
KIN_STATUS_LIST X-macro, every enumerator of a public enum and every
object-like KIN_* macro with a value (KIN_HOMOTOPY_MAX_PATHS, the version)
must be a named constant in the generated libkin_constants.inc.

usage: check_bindings.py INCLUDE_DIR LIBKIN_F90 CONSTANTS_INC"""
import pathlib
import re
import sys

API = re.compile(r"\bKIN_API\b[^;{]*?\b(kin_\w+)\s*\(", re.S)
BIND = re.compile(r"\bbind\s*\(\s*C\s*,\s*name\s*=\s*['\"](\w+)['\"]\s*\)", re.I)
ENUM = re.compile(r"\benum\s+\w+\s*\{([^}]*)\}", re.S)
STATUS = re.compile(r"\bX\(\s*(KIN_\w+)\s*,")
PARAM = re.compile(r"parameter\s*,\s*public\s*::\s*(\w+)\s*=", re.I)
MACRO = re.compile(r"^\s*#\s*define\s+(KIN_\w+)[ \t]+([^\s{].*)$", re.M)
# Fortran names ignore case: these would clash with kin_version_number() and
# kin_version_string(), so the module spells them differently.
RENAMED = {"KIN_VERSION_NUMBER": "KIN_MODULE_VERSION_NUMBER",
           "KIN_VERSION_STRING": "KIN_MODULE_VERSION_STRING"}
NOT_CONSTANTS = {"KIN_API"}


def strip_comments(c):
    return re.sub(r"/\*.*?\*/", " ", c, flags=re.S)


def main():
    include, f90, inc = map(pathlib.Path, sys.argv[1:4])
    headers = sorted(include.glob("libkin/*.h"))
    functions, enumerators = set(), set()
    for h in headers:
        text = strip_comments(h.read_text())
        functions.update(API.findall(text))
        enumerators.update(STATUS.findall(text))
        enumerators.update(RENAMED.get(n, n) for n, _ in MACRO.findall(text)
                           if n not in NOT_CONSTANTS and not n.endswith("_H"))
        for body in ENUM.findall(text):
            enumerators.update(n for n in re.findall(r"\b(KIN_\w+)\b(?!\s*\()", body)
                               if not n.endswith("_"))  # KIN_STATUS_COUNT_: internal
    fortran = re.sub(r"!.*", "", f90.read_text())
    bound = set(BIND.findall(fortran)) - {"strlen"}
    constants = {n.upper() for n in PARAM.findall(inc.read_text())}
    problems = []
    problems += [f"no Fortran binding for {f}" for f in sorted(functions - bound)]
    problems += [f"Fortran binds {f}, which no header declares" for f in sorted(bound - functions)]
    problems += [f"no Fortran constant for {e}" for e in sorted(enumerators - constants)]
    if not functions or not enumerators:
        problems.append(f"found no KIN_API functions or enumerators under {include}")
    if problems:
        print("\n".join(problems))
        return 1
    print(f"check_bindings: {len(functions)} functions of {len(headers)} headers bound, "
          f"{len(enumerators)} enumerators and macros as constants")
    return 0


if __name__ == "__main__":
    sys.exit(main())
