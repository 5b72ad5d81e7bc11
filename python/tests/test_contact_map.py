"""The study's path map with contact as an event (issue 23 item 3, `libkin
study --contact`; studies/contactmap.py): every mapped path either ends in a
contact of two parts that share no joint, at a configuration where they
touch, or reaches its next event with every pair of parts apart."""
import json
import subprocess
import sys

import numpy as np
import pytest

from libkin import Assembly
from libkin.studies.contactmap import contact_map, contact_map_md
from libkin.studies.contactstudy import TOUCH, sail_panels
from libkin.studies.sailmap import SailMap, explore_symmetric


@pytest.fixture(scope="module")
def sail61():
    a = Assembly.sail(6, 1)
    smap = SailMap(explore_symmetric(a, 1))
    cm = contact_map(a, smap, 1, 0.0)
    return a, smap, cm


def _membrane(a):
    m = a.clone()
    m.panels = sail_panels(a)
    m.set_thickness(0.0)
    return m


def test_every_path_is_counted_once(sail61):
    a, smap, cm = sail61
    atlas = cm["atlas"]
    assert cm["paths"] == len(atlas.edges) > 0
    assert sum(r["paths"] for r in cm["by_node"]) == cm["paths"]
    for r in cm["by_node"]:
        assert r["contact"] + r["free"] == r["paths"] == sum(r["events"].values())
        assert sum(c["paths"] for c in r["contacts"]) == r["contact"]
    assert cm["free"] + cm["edge_events"].get("contact", 0) == cm["paths"]
    # the start is the path map's start, by name
    assert cm["by_node"][0]["node"] == smap.names()[0]
    json.dumps({k: v for k, v in cm.items() if k != "atlas"})


def test_a_contact_end_touches_and_no_path_passed_one(sail61):
    a, smap, cm = sail61
    atlas, m = cm["atlas"], _membrane(a)
    rms = float(np.sqrt(np.mean(np.asarray(a.rest_lengths) ** 2)))
    cutoff = 64 * np.finfo(float).eps * rms  # contact: clearance at most this (docs/contact.md)
    ends = {n.id: n for n in atlas.nodes}
    n_contact = n_samples = 0
    for e in atlas.edges:
        if e.event == "contact":
            n_contact += 1
            # located along the path to 1e-9 x the RMS bar length; the
            # clearance changes at most sqrt 2 per unit length
            assert m.clearance(ends[e.target].coords).value <= 2 * 1e-9 * rms + cutoff, e.id
        # the configurations recorded along the path, before its end, are
        # all clear of contact: the follow would have stopped at them
        for x in e.samples:
            n_samples += 1
            assert m.clearance(np.asarray(x)).value > cutoff, e.id
    assert n_contact == cm["edge_events"].get("contact", 0) > 0
    assert n_samples > 0
    md = "\n".join(contact_map_md(cm, 999, "contact_map.png"))
    assert f"**{n_contact} end in contact**" in md and "contact_map.png" in md


def test_the_map_without_contact_is_the_plain_map(sail61):
    # a path that is free of contact ends where the plain map's does
    a, smap, cm = sail61
    atlas = cm["atlas"]
    for e in atlas.edges:
        if e.event != "contact":
            t = atlas.nodes[e.target]
            assert smap.node_at(t.coords, t.located_tol) is not None, e.id


def test_the_cli_refuses_bad_contact_options(tmp_path):
    base = [sys.executable, "-m", "libkin", "study", "--quiet", "--quick"]
    for extra in (["--contact", "-0.1"], ["--contact", "1.5"], ["--contact", "0", "--interference"],
                  ["--hub", "4", "--loops", "1", "--contact"]):
        out = tmp_path / "bad"
        p = subprocess.run(base + extra + ["--out", str(out)], capture_output=True, text=True, timeout=120)
        assert p.returncode == 2, (extra, p.returncode, p.stderr)
        assert not out.exists()
