"""atlas.html in a real browser: Debian's Chromium, headless, driven by
selenium through chromedriver (tools/deps.sh installs both).

The page loads from a file with no console error; the map draws as many
nodes as the atlas has (the page's own count of the points in its node
traces, body[data-nodes-drawn]); a mouse click on a node draws its
configuration in 3D, which a drag rotates; a click on a path's marker
animates the structure along it; the filters narrow what is drawn. The
23,359-node page (the hexagonal sail's depth-one atlas has that many nodes;
here a synthetic load, atlas_synthetic.py, without samples as the real one)
draws every node. Its load time
is printed (no timed assertion: bench/bench_viewer.py measures it).
Screenshots go to $LIBKIN_VIEWER_SHOTS or a temporary folder (printed).

Skipped, saying why, where Chromium, chromedriver or selenium is missing.
"""
import json
import os
import pathlib
import shutil
import sys
import tempfile
import time

import numpy as np
import pytest

from libkin.atlas import Atlas, html as atlas_html

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from atlas_synthetic import replicate  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SQUARE = ROOT / "examples" / "atlas" / "square_sail" / "atlas.json"
CHROMIUM = os.environ.get("LIBKIN_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("LIBKIN_CHROMEDRIVER", "/usr/bin/chromedriver")
# this machine's network is closed: without these Chromium waits on connections;
# WebGL (the map, the 3D view) runs on SwiftShader, the CPU renderer
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=1500,900"]
BIG = 23359


def _missing():
    for what, path in (("Chromium", CHROMIUM), ("chromedriver", CHROMEDRIVER)):
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            return f"{what} not found at {path} (Debian: apt-get install chromium chromium-driver, or tools/deps.sh)"
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium not installed (pip install selenium; python/requirements-dev.txt)"
    try:
        import plotly  # noqa: F401
    except ImportError:
        return "plotly not installed (pip install plotly): the page carries its plotly.js"
    return None


pytestmark = pytest.mark.skipif(_missing() is not None, reason=f"no browser test: {_missing()}")


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    d = pathlib.Path(os.environ.get("LIBKIN_VIEWER_SHOTS") or tmp_path_factory.mktemp("viewer_shots"))
    d.mkdir(parents=True, exist_ok=True)
    print(f"\nviewer screenshots: {d}")
    return d


def new_driver():
    """Headless Chromium through chromedriver, with a fresh profile and the
    browser's console log kept (also bench/bench_viewer.py's)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    profile = tempfile.mkdtemp(prefix="libkin-chromium-")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for f in FLAGS + [f"--user-data-dir={profile}"]:
        opts.add_argument(f)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    d.libkin_profile = profile  # removed by the caller after quit()
    return d


@pytest.fixture(scope="module")
def driver():
    d = new_driver()
    d.set_page_load_timeout(120)
    d.set_script_timeout(60)
    try:
        yield d
    finally:
        d.quit()
        shutil.rmtree(d.libkin_profile, ignore_errors=True)


@pytest.fixture(scope="module")
def square():
    return Atlas.from_dict(json.loads(SQUARE.read_text()))


def _wait(d, script, timeout=60.0):
    t = time.monotonic()
    while time.monotonic() - t < timeout:
        v = d.execute_script(script)
        if v:
            return v
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for: {script}")


def _open(d, page):
    d.get_log("browser")  # drop what an earlier page logged
    d.get(page.as_uri())
    _wait(d, "return document.body.dataset.ready === '1'")
    return d.execute_script("const b = document.body.dataset; return {drawn: +b.nodesDrawn, edges: +b.edgesDrawn, "
                            "ready_ms: +b.loadMs, errors: libkinViewer.errors}")


def _errors(d):
    return [e for e in d.get_log("browser") if e["level"] == "SEVERE"]


def _click(d, x, y):
    from selenium.webdriver.common.actions.action_builder import ActionBuilder
    a = ActionBuilder(d)
    a.pointer_action.move_to_location(int(round(x)), int(round(y)))
    a.perform()
    time.sleep(0.3)  # plotly's hover picks the point under the mouse
    a = ActionBuilder(d)
    a.pointer_action.click()
    a.perform()


def test_click_a_node_then_a_path(driver, square, shots, tmp_path):
    page = tmp_path / "square.html"
    atlas_html.write(square, page)
    got = _open(driver, page)
    assert got["drawn"] == len(square.nodes) and not got["errors"]
    assert got["edges"] == len(square.edges)
    driver.save_screenshot(str(shots / "square_map.png"))
    # a node: its configuration in 3D
    i = next(k for k, n in enumerate(square.nodes) if n.depth == 1)
    _click(driver, *driver.execute_script("return libkinViewer.pixelOfNode(arguments[0])", i))
    _wait(driver, f"return libkinViewer.selectedNode === {i} && document.getElementById('view3d').data "
                  "&& document.getElementById('view3d').data.length === 2")
    view = driver.execute_script("const v = document.getElementById('view3d'); return {types: v.data.map(t => t.type),"
                                 " canvas: v.querySelectorAll('canvas').length, joints: v.data[1].x.length,"
                                 " title: document.body.dataset.view3d}")
    assert view["types"] == ["scatter3d", "scatter3d"] and view["canvas"] >= 1
    assert view["joints"] == square.nodes[i].coords.shape[0] and view["title"] == f"node {square.nodes[i].id}"
    # rotatable: a drag turns the camera
    eye = "return JSON.stringify(document.getElementById('view3d')._fullLayout.scene._scene.getCamera().eye)"
    before = driver.execute_script(eye)
    from selenium.webdriver.common.action_chains import ActionChains
    v3 = driver.find_element("id", "view3d")
    ActionChains(driver).move_to_element(v3).click_and_hold().move_by_offset(80, 30).move_by_offset(40, 10) \
        .release().perform()
    _wait(driver, eye.replace("return ", "return ") + " !== " + json.dumps(before))
    driver.save_screenshot(str(shots / "square_node.png"))
    # a path: the structure moves along it
    e = next(k for k, x in enumerate(square.edges) if x.source != x.target)
    ends = {(square.edges[e].source, square.edges[e].target)}
    _click(driver, *driver.execute_script("return libkinViewer.pixelOfEdge(arguments[0])", e))
    _wait(driver, "return libkinViewer.selectedEdge >= 0 && libkinViewer.frames > 3")
    sel = driver.execute_script("return libkinViewer.selectedEdge")
    pair = (square.edges[sel].source, square.edges[sel].target)
    assert pair in ends or pair[::-1] in ends  # this path or one of its parallels
    assert driver.execute_script("return libkinViewer.animating")
    x0 = driver.execute_script("return document.getElementById('view3d').data[1].x.slice()")
    time.sleep(0.4)
    x1 = driver.execute_script("return document.getElementById('view3d').data[1].x.slice()")
    assert x0 != x1  # moving
    driver.save_screenshot(str(shots / "square_path.png"))
    assert _errors(driver) == []


def test_filters_narrow_the_map(driver, square, tmp_path):
    page = tmp_path / "square.html"
    atlas_html.write(square, page)
    _open(driver, page)
    # m at least 3: the nodes with m >= 3 and the paths between them
    driver.execute_script("const f = document.getElementById('f-m-lo'); f.value = 3;"
                          "f.dispatchEvent(new Event('change', {bubbles: true}));")
    keep = {n.id for n in square.nodes if n.m >= 3}
    want = (len(keep), sum(1 for e in square.edges if e.source in keep and e.target in keep))
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {want[0]}")
    assert driver.execute_script("return +document.body.dataset.edgesDrawn") == want[1]
    # an event kind off
    ev = sorted({e.event for e in square.edges})[0]
    j = driver.execute_script("return libkinViewer && JSON.parse(document.getElementById('libkin-data').textContent)"
                              ".events.indexOf(arguments[0])", ev)
    driver.execute_script(f"document.getElementById('f-reset').click();"
                          f"const c = document.querySelector('[data-event=\"{j}\"]'); c.checked = false;"
                          "c.dispatchEvent(new Event('change', {bubbles: true}));")
    want_e = sum(1 for e in square.edges if e.event != ev)
    _wait(driver, f"return +document.body.dataset.edgesDrawn === {want_e} && "
                  f"+document.body.dataset.nodesDrawn === {len(square.nodes)}")
    # one node per orbit
    driver.execute_script("document.getElementById('f-reset').click(); const c = document.getElementById('f-reps');"
                          "c.checked = true; c.dispatchEvent(new Event('change', {bubbles: true}));")
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {len({n.orbit for n in square.nodes})}")
    # the orbit of a node, by its name
    n = square.nodes[-1]
    driver.execute_script("document.getElementById('f-reset').click(); const c = document.getElementById('f-orbit');"
                          f"c.value = 'N{n.id}'; c.dispatchEvent(new Event('change', {{bubbles: true}}));")
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {sum(1 for x in square.nodes if x.orbit == n.orbit)}")
    assert _errors(driver) == []


def test_the_23359_node_atlas_draws_every_node(driver, square, shots, tmp_path):
    big = replicate(square, BIG)
    page = tmp_path / "big.html"
    t = time.perf_counter()
    # without samples, as the real depth-one atlas (recorded with samples=0);
    # bench/bench_viewer.py times pages with them
    atlas_html.write(big, page, max_sample_values=0)
    t_write = time.perf_counter() - t
    t = time.perf_counter()
    got = _open(driver, page)
    t_open = time.perf_counter() - t
    timing = driver.execute_script("const t = performance.timing; return [t.domInteractive - t.navigationStart,"
                                   " t.loadEventEnd - t.navigationStart]")
    print(f"\n{BIG:,}-node page ({len(big.edges):,} paths, {page.stat().st_size / 1e6:.1f} MB): written in "
          f"{t_write:.1f} s; in Chromium the map is drawn {got['ready_ms'] / 1e3:.1f} s after navigation "
          f"(load event {timing[1] / 1e3:.1f} s; {t_open:.1f} s as selenium sees it; load average "
          f"{os.getloadavg()[0]:.1f})")
    assert got["drawn"] == BIG and got["edges"] == len(big.edges) and not got["errors"]
    driver.save_screenshot(str(shots / "big_map.png"))
    i = BIG - 1
    _click(driver, *driver.execute_script("return libkinViewer.pixelOfNode(arguments[0])", i))
    _wait(driver, "return libkinViewer.selectedNode >= 0 && document.getElementById('view3d').data")
    driver.save_screenshot(str(shots / "big_node.png"))
    assert _errors(driver) == []


def test_a_turn_is_drawn_whole_and_the_shape_filters(driver, shots, tmp_path):
    """The parallelogram four-bar to depth 3 (paths of a whole turn): every
    frame the animation can show lies in the 3D box (fitted to the whole
    curve, not to its keyframes); the nodes carry their names on the map;
    the filters and colours by compactness (x-y extent, height) and by
    contact narrow and colour what is drawn; the header says the depth
    reached and why it stopped there."""
    import libkin
    from test_cli_reports import parallelogram
    a = libkin.Assembly.from_json(parallelogram(tmp_path / "p.json"))
    # the header: the depth reached and the limit that stopped it there
    cut = libkin.explore(a, depth=3, max_nodes=2)
    page = tmp_path / "cut.html"
    atlas_html.write(cut, page)
    got = _open(driver, page)
    assert got["drawn"] == len(cut.nodes) and not got["errors"]
    head = driver.execute_script("return [document.getElementById('summary').textContent,"
                                 " document.getElementById('stopped').textContent]")
    reached = max(n.depth for n in cut.nodes)
    assert reached < 3 and f"reached depth {reached} of 3" in head[0] and "--max-nodes" in head[1]
    # the whole atlas to depth 3: paths of whole turns
    at = libkin.explore(a, depth=3)
    page = tmp_path / "turn.html"
    atlas_html.write(at, page)
    got = _open(driver, page)
    assert got["drawn"] == len(at.nodes) and not got["errors"]
    assert driver.execute_script("return +document.body.dataset.namesDrawn") == len(at.nodes)
    # every frame of every path's animation in its box
    for e, edge in enumerate(at.edges):
        driver.execute_script("libkinViewer.selectEdge(arguments[0])", e)
        _wait(driver, f"return libkinViewer.selectedEdge === {e} && libkinViewer.box")
        box, fr = driver.execute_script("return [libkinViewer.box, Array.from({length: 401}, "
                                        "(_, k) => libkinViewer.frameAt(k / 400))]")
        f = np.asarray(fr).reshape(401, -1, 3)
        lo, hi = np.asarray(box)[:, 0], np.asarray(box)[:, 1]
        assert (f >= lo).all() and (f <= hi).all(), (e, edge.length)
    driver.save_screenshot(str(shots / "turn_path.png"))
    assert _errors(driver) == []


def test_filter_and_colour_by_shape_and_contact(driver, square, shots, tmp_path):
    """The square sail: the filters and colours by compactness (x-y extent,
    height) and by contact narrow and colour what is drawn (the page's own
    values: atlas_html.shape; its folded states touch, its flat state not)."""
    at = square
    page = tmp_path / "square.html"
    atlas_html.write(at, page)
    _open(driver, page)
    sh = atlas_html.shape(at)
    want_contact = sum(1 for c in sh["contact"] if c)
    assert 0 < want_contact < len(at.nodes)

    def set_value(el, v):
        driver.execute_script(f"const c = document.getElementById('{el}'); c.value = arguments[0];"
                              "c.dispatchEvent(new Event('change', {bubbles: true}));", v)
    set_value("f-contact", "contact")
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {want_contact}")
    set_value("f-contact", "clear")
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {len(at.nodes) - want_contact}")
    driver.execute_script("document.getElementById('f-reset').click()")
    cut = float(np.median(sh["xy_extent"]))
    set_value("f-xy-lo", cut + 1e-3)
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {sum(1 for v in sh['xy_extent'] if v > cut + 1e-3)}")
    driver.execute_script("document.getElementById('f-reset').click()")
    set_value("f-h-hi", 1.0)  # flat: the start only
    _wait(driver, f"return +document.body.dataset.nodesDrawn === {sum(1 for v in sh['height'] if v <= 1.0)}")
    driver.execute_script("document.getElementById('f-reset').click()")
    set_value("f-colour", "xy_extent")
    _wait(driver, "return libkinViewer.colourBy === 'xy_extent' && +document.body.dataset.nodesDrawn > 0")
    colours = driver.execute_script("const g = document.getElementById('graph'); return g.data.filter("
                                    "t => t.marker && Array.isArray(t.marker.color) && t.mode.startsWith('markers') "
                                    "&& t.name && !t.name.startsWith('paths')).map(t => t.marker.color)")
    assert sorted(np.concatenate(colours)) == pytest.approx(sorted(sh["xy_extent"]), rel=1e-3)
    driver.save_screenshot(str(shots / "square_xy.png"))
    assert _errors(driver) == []
