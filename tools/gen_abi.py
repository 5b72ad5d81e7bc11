#!/usr/bin/env python3
"""Generate the ABI lists of libkin's size-prefixed structs from the headers.

The public headers are the one source of truth (docs/abi.md). An extensible
struct is a `typedef struct kin_X {...} kin_X;` in include/libkin/*.h whose
first member is `size_t size`, unless a `#define KIN_X_SIZE` fixes its size
(a record format such as kin_homotopy_endpoint). Inside such a struct a
comment line starting `/* layout N` (N = 2, 3, ...) marks where the fields
appended for layout N begin; the fields before the first marker are layout 1,
the first size-prefixed layout. Every layout ever published stays accepted.

A field that a published header had inside an older layout's tail padding
(TAIL_PADDING below) belongs to that layout too: a host of that header
passes the older layout's size with the field's value in those bytes, so the
library reads and writes it there (the size cannot tell the two headers
apart; the field's own range check refuses padding garbage).

Written from that:
  libkin/model/abi_layouts.h  each older layout as a struct (what a host
                              compiled against it has), the layout table the
                              library checks sizes with (model/abi.c), and
                              compile-time checks: every layout a prefix of
                              the next and sizeof strictly increasing (an
                              appended field that fits in the tail padding
                              would make two layouts the same size);
  abi/libkin.suppr            abidiff may accept only members appended at
                              the end of exactly these structs;
  docs/abi.md                 the list of structs and layouts between the
                              `gen_abi` markers.

usage: python3 tools/gen_abi.py [--check]   (--check: exit 1 on drift)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
INCLUDE = ROOT / "include"
OUT_H = ROOT / "libkin" / "model" / "abi_layouts.h"
OUT_SUPPR = ROOT / "abi" / "libkin.suppr"
DOC = ROOT / "docs" / "abi.md"
DOC_BEGIN = "<!-- gen_abi: begin (tools/gen_abi.py writes this list from the headers) -->"
DOC_END = "<!-- gen_abi: end -->"
MARKER = re.compile(r"/\*\s*layout\s+(\d+)\b")
# {struct: {layout: [fields of the next layout that published headers had in
# this layout's tail padding]}}. kin_options.step_control: the 0.3.0 headers
# of 2026-11-23 to 2026-11-26 (commits 117529c..c185a3e) appended it after
# factorization, where it fits in layout 1's 4 bytes of tail padding
# (sizeof 72 either way); layout 2 (80 bytes) was made larger only later.
# Such a host passes size 72 with step_control set (docs/abi.md).
TAIL_PADDING = {"kin_options": {1: ["step_control"]}}


def _strip_comments(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def _fields(segment):
    """Declarations of a piece of a struct body: [(decl text, [names])]."""
    out = []
    for decl in _strip_comments(segment).split(";"):
        decl = " ".join(decl.split())
        if not decl:
            continue
        m = re.match(r"^(.*?[\s*])(\w+(?:\s*,\s*\**\s*\w+)*)$", decl)
        if not m:
            raise SystemExit(f"gen_abi: cannot parse member declaration {decl!r}")
        names = [n.strip(" *") for n in m.group(2).split(",")]
        out.append((decl, names))
    return out


def structs(include=INCLUDE):
    """[(header, name, [layout fields: [(decl, names)]])] in the order of the
    umbrella header include/libkin.h ([] if include has none)."""
    include = pathlib.Path(include)
    if not (include / "libkin.h").is_file():
        return []
    umbrella = (include / "libkin.h").read_text()
    headers = re.findall(r'#include "(libkin/[\w.]+)"', umbrella)
    texts = {h: (include / h).read_text() for h in headers}
    fixed = set()
    for raw in texts.values():
        fixed.update(m.lower() for m in re.findall(r"#define (KIN_\w+)_SIZE\b", raw))
    found = []
    for h in headers:
        for m in re.finditer(r"typedef struct (kin_\w+)\s*\{(.*?)\}\s*(kin_\w+)\s*;", texts[h], flags=re.S):
            name, body = m.group(1), m.group(2)
            first = _fields(body)[:1]
            if not first or first[0][0] != "size_t size" or name in fixed:
                continue
            cuts = [(0, 1)] + [(mk.start(), int(mk.group(1))) for mk in MARKER.finditer(body)]
            layouts = []
            for i, (start, num) in enumerate(cuts):
                if num != i + 1:
                    raise SystemExit(f"gen_abi: {name}: layout markers must be 2, 3, ... in order")
                end = cuts[i + 1][0] if i + 1 < len(cuts) else len(body)
                fields = _fields(body[start:end])
                if not fields:
                    raise SystemExit(f"gen_abi: {name}: layout {num} has no fields")
                layouts.append(fields)
            for k, moved in TAIL_PADDING.get(name, {}).items():
                later = layouts[k]
                if [ns for _, ns in later[:len(moved)]] != [[n] for n in moved]:
                    raise SystemExit(f"gen_abi: {name}: TAIL_PADDING {moved} must open layout {k + 1}")
                layouts[k - 1] = layouts[k - 1] + later[:len(moved)]
                layouts[k] = later[len(moved):]
                if not layouts[k]:
                    raise SystemExit(f"gen_abi: {name}: layout {k + 1} has no fields beyond TAIL_PADDING")
            found.append((h, name, layouts))
    return found


def _padded(name, k):
    """The fields layout k of name has in its tail padding ([] mostly)."""
    return TAIL_PADDING.get(name, {}).get(k, [])


def _layout_type(name, k, layouts):
    return name if k == len(layouts) else f"struct kin__{name}_{k}"


def gen_header(found):
    L = ['/* Generated by tools/gen_abi.py from the headers in include/libkin: do not edit.',
         ' * The published layouts of the size-prefixed structs (docs/abi.md). */',
         "#ifndef KIN_MODEL_ABI_LAYOUTS_H", "#define KIN_MODEL_ABI_LAYOUTS_H", "",
         "#include <stddef.h>", "", '#include "libkin.h"', ""]
    for _, name, layouts in found:
        acc = []
        for k, fields in enumerate(layouts[:-1], start=1):
            acc += fields
            L.append(f"/* {name} as a host compiled against layout {k} has it */")
            L.append(f"struct kin__{name}_{k} {{")
            L += [f"    {d};" for d, _ in acc]
            L.append("};")
            pad = _padded(name, k)
            if pad:
                L.append(f"/* the same without what published headers put in its tail padding ({', '.join(pad)}) */")
                L.append(f"struct kin__{name}_{k}_unpadded {{")
                L += [f"    {d};" for d, ns in acc if ns[0] not in pad]
                L.append("};")
    L.append("")
    L.append("/* each struct as a host compiled against its first layout has it */")
    for _, name, layouts in found:
        first = f"struct kin__{name}_1" if len(layouts) > 1 else name
        L.append(f"typedef {first} kin__{name}_layout1;")
    L.append("")
    L.append("/* the structs, in header order */")
    L.append("enum kin__abi_id {")
    L += [f"    KIN__ABI_ID_{name}," for _, name, _ in found]
    L.append("    KIN__ABI_NTYPES")
    L.append("};")
    L.append(f"#define KIN__ABI_MAX_LAYOUTS {max(len(l) for _, _, l in found)}")
    L.append("")
    L.append("/* {name, layouts, {sizeof each layout}, {where its fields end}}, oldest first;")
    L.append(" * the last layout is the struct of today's header */")
    L.append("#define KIN__ABI_TABLE \\")
    rows = []
    for _, name, layouts in found:
        sizes, ends = [], []
        for k, fields in enumerate(layouts[:-1], start=1):
            last = fields[-1][1][-1]
            sizes.append(f"sizeof(struct kin__{name}_{k})")
            ends.append(f"offsetof(struct kin__{name}_{k}, {last}) + sizeof(((struct kin__{name}_{k} *)0)->{last})")
        sizes.append(f"sizeof({name})")
        ends.append(f"sizeof({name})")
        rows.append(f'    {{"{name}", {len(layouts)}, {{{", ".join(sizes)}}}, {{{", ".join(ends)}}}}}')
    L.append(", \\\n".join(rows))
    L.append("")
    L.append("/* compile-time checks (C99: a negative array size is an error). Each older")
    L.append(" * layout is a prefix of the next, and each layout's sizeof is larger than")
    L.append(" * the one before: if it is not, fields appended to a layout fit in the")
    L.append(" * previous one's tail padding and a host's size could not tell the two")
    L.append(" * apart; then append a member (e.g. `int reserved;`) to the new layout. */")
    for _, name, layouts in found:
        acc = []
        for k, fields in enumerate(layouts[:-1], start=1):
            acc += fields
            nxt = f"struct kin__{name}_{k + 1}" if k + 1 < len(layouts) else name
            cur = f"struct kin__{name}_{k}"
            L.append(f"typedef char kin__abi_grows_{name}_{k}[sizeof({cur}) < sizeof({nxt}) ? 1 : -1];")
            if _padded(name, k):
                L.append(f"typedef char kin__abi_padding_{name}_{k}"
                         f"[sizeof({cur}) == sizeof({cur}_unpadded) ? 1 : -1];")
            for _, names in acc:
                for n in names:
                    L.append(f"typedef char kin__abi_prefix_{name}_{k}_{n}"
                             f"[offsetof({cur}, {n}) == offsetof({nxt}, {n}) ? 1 : -1];")
    L.append("")
    L.append("/* every field of every layout: X(struct, layout, the layout's type, field),")
    L.append(" * per struct and all together; the old-host test sets each through its")
    L.append(" * layout (tests/test_abi_fields.c) */")
    for _, name, layouts in found:
        acc, xs = [], []
        for k, fields in enumerate(layouts, start=1):
            acc += fields
            xs += [f"    X({name}, {k}, {_layout_type(name, k, layouts)}, {n})"
                   for _, ns in acc for n in ns if n != "size"]
        L.append(f"#define KIN__ABI_FIELDS_{name}(X) \\")
        L.append(" \\\n".join(xs))
    L.append("#define KIN__ABI_FIELDS(X) \\")
    L.append(" \\\n".join(f"    KIN__ABI_FIELDS_{name}(X)" for _, name, _ in found))
    L += ["", "#endif /* KIN_MODEL_ABI_LAYOUTS_H */", ""]
    return "\n".join(L)


def gen_suppr(found):
    names = "|".join(name[len("kin_"):] for _, name, _ in found)
    return (
        "# Generated by tools/gen_abi.py from the headers in include/libkin: do not edit.\n"
        "# Changes tools/abi_check.sh does not count as ABI breaks (docs/abi.md):\n"
        "# these public structs start with `size_t size` and the library reads and\n"
        "# writes only the fields of the layout that size names (libkin/model/abi.c),\n"
        "# so a member appended at the end keeps older callers working. Any other\n"
        "# change to them (a member removed, reordered, inserted or retyped) still\n"
        "# counts.\n"
        "[suppress_type]\n"
        "  type_kind = struct\n"
        f"  name_regexp = ^kin_({names})$\n"
        "  has_data_member_inserted_at = end\n"
        "  has_size_change = yes\n"
    )


def gen_doc_list(found):
    L = [DOC_BEGIN, "", "| struct | header | layout 1 ends at | appended in later layouts |",
         "| --- | --- | --- | --- |"]
    for h, name, layouts in found:
        later = "; ".join(f"{k}: " + ", ".join(f"`{n}`" for _, ns in fields for n in ns)
                          for k, fields in enumerate(layouts[1:], start=2)) or "-"
        pad = _padded(name, 1)
        end = f"`{layouts[0][-1][1][-1]}`"
        if pad:
            end = f"`{layouts[0][-1 - len(pad)][1][-1]}` (+ " + ", ".join(f"`{n}`" for n in pad) + " in its tail padding)"
        L.append(f"| `{name}` | `include/{h}` | {end} | {later} |")
    L += ["", DOC_END]
    return "\n".join(L)


def gen_doc(found):
    text = DOC.read_text()
    i, j = text.find(DOC_BEGIN), text.find(DOC_END)
    if i < 0 or j < 0:
        raise SystemExit(f"gen_abi: {DOC} has no gen_abi markers")
    return text[:i] + gen_doc_list(found) + text[j + len(DOC_END):]


def main(argv):
    found = structs()
    outputs = {OUT_H: gen_header(found), OUT_SUPPR: gen_suppr(found), DOC: gen_doc(found)}
    if "--check" in argv:
        stale = [p for p, s in outputs.items() if not p.exists() or p.read_text() != s]
        for p in stale:
            print(f"{p.relative_to(ROOT)} is out of date: run python3 tools/gen_abi.py", file=sys.stderr)
        return 1 if stale else 0
    for p, s in outputs.items():
        if not p.exists() or p.read_text() != s:
            p.write_text(s)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
