#!/usr/bin/env python3
"""Compare the public struct layouts of two abidw dumps (tools/abi_check.sh).

libabigail 2.2's abidiff misses struct layout changes when one side is an
XML dump: two swapped members of kin_step_info went unreported between the
stored baseline and a rebuilt libkin.so (binary against binary it sees
them), and a has_data_member_inserted_at = end suppression would accept a
swap anyway. So the layouts are compared here, member by member, from two
dumps made by the same abidw with the same options.

For every struct named kin_* of the baseline that the current dump still
has: each baseline member must be at the same position with the same name,
offset and type; members may be added only after the last one and only to
the size-prefixed structs that the suppression file lists (generated from
the headers by tools/gen_abi.py); the size may change only for those. And where the headers (INCLUDE_DIR, the
folder holding libkin.h; optional) say how a size-prefixed struct's layouts
end (the `/* layout N` markers, tools/gen_abi.py), the baseline's last member
must end one of them: members appended to a layout the baseline has would
change that layout's size, and hosts compiled against it would be refused.

usage: abi_layouts_diff.py BASELINE.abi CURRENT.abi SUPPRESSIONS [INCLUDE_DIR]
exit 0 compatible, 1 a layout changed incompatibly (listed), 2 usage/parse error
"""
import pathlib
import re
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import gen_abi  # noqa: E402


def layouts(path):
    """{struct name: (size in bits, [(offset, member name, type id)])}."""
    out = {}
    for cls in ET.parse(path).getroot().iter("class-decl"):
        name = cls.get("name", "")
        if not name.startswith("kin_") or cls.get("is-declaration-only") == "yes":
            continue
        members = []
        for dm in cls.findall("data-member"):
            var = dm.find("var-decl")
            members.append((int(dm.get("layout-offset-in-bits", "-1")), var.get("name"), var.get("type-id")))
        entry = (int(cls.get("size-in-bits", "0")), members)
        if name in out and out[name] != entry:
            raise SystemExit(f"abi_layouts_diff: {path}: two different definitions of {name}")
        out[name] = entry
    return out


def extensible(suppr_path):
    text = open(suppr_path).read()
    m = re.search(r"name_regexp\s*=\s*\^kin_\(([^)]*)\)\$", text)
    return {"kin_" + n for n in m.group(1).split("|")} if m else set()


def main(argv):
    if len(argv) not in (4, 5):
        print(__doc__, file=sys.stderr)
        return 2
    old, new, ext = layouts(argv[1]), layouts(argv[2]), extensible(argv[3])
    ends = {}
    if len(argv) == 5:
        for _, name, lays in gen_abi.structs(argv[4]):
            ends[name] = [fields[-1][1][-1] for fields in lays]
    problems = []
    for name in sorted(old):
        if name not in new:
            continue  # no exported function uses it any more: not ABI (removed functions are abidiff's)
        (osize, om), (nsize, nm) = old[name], new[name]
        for i, (off, mem, tid) in enumerate(om):
            if i >= len(nm):
                problems.append(f"{name}: member '{mem}' removed")
            elif nm[i] != (off, mem, tid):
                noff, nmem, ntid = nm[i]
                what = []
                if nmem != mem:
                    what.append(f"now '{nmem}'")
                if noff != off:
                    what.append(f"offset {off} -> {noff} bits")
                if ntid != tid:
                    what.append("type changed")
                problems.append(f"{name}: member {i} '{mem}' at {off} bits: {', '.join(what)}")
        added = nm[len(om):]
        if added and name not in ext:
            problems.append(f"{name}: members appended ({', '.join(m for _, m, _ in added)}), but {name} "
                            "carries no layout size (only the size-prefixed structs may grow)")
        if added and name in ends and om and om[-1][1] not in ends[name]:
            problems.append(f"{name}: members appended to a layout the baseline has (it ends at '{om[-1][1]}'; "
                            f"layouts end at {', '.join(ends[name])}): start a new layout with a "
                            "`/* layout N` comment line before them (docs/abi.md)")
        if nsize != osize and name not in ext:
            problems.append(f"{name}: size {osize} -> {nsize} bits")
        elif nsize < osize:
            problems.append(f"{name}: size {osize} -> {nsize} bits (shrank)")
    for p in problems:
        print(f"abi_layouts_diff: {p}")
    if problems:
        return 1
    print(f"abi_layouts_diff: OK: {len([n for n in old if n in new])} public struct layouts compatible")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
