#!/usr/bin/env python3
"""The shared library exports the public API and nothing else (docs/abi.md).

Fails when a defined dynamic symbol of LIB is not `kin_` followed by a letter
or digit (kin__* internals, the ifunc resolvers of target_clones kernels,
anything else), or when a KIN_API function of the headers is not exported.

usage: check_exports.py LIB INCLUDE_DIR     (ctest: exports)
"""
import pathlib
import re
import subprocess
import sys

API = re.compile(r"\bKIN_API\b[^;{]*?\b(kin_\w+)\s*\(", re.S)
PUBLIC = re.compile(r"^kin_[a-z0-9]\w*$")


def main(argv):
    lib, include = argv[1], pathlib.Path(argv[2])
    out = subprocess.run(["nm", "-D", "--defined-only", lib], check=True, capture_output=True, text=True).stdout
    exported = {line.split()[-1].split("@")[0] for line in out.splitlines() if line.strip()}
    api = set()
    for h in sorted(include.glob("libkin/*.h")):
        api.update(API.findall(re.sub(r"/\*.*?\*/", " ", h.read_text(), flags=re.S)))
    extra = sorted(s for s in exported if not PUBLIC.match(s))
    missing = sorted(api - exported)
    for s in extra:
        print(f"check_exports: {lib} exports {s}: not public API (kin_ and a letter)")
    for s in missing:
        print(f"check_exports: {lib} does not export {s} (KIN_API in the headers)")
    if extra or missing:
        return 1
    print(f"check_exports: OK: {len(exported)} symbols exported, the {len(api)} KIN_API functions among them")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
