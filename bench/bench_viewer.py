"""Benchmark: how fast atlas.html opens in Chromium, up to the hexagonal
sail's 23,359 nodes.

  python bench/bench_viewer.py [--atlas examples/atlas/square_sail/atlas.json]
                               [--nodes 1000,5000,23359] [--repeat 3] [--samples keep|drop]
                               [--shots DIR] [--select-edge K]

For each size, a synthetic atlas is made from the real one (python/tests/
atlas_synthetic.py: its nodes and paths copied under new ids, with their
configurations and samples; --samples drop leaves the samples out, as in the
depth-one benchmark's atlas, bench_atlas_flat.py, which records none), its
page is written (libkin.atlas.html) and opened --repeat times in headless
Chromium (a fresh profile each time). Printed per size: the page's size, the
time to write it, and in the browser (Navigation Timing, milliseconds after
navigation start) when the map was drawn (the page's own mark,
body[data-load-ms]: plotly.js and the viewer have run and the first frame
with the map is on its way) and when the load event ended (the first
frame painted); medians of the runs, and their ratio to the smallest page.

Not a test (the browser test is python/tests/test_viewer_browser.py): the
times depend on the machine and its load (printed), and on the renderer
(here SwiftShader, WebGL on the CPU; a GPU draws the map much faster).
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import shutil
import statistics
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "tests"))

from atlas_synthetic import replicate  # noqa: E402
from test_viewer_browser import CHROMIUM, new_driver  # noqa: E402

from libkin.atlas import Atlas, html  # noqa: E402


def open_page(page: pathlib.Path, shot: "pathlib.Path | None", edge: int = -1) -> dict:
    d = new_driver()
    try:
        d.set_page_load_timeout(300)
        d.get(page.as_uri())
        while d.execute_script("return document.body.dataset.ready") != "1":
            time.sleep(0.05)
        r = d.execute_script("const t = performance.timing, b = document.body.dataset; return {drawn: +b.loadMs,"
                             " load: t.loadEventEnd - t.navigationStart, parsed: t.domInteractive - t.navigationStart,"
                             " nodes: +b.nodesDrawn}")
        r["errors"] = [e["message"] for e in d.get_log("browser") if e["level"] == "SEVERE"]
        if shot is not None:
            if edge >= 0:  # the path's animation under way, its source's list of paths beside it
                d.execute_script("libkinViewer.selectEdge(arguments[0])", edge)
                time.sleep(1.5)  # then halfway along it, paused (the slider)
                d.execute_script("const p = document.getElementById('a-pos'); p.value = 500;"
                                 "p.dispatchEvent(new Event('input'));")
                time.sleep(0.5)
            shot.parent.mkdir(parents=True, exist_ok=True)
            d.save_screenshot(str(shot))
        return r
    finally:
        d.quit()
        shutil.rmtree(d.libkin_profile, ignore_errors=True)


def main() -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--atlas", default=str(ROOT / "examples" / "atlas" / "square_sail" / "atlas.json"))
    ap.add_argument("--nodes", default="1000,5000,23359")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--samples", choices=["keep", "drop"], default="keep")
    ap.add_argument("--shots", default=None, help="folder for a screenshot of each page")
    ap.add_argument("--select-edge", type=int, default=-1, help="the path to animate in the screenshots")
    a = ap.parse_args()
    base = Atlas.from_dict(json.loads(pathlib.Path(a.atlas).read_text()))
    if a.samples == "drop":
        for e in base.edges:
            e.samples = []
    print(f"base atlas: {a.atlas} ({len(base.nodes)} nodes, {len(base.edges)} paths); samples {a.samples}; "
          f"load average at the start {os.getloadavg()[0]:.2f}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(x) for x in a.nodes.split(",")]:
            at = replicate(base, n)
            page = pathlib.Path(tmp) / f"atlas_{n}.html"
            t = time.perf_counter()
            html.write(at, page)
            t_write = time.perf_counter() - t
            runs = []
            for k in range(a.repeat):
                shot = pathlib.Path(a.shots) / f"viewer_{n}.png" if a.shots and k == 0 else None
                runs.append(open_page(page, shot, a.select_edge))
            assert all(r["nodes"] == n and not r["errors"] for r in runs), runs
            rows.append((n, len(at.edges), page.stat().st_size / 1e6, t_write,
                         statistics.median(r["drawn"] for r in runs), statistics.median(r["load"] for r in runs)))
    print(f"load average at the end {os.getloadavg()[0]:.2f}; Chromium {CHROMIUM}, WebGL on SwiftShader\n")
    print("| nodes | paths | page MB | write s | map drawn s | load event s | drawn / smallest | load / smallest |")
    print("|---|---|---|---|---|---|---|---|")
    for n, ne, mb, tw, dr, ld in rows:
        print(f"| {n:,} | {ne:,} | {mb:.1f} | {tw:.2f} | {dr / 1e3:.2f} | {ld / 1e3:.2f} | "
              f"{dr / rows[0][4]:.2f} | {ld / rows[0][5]:.2f} |")


if __name__ == "__main__":
    main()
