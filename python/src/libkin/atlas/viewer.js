/* libkin atlas viewer: draws the atlas this page carries (written by
   libkin.atlas.html). Uses plotly.js, inlined in the page; loads nothing
   from a network. The map: WebGL markers and lines (scattergl); a node's
   configuration and a path's animation: plotly's scatter3d. */
(function () {
  "use strict";
  const T0 = performance.now();
  const body = document.body;
  const V = { ready: false, selectedNode: -1, selectedEdge: -1, animating: false, frames: 0, errors: [] };
  window.libkinViewer = V;
  window.addEventListener("error", function (ev) { V.errors.push(String(ev.message)); });

  const D = JSON.parse(document.getElementById("libkin-data").textContent);
  const B64C = document.getElementById("libkin-configs").textContent;
  const B64S = document.getElementById("libkin-samples").textContent;
  const nd = D.nodes, ed = D.edges, M = D.model;
  const N = nd.id.length, E = ed.id.length, J = M.joints, DIM = M.dimension;
  V.nodes = N; V.edges = E;

  const STYLE = {  // kind: [symbol, colour]; the colours of the PNG map (atlas/plot.py)
    bifurcation: ["diamond", "#d62728"], regular: ["circle", "#a0a0a0"], near_miss: ["triangle-up", "#ff7f0e"],
    multi_dof: ["square", "#9467bd"], rigid: ["cross", "#333333"], failure: ["x", "#8c564b"],
    undecided: ["triangle-down", "#bcbd22"] };
  const EVENT_COLOUR = { bifurcation: "#d62728", near_miss: "#ff7f0e", loop: "#2ca02c", budget: "#7f7f7f",
    failure: "#8c564b", contact: "#e377c2" };
  const word = (k) => String(k).replace(/_/g, "-");
  const fmt = (v, d) => (v === null || v === undefined) ? "-" : Number(v).toPrecision(d || 4).replace(/\.?0+(e|$)/, "$1");
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
  const $ = (id) => document.getElementById(id);
  const kindOf = (i) => D.kinds[nd.kind[i]];

  // ---- the graph's geometry (node places come from Python's layout)
  const X = Float64Array.from(nd.x), Y = Float64Array.from(nd.y);
  const src = Int32Array.from(ed.source), tgt = Int32Array.from(ed.target);
  // per node: its paths out and in (CSR), and loops
  function csr(keys) {
    const start = new Int32Array(N + 1);
    for (let e = 0; e < E; e++) start[keys[e] + 1]++;
    for (let i = 0; i < N; i++) start[i + 1] += start[i];
    const fill = start.slice(0, N), list = new Int32Array(E);
    for (let e = 0; e < E; e++) list[fill[keys[e]]++] = e;
    return [start, list];
  }
  const OUT = csr(src), IN = csr(tgt);
  // a marker per path to click: the middle of its line, parallel paths
  // side by side across it; a path back to its own node beside the node
  const HX = new Float64Array(E), HY = new Float64Array(E), CURVED = new Uint8Array(E);
  const CX = new Float64Array(E), CY = new Float64Array(E);
  (function () {
    const groups = new Map();
    for (let e = 0; e < E; e++) {
      const a = Math.min(src[e], tgt[e]), b = Math.max(src[e], tgt[e]), k = a * N + b;
      let g = groups.get(k); if (!g) { g = []; groups.set(k, g); } g.push(e);
    }
    groups.forEach(function (es) {
      const e0 = es[0], s = src[e0], t = tgt[e0];
      if (s === t) {  // paths back to their node: markers on small rings around it
        es.forEach(function (e, k) {
          const a = 2 * Math.PI * ((k % 24) + 0.5) / Math.min(24, es.length), rho = 0.03 * (1 + Math.floor(k / 24));
          HX[e] = X[s] + rho * Math.sin(a); HY[e] = Y[s] + rho * Math.cos(a);
        });
        return;
      }
      const sameRing = nd.depth[s] === nd.depth[t];
      let mx = 0.5 * (X[s] + X[t]), my = 0.5 * (Y[s] + Y[t]);
      if (sameRing) { mx *= 0.7; my *= 0.7; }  // a path within a ring bows towards the centre
      const dx = X[t] - X[s], dy = Y[t] - Y[s], L = Math.hypot(dx, dy) || 1;
      const step = Math.min(0.012, 0.4 * L / Math.max(1, es.length));
      es.forEach(function (e, k) {
        const off = (k - 0.5 * (es.length - 1)) * step;
        HX[e] = mx - off * dy / L; HY[e] = my + off * dx / L;
        if (sameRing) { CURVED[e] = 1; CX[e] = 2 * mx - 0.5 * (X[s] + X[t]); CY[e] = 2 * my - 0.5 * (Y[s] + Y[t]); }
      });
    });
  })();

  // ---- configurations: int16 on one grid, decoded on demand
  const G = D.grid, PER = J * DIM;
  function decode(b64, config) {
    const start = config * PER * 2, len = PER * 2;
    const a = Math.floor(start / 3) * 3, b = Math.ceil((start + len) / 3) * 3;
    const bin = atob(b64.substring(a / 3 * 4, b / 3 * 4));
    const out = new Float64Array(J * 3);
    for (let k = 0; k < PER; k++) {
      const o = start - a + 2 * k;
      let v = bin.charCodeAt(o) | (bin.charCodeAt(o + 1) << 8);
      if (v >= 32768) v -= 65536;
      out[Math.floor(k / DIM) * 3 + (k % DIM)] = G.centre[k % DIM] + G.step * v;
    }
    return out;
  }
  const nodeConfig = (i) => decode(B64C, i);
  function keyframes(e) {  // the source, the samples, the target (or the path's own end, the last sample)
    const fr = [nodeConfig(src[e])];
    for (let k = 0; k < ed.samples[e]; k++) fr.push(decode(B64S, ed.sample_start[e] + k));
    if (!(ed.own_end && ed.own_end[e])) fr.push(nodeConfig(tgt[e]));
    return fr;
  }

  // ---- filters
  const present = (arr, n) => { const c = new Int32Array(n); for (const v of arr) c[v]++; return c; };
  const kindCount = present(nd.kind, D.kinds.length), eventCount = present(ed.event, D.events.length);
  const range = (a) => [Math.min.apply(null, a), Math.max.apply(null, a)];
  const finiteRange = (a) => { const f = (a || []).filter((v) => v !== null && isFinite(v)); return f.length ? range(f) : [0, 0]; };
  const R = { m: range(nd.m), s: range(nd.s), depth: range(nd.depth), xy_extent: finiteRange(nd.xy_extent),
    height: finiteRange(nd.height), clearance: finiteRange(nd.clearance) };
  const COLOUR_TITLE = { m: "m", s: "s", depth: "depth", xy_extent: "x-y extent", height: "height",
    clearance: "clearance", contact: "contact" };
  R.contact = [0, 1];
  const byName = new Map();
  for (let i = 0; i < N; i++) { byName.set(nd.name[i].toLowerCase(), i); byName.set(String(nd.id[i]), i); byName.set("n" + nd.id[i], i); }
  function checkboxes(box, names, counts, colours, cls) {
    names.forEach(function (k, j) {
      if (!counts[j]) return;
      const l = document.createElement("label");
      l.innerHTML = '<input type="checkbox" checked data-' + cls + '="' + j + '"> <span class="swatch" style="background:' +
        (colours[k] || "#888") + '"></span>' + esc(word(k)) + ' <span class="count">' + counts[j].toLocaleString() + "</span>";
      box.appendChild(l);
    });
  }
  checkboxes($("f-kinds"), D.kinds, kindCount, Object.fromEntries(Object.entries(STYLE).map(([k, v]) => [k, v[1]])), "kind");
  checkboxes($("f-events"), D.events, eventCount, EVENT_COLOUR, "event");
  function resetRanges() {
    [["m", "f-m"], ["s", "f-s"], ["depth", "f-d"]].forEach(function ([k, id]) {
      $(id + "-lo").value = R[k][0]; $(id + "-hi").value = R[k][1];
    });
    [["xy_extent", "f-xy"], ["height", "f-h"]].forEach(function ([k, id]) {  // rounded outwards
      $(id + "-lo").value = fmt(Math.floor(R[k][0] * 1000) / 1000, 4); $(id + "-hi").value = fmt(Math.ceil(R[k][1] * 1000) / 1000, 4);
    });
    $("f-contact").value = "any";
  }
  resetRanges();
  // markers on the paths: shown unless there are so many that they hide the map
  const HANDLES = E <= 5000;
  $("f-handles").checked = HANDLES;
  // node names beside the markers: shown while they can be read
  const NAMES = N <= 300;
  $("f-names").checked = NAMES;
  function numberOr(id, dflt) { const v = parseFloat($(id).value); return isFinite(v) ? v : dflt; }
  function filters() {
    const kinds = new Set(), events = new Set();
    document.querySelectorAll("[data-kind]").forEach((c) => { if (c.checked) kinds.add(+c.dataset.kind); });
    document.querySelectorAll("[data-event]").forEach((c) => { if (c.checked) events.add(+c.dataset.event); });
    const orbitText = $("f-orbit").value.trim().toLowerCase();
    const orbitNode = orbitText ? byName.get(orbitText) : undefined;
    return { kinds: kinds, events: events, m: [numberOr("f-m-lo", -Infinity), numberOr("f-m-hi", Infinity)],
      s: [numberOr("f-s-lo", -Infinity), numberOr("f-s-hi", Infinity)],
      depth: [numberOr("f-d-lo", -Infinity), numberOr("f-d-hi", Infinity)],
      xy: [numberOr("f-xy-lo", -Infinity), numberOr("f-xy-hi", Infinity)],
      h: [numberOr("f-h-lo", -Infinity), numberOr("f-h-hi", Infinity)], contact: $("f-contact").value,
      names: $("f-names").checked,
      orbit: orbitText ? (orbitNode === undefined ? -2 : nd.orbit[orbitNode]) : -1, reps: $("f-reps").checked,
      colour: $("f-colour").value, handles: $("f-handles").checked };
  }
  // a node whose value is not known (null) is shown whatever the range
  const inRange = (v, r) => v === null || v === undefined || (v >= r[0] && v <= r[1]);
  function visible(f) {
    const vn = new Uint8Array(N), ve = new Uint8Array(E);
    for (let i = 0; i < N; i++) {
      vn[i] = f.kinds.has(nd.kind[i]) && nd.m[i] >= f.m[0] && nd.m[i] <= f.m[1] && nd.s[i] >= f.s[0] &&
        nd.s[i] <= f.s[1] && nd.depth[i] >= f.depth[0] && nd.depth[i] <= f.depth[1] &&
        (f.orbit === -1 || nd.orbit[i] === f.orbit) && (!f.reps || nd.orbit[i] === i) &&
        inRange(nd.xy_extent[i], f.xy) && inRange(nd.height[i], f.h) &&
        (f.contact === "any" || (f.contact === "contact") === (nd.contact[i] === 1)) ? 1 : 0;
    }
    for (let e = 0; e < E; e++) ve[e] = f.events.has(ed.event[e]) && vn[src[e]] && vn[tgt[e]] ? 1 : 0;
    return [vn, ve];
  }

  // ---- the map
  const gd = $("graph");
  const nodeText = new Array(N), edgeText = new Array(E);
  for (let i = 0; i < N; i++) {
    nodeText[i] = nd.name[i] + " \u00b7 " + word(kindOf(i)) + " \u00b7 m = " + nd.m[i] + ", s = " + nd.s[i] +
      "<br>depth " + nd.depth[i] + " \u00b7 orbit of " + nd.name[nd.orbit[i]] + " \u00b7 " +
      (OUT[0][i + 1] - OUT[0][i]) + " paths out, " + (IN[0][i + 1] - IN[0][i]) + " in<br>x-y extent " +
      fmt(nd.xy_extent[i], 3) + ", height " + fmt(nd.height[i], 3) + " \u00b7 " + (nd.contact[i] ? "in contact" :
      "clearance " + (nd.clearance[i] === null ? "large" : fmt(nd.clearance[i], 3)));
  }
  function edgeLabel(e) {  // built when its marker is drawn
    if (edgeText[e] === undefined) {
      edgeText[e] = "path " + ed.id[e] + ": " + nd.name[src[e]] + " \u2192 " + nd.name[tgt[e]] + " \u00b7 " +
        word(D.events[ed.event[e]]) + " \u00b7 length " + fmt(ed.length[e]) + "<br>click: animate";
    }
    return edgeText[e];
  }
  const msize = N > 8000 ? 5 : N > 1000 ? 7 : N > 100 ? 9 : 13;
  const roles = [];  // per trace: ["node" | "handle" | "other", index array]
  function traces(vn, ve, f) {
    const out = [];
    roles.length = 0;
    D.events.forEach(function (ev, j) {  // legend entries only: the paths are drawn by drawEdges()
      if (!eventCount[j]) return;
      out.push({ type: "scattergl", mode: "lines", x: [NaN], y: [NaN], hoverinfo: "skip", legendgroup: "e",
        name: "paths ending in " + word(ev), line: { color: EVENT_COLOUR[ev] || "#444", width: 2 } });
      roles.push(["other", null]);
    });
    const hi = [];
    if (f.handles) for (let e = 0; e < E; e++) if (ve[e]) hi.push(e);
    out.push({ type: "scattergl", mode: "markers", x: hi.map((e) => HX[e]), y: hi.map((e) => HY[e]),
      text: hi.map(edgeLabel), hoverinfo: "text", showlegend: false, name: "paths",
      marker: { size: Math.max(4, msize - 4), color: hi.map((e) => EVENT_COLOUR[D.events[ed.event[e]]] || "#444"),
        opacity: 0.55, symbol: "circle" } });
    roles.push(["handle", hi]);
    const cvals = f.colour === "kind" ? null : nd[f.colour];
    const crange = f.colour === "kind" ? null : R[f.colour];
    const showNames = f.names;
    let scale = true;
    D.kinds.forEach(function (k, j) {
      if (!kindCount[j]) return;
      const idx = [];
      for (let i = 0; i < N; i++) if (vn[i] && nd.kind[i] === j) idx.push(i);
      const st = STYLE[k] || ["circle", "#444"];
      const marker = { symbol: st[0], size: idx.map((i) => (nd.depth[i] === 0 ? 2 * msize : msize)),
        color: st[1], line: { color: "#222", width: msize > 6 ? 1 : 0.5 } };
      if (cvals) {
        // unknown values (a clearance beyond the cutoff) take the top of the scale
        Object.assign(marker, { color: idx.map((i) => (cvals[i] === null ? crange[1] : cvals[i])), colorscale: "Viridis",
          cmin: crange[0], cmax: crange[1] > crange[0] ? crange[1] : crange[0] + 1, showscale: scale,
          colorbar: { title: { text: COLOUR_TITLE[f.colour] || f.colour }, thickness: 12, len: 0.5, x: 1.0 } });
        scale = false;
      }
      out.push({ type: "scattergl", mode: showNames ? "markers+text" : "markers", x: idx.map((i) => X[i]),
        y: idx.map((i) => Y[i]), text: idx.map((i) => nd.name[i]), hovertext: idx.map((i) => nodeText[i]),
        hoverinfo: "text", textposition: "top center", textfont: { size: 10, color: "#333" },
        name: word(k) + " (" + idx.length.toLocaleString() + ")", marker: marker, legendgroup: "n" });
      roles.push(["node", idx]);
    });
    out.push(highlightTrace());
    roles.push(["other", null]);
    return out;
  }
  function highlight() {  // the selection's marker on the map, moved without redrawing the rest
    const h = highlightTrace();
    return Plotly.restyle(gd, { x: [h.x], y: [h.y], mode: h.mode }, [gd.data.length - 1]);
  }
  function highlightTrace() {
    const xs = [], ys = [];
    if (V.selectedEdge >= 0) {
      const e = V.selectedEdge, s = src[e], t = tgt[e];
      xs.push(X[s], HX[e], X[t]); ys.push(Y[s], HY[e], Y[t]);
    } else if (V.selectedNode >= 0) { xs.push(X[V.selectedNode]); ys.push(Y[V.selectedNode]); }
    return { type: "scattergl", mode: V.selectedEdge >= 0 ? "lines+markers" : "markers", x: xs, y: ys,
      hoverinfo: "skip", showlegend: false, line: { color: "#1f77b4", width: 3 },
      marker: { size: 2 * msize + 6, color: "rgba(0,0,0,0)", line: { color: "#1f77b4", width: 3 } } };
  }
  function graphLayout() {
    const depths = [];
    for (let d = Math.max(1, R.depth[0]); d <= R.depth[1]; d++) depths.push(d);
    const perDepth = new Map();
    for (let i = 0; i < N; i++) perDepth.set(nd.depth[i], (perDepth.get(nd.depth[i]) || 0) + 1);
    const ring = (r) => ({ type: "circle", xref: "x", yref: "y", x0: -r, y0: -r, x1: r, y1: r,
      line: { color: "#e4e4e4", width: 1, dash: "dot" }, layer: "below" });
    return {
      margin: { l: 0, r: 0, t: 0, b: 0 }, dragmode: "pan", hovermode: "closest", hoverdistance: 12,
      uirevision: "map", paper_bgcolor: "rgba(0,0,0,0)", plot_bgcolor: "rgba(0,0,0,0)",
      xaxis: { visible: false }, yaxis: { visible: false, scaleanchor: "x", scaleratio: 1 },
      legend: { x: 0.005, y: 0.995, bgcolor: "rgba(255,255,255,0.8)", itemclick: false, itemdoubleclick: false,
        font: { size: 11 } },
      shapes: depths.map((d) => ring(d - 0.06)),
      annotations: [{ xref: "paper", yref: "paper", x: 0.005, y: 0.005, xanchor: "left", yanchor: "bottom",
        showarrow: false, align: "left", font: { size: 11, color: "#777" }, bgcolor: "rgba(255,255,255,0.8)",
        text: "rings from the centre: " + ["the start"].concat(depths.map((d) => "depth " + d + " (" +
          (perDepth.get(d) || 0).toLocaleString() + " nodes)")).join(", ") }] };
  }
  function nodesDrawn() {
    let n = 0;
    (gd.data || []).forEach(function (tr, k) { if (roles[k] && roles[k][0] === "node") n += tr.x.length; });
    return n;
  }
  function draw(first) {
    const f = filters();
    V.colourBy = f.colour;
    const [vn, ve] = visible(f);
    let nve = 0;
    for (let e = 0; e < E; e++) nve += ve[e];
    edgeBuffers(ve);
    const fn = first ? Plotly.newPlot : Plotly.react;
    return fn(gd, traces(vn, ve, f), graphLayout(), { scrollZoom: true, displaylogo: false, responsive: true,
      modeBarButtonsToRemove: ["select2d", "lasso2d", "autoScale2d"] }).then(function () {
      const drawn = nodesDrawn();
      body.dataset.nodesDrawn = drawn; body.dataset.edgesDrawn = nve;
      body.dataset.namesDrawn = f.names ? drawn : 0;
      $("counts").textContent = "showing " + drawn.toLocaleString() + " of " + N.toLocaleString() + " nodes, " +
        nve.toLocaleString() + " of " + E.toLocaleString() + " paths";
    });
  }

  // ---- the paths: line segments in one WebGL draw under the map (plotly's
  // line traces take seconds to draw tens of thousands of separate lines;
  // without multisampling, which costs seconds more on a CPU renderer)
  const canvas = $("edges");
  const gl = canvas.getContext("webgl", { premultipliedAlpha: true, antialias: false, preserveDrawingBuffer: true });
  const EG = { n: 0, key: "", dirty: true };
  function shader(type, text) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, text); gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error("edge shader: " + gl.getShaderInfoLog(sh));
    return sh;
  }
  if (gl) {
    EG.prog = gl.createProgram();
    gl.attachShader(EG.prog, shader(gl.VERTEX_SHADER, "attribute vec2 p; attribute vec4 c; uniform vec4 T; varying vec4 v;" +
      "void main() { gl_Position = vec4(p.x * T.x + T.z, p.y * T.y + T.w, 0.0, 1.0); v = c; }"));
    gl.attachShader(EG.prog, shader(gl.FRAGMENT_SHADER, "precision mediump float; varying vec4 v;" +
      "void main() { gl_FragColor = vec4(v.rgb * v.a, v.a); }"));
    gl.linkProgram(EG.prog);
    EG.pos = gl.createBuffer(); EG.col = gl.createBuffer();
    EG.aP = gl.getAttribLocation(EG.prog, "p"); EG.aC = gl.getAttribLocation(EG.prog, "c");
    EG.uT = gl.getUniformLocation(EG.prog, "T");
  }
  const rgb = (hex) => [1, 3, 5].map((k) => parseInt(hex.substr(k, 2), 16) / 255);
  function edgeBuffers(ve) {  // the segments of the visible paths (a path within a ring: 8 segments of its curve)
    let nseg = 0, nve = 0;
    for (let e = 0; e < E; e++) if (ve[e] && src[e] !== tgt[e]) { nseg += CURVED[e] ? 8 : 1; nve++; }
    const P = new Float32Array(4 * nseg), C = new Float32Array(8 * nseg);
    const alpha = Math.max(0.03, Math.min(0.8, 6 / Math.sqrt(Math.max(1, nve))));
    const cols = D.events.map((ev) => rgb(EVENT_COLOUR[ev] || "#444444").concat([alpha]));
    let k = 0;
    function seg(x0, y0, x1, y1, c) {
      P[4 * k] = x0; P[4 * k + 1] = y0; P[4 * k + 2] = x1; P[4 * k + 3] = y1;
      C.set(c, 8 * k); C.set(c, 8 * k + 4); k++;
    }
    for (let e = 0; e < E; e++) {
      if (!ve[e] || src[e] === tgt[e]) continue;
      const s = src[e], t = tgt[e], c = cols[ed.event[e]];
      if (!CURVED[e]) { seg(X[s], Y[s], X[t], Y[t], c); continue; }
      let px = X[s], py = Y[s];
      for (let q = 1; q <= 8; q++) {
        const u = q / 8, a = (1 - u) * (1 - u), b = 2 * u * (1 - u), cc = u * u;
        const qx = a * X[s] + b * CX[e] + cc * X[t], qy = a * Y[s] + b * CY[e] + cc * Y[t];
        seg(px, py, qx, qy, c); px = qx; py = qy;
      }
    }
    if (!gl) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, EG.pos); gl.bufferData(gl.ARRAY_BUFFER, P, gl.STATIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, EG.col); gl.bufferData(gl.ARRAY_BUFFER, C, gl.STATIC_DRAW);
    EG.n = 2 * nseg; EG.dirty = true;
  }
  function drawEdges() {  // with the map's current axes; called whenever they change
    const fl = gd._fullLayout;
    if (!gl || !fl || !fl.xaxis || !fl._size) return;
    const xr = fl.xaxis.range, yr = fl.yaxis.range, sz = fl._size, box = gd.getBoundingClientRect();
    const key = [xr[0], xr[1], yr[0], yr[1], sz.l, sz.t, sz.w, sz.h, box.width, box.height].join();
    if (key === EG.key && !EG.dirty) return;
    EG.key = key; EG.dirty = false;
    const dpr = window.devicePixelRatio || 1;
    const W = Math.round(box.width * dpr), H = Math.round(box.height * dpr);
    if (canvas.width !== W || canvas.height !== H) {
      canvas.width = W; canvas.height = H; canvas.style.width = box.width + "px"; canvas.style.height = box.height + "px";
    }
    gl.disable(gl.SCISSOR_TEST); gl.clearColor(0, 0, 0, 0); gl.clear(gl.COLOR_BUFFER_BIT);
    if (!EG.n) return;
    const vx = sz.l * dpr, vy = H - (sz.t + sz.h) * dpr, vw = sz.w * dpr, vh = sz.h * dpr;
    gl.viewport(vx, vy, vw, vh); gl.enable(gl.SCISSOR_TEST); gl.scissor(vx, vy, vw, vh);
    gl.useProgram(EG.prog);
    gl.enable(gl.BLEND); gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    const sx = 2 / (xr[1] - xr[0]), sy = 2 / (yr[1] - yr[0]);
    gl.uniform4f(EG.uT, sx, sy, -1 - xr[0] * sx, -1 - yr[0] * sy);
    gl.bindBuffer(gl.ARRAY_BUFFER, EG.pos); gl.enableVertexAttribArray(EG.aP);
    gl.vertexAttribPointer(EG.aP, 2, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ARRAY_BUFFER, EG.col); gl.enableVertexAttribArray(EG.aC);
    gl.vertexAttribPointer(EG.aC, 4, gl.FLOAT, false, 0, 0);
    gl.drawArrays(gl.LINES, 0, EG.n);
  }
  (function follow() { drawEdges(); requestAnimationFrame(follow); })();  // pan and zoom move the axes

  function pixelOf(x, y) {  // page pixel of a map point (tests, and centring)
    const fl = gd._fullLayout, r = gd.getBoundingClientRect();
    return [r.left + fl._size.l + fl.xaxis.l2p(x), r.top + fl._size.t + fl.yaxis.l2p(y)];
  }
  V.pixelOfNode = (i) => pixelOf(X[i], Y[i]);
  V.pixelOfEdge = (e) => pixelOf(HX[e], HY[e]);

  // ---- the 3D view
  const v3 = $("view3d");
  const BARS = M.bars;
  function curveFrames(fr) {  // every frame the animation can show: each segment at SEG points
    if (fr.length < 2) return fr;
    const out = [], SEG = 24;
    for (let k = 0; k < fr.length - 1; k++)
      for (let q = 0; q < SEG; q++) out.push(segmentAt(fr, k, q / SEG, new Float64Array(J * 3)));
    out.push(fr[fr.length - 1]);
    return out;
  }
  function bounds(frames) {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    frames.forEach(function (c) {
      for (let j = 0; j < J; j++) for (let a = 0; a < 3; a++) {
        const v = c[3 * j + a]; if (v < lo[a]) lo[a] = v; if (v > hi[a]) hi[a] = v;
      }
    });
    const ext = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-9);
    const rng = [0, 1, 2].map(function (a) {
      const h = Math.max(0.5 * (hi[a] - lo[a]), 0.06 * ext) * 1.08, m = 0.5 * (lo[a] + hi[a]);
      return [m - h, m + h];
    });
    return rng;
  }
  function geometry(c) {
    const bx = [], by = [], bz = [];
    BARS.forEach(function (b) {
      bx.push(c[3 * b[0]], c[3 * b[1]], null); by.push(c[3 * b[0] + 1], c[3 * b[1] + 1], null);
      bz.push(c[3 * b[0] + 2], c[3 * b[1] + 2], null);
    });
    const jx = [], jy = [], jz = [];
    for (let j = 0; j < J; j++) { jx.push(c[3 * j]); jy.push(c[3 * j + 1]); jz.push(c[3 * j + 2]); }
    return [[bx, by, bz], [jx, jy, jz]];
  }
  function draw3d(c, rng, title) {
    const [b, j] = geometry(c);
    const span = rng.map((r) => r[1] - r[0]), big = Math.max.apply(null, span);
    const ax = (r, name) => ({ range: r, title: { text: name }, nticks: 5, backgroundcolor: "#fafafa", showbackground: true,
      gridcolor: "#e6e6e6", zerolinecolor: "#ccc" });
    const traces3 = [
      { type: "scatter3d", mode: "lines", x: b[0], y: b[1], z: b[2], line: { color: "#1f77b4", width: 4 },
        hoverinfo: "skip", name: "bars" },
      { type: "scatter3d", mode: "markers", x: j[0], y: j[1], z: j[2], text: M.labels, hoverinfo: "text",
        name: "joints", marker: { size: 3, color: M.fixed.map((f) => (f ? "#111" : "#ff7f0e")),
          symbol: M.fixed.map((f) => (f ? "square" : "circle")) } }];
    const lay = { margin: { l: 0, r: 0, t: 24, b: 0 }, showlegend: false, uirevision: "view3d",
      modebar: { orientation: "v" },  // down the right side, clear of the title
      title: { text: title, font: { size: 12 }, x: 0.02, y: 0.98 },
      scene: { xaxis: ax(rng[0], "x"), yaxis: ax(rng[1], "y"), zaxis: ax(rng[2], "z"), aspectmode: "manual",
        aspectratio: { x: span[0] / big, y: span[1] / big, z: span[2] / big } } };
    if (DIM < 3) {  // a plane structure: seen from above, still rotatable
      Object.assign(lay.scene.zaxis, { visible: false });
      lay.scene.camera = { eye: { x: 0, y: -0.01, z: 1.9 }, up: { x: 0, y: 1, z: 0 } };
    }
    return Plotly.react(v3, traces3, lay, { displaylogo: false, responsive: true });
  }
  function restyle3d(c) {
    const [b, j] = geometry(c);
    return Plotly.restyle(v3, { x: [b[0], j[0]], y: [b[1], j[1]], z: [b[2], j[2]] }, [0, 1]);
  }

  // ---- selection: a node
  function row(k, v) { return "<tr><td>" + k + "</td><td>" + v + "</td></tr>"; }
  function edgeRows(list, start, i, dir) {
    const a = start[i], b = start[i + 1], n = b - a, cap = 200;
    if (!n) return "";
    let h = "<h4>" + n.toLocaleString() + " path" + (n > 1 ? "s" : "") + (dir ? " out" : " in") + "</h4>";
    for (let k = a; k < Math.min(b, a + cap); k++) {
      const e = list[k], other = dir ? tgt[e] : src[e];
      h += '<div class="row" data-edge="' + e + '">' + (dir ? "\u2192 " : "\u2190 ") + esc(nd.name[other]) +
        (other === i ? " (itself)" : "") + " \u00b7 " + word(D.events[ed.event[e]]) + " \u00b7 l = " + fmt(ed.length[e]) +
        " \u00b7 solution " + ed.solution[e] + (ed.sign[e] > 0 ? "+" : "\u2212") + "</div>";
    }
    if (n > cap) h += '<div class="more">\u2026 ' + (n - cap).toLocaleString() + " more (narrow with the filters)</div>";
    return h;
  }
  function selectNode(i) {
    stopAnimation();
    V.selectedNode = i; V.selectedEdge = -1;
    const st = D.statuses[nd.status[i]] || "";
    $("info").innerHTML = "<h3>" + esc(nd.name[i]) + ": " + esc(word(kindOf(i))) + "</h3><table>" +
      row("m, s", nd.m[i] + ", " + nd.s[i]) + row("v<sub>r</sub>/v<sub>max</sub>", fmt(nd.v_r[i], 3)) +
      row("depth", nd.depth[i]) + row("orbit of", esc(nd.name[nd.orbit[i]])) +
      row("expanded", nd.expanded[i] ? "yes" : "no") + (st ? row("status", esc(st)) : "") + "</table>";
    $("edgelist").innerHTML = edgeRows(OUT[1], OUT[0], i, true) + edgeRows(IN[1], IN[0], i, false);
    $("anim").hidden = true;
    const c = nodeConfig(i);
    body.dataset.view3d = "node " + nd.id[i];
    highlight();
    return draw3d(c, bounds([c]), nd.name[i] + " (" + word(kindOf(i)) + ", m = " + nd.m[i] + ", s = " + nd.s[i] + ")");
  }
  V.selectNode = selectNode;

  // ---- selection: a path, animated from its samples
  let anim = null;
  // the keyframes' places along the path: cumulative chord length, 0 to 1
  // (the samples are denser where the path turns: the animation keeps a
  // steady pace along the path)
  function knots(fr) {
    const u = [0];
    for (let k = 1; k < fr.length; k++) {
      let d = 0;
      for (let q = 0; q < fr[k].length; q++) d += (fr[k][q] - fr[k - 1][q]) ** 2;
      u.push(u[k - 1] + Math.sqrt(d));
    }
    const L = u[u.length - 1];
    return u.map((v, k) => (L > 0 ? v / L : k / Math.max(1, fr.length - 1)));
  }
  function catmull(fr, u, out) {  // the uniform Catmull-Rom spline through the keyframes at u in [0, 1] of the path
    const K = fr.length - 1, kn = anim && anim.frames === fr ? anim.knots : knots(fr);
    const x = Math.min(Math.max(u, 0), 1);
    let k = 0;
    while (k < K - 1 && kn[k + 1] <= x) k++;
    const t = kn[k + 1] > kn[k] ? Math.min(1, (x - kn[k]) / (kn[k + 1] - kn[k])) : 0;
    return segmentAt(fr, k, t, out);
  }
  function segmentAt(fr, k, t, out) {  // segment k (keyframes k to k+1) at t in [0, 1]; atlas/frames.py catmull()
    const K = fr.length - 1;
    const p0 = fr[Math.max(k - 1, 0)], p1 = fr[k], p2 = fr[k + 1], p3 = fr[Math.min(k + 2, K)];
    const t2 = t * t, t3 = t2 * t;
    for (let q = 0; q < out.length; q++) {
      out[q] = 0.5 * (2 * p1[q] + (-p0[q] + p2[q]) * t + (2 * p0[q] - 5 * p1[q] + 4 * p2[q] - p3[q]) * t2 +
        (-p0[q] + 3 * p1[q] - 3 * p2[q] + p3[q]) * t3);
    }
    return out;
  }
  const PERIOD = 3000, HOLD = 600;
  function showAt(u) {
    catmull(anim.frames, u, anim.buf);
    $("a-pos").value = Math.round(1000 * u);
    $("a-label").textContent = "l \u2248 " + fmt(u * (ed.length[anim.e] || 0), 3) + " of " + fmt(ed.length[anim.e], 3);
    return restyle3d(anim.buf);
  }
  function tick(now) {
    if (!anim || !anim.playing) return;
    if (!anim.busy) {
      const u = Math.min(1, (Math.max(0, now - anim.t0) % (PERIOD + HOLD)) / PERIOD);
      anim.busy = true;
      Promise.resolve(showAt(u)).then(function () { anim && (anim.busy = false); V.frames++; });
    }
    anim.raf = requestAnimationFrame(tick);
  }
  function stopAnimation() {
    if (anim && anim.raf) cancelAnimationFrame(anim.raf);
    anim = null; V.animating = false;
  }
  function selectEdge(e, fromList) {
    stopAnimation();
    if (!fromList) $("edgelist").innerHTML = edgeRows(OUT[1], OUT[0], src[e], true) + edgeRows(IN[1], IN[0], src[e], false);
    V.selectedEdge = e; V.selectedNode = -1;
    const s = src[e], t = tgt[e], ns = ed.samples[e];
    $("info").innerHTML = "<h3>path " + ed.id[e] + ": " + esc(nd.name[s]) + " \u2192 " + esc(nd.name[t]) + "</h3><table>" +
      row("ends in", word(D.events[ed.event[e]])) + row("length", fmt(ed.length[e])) +
      row("solution", ed.solution[e] + ", sense " + (ed.sign[e] > 0 ? "+" : "\u2212")) +
      row("drawn from", ns ? ns + " configuration" + (ns > 1 ? "s" : "") + " along the path" +
        (ed.own_end && ed.own_end[e] ? " (the last its own end: a copy of " + esc(nd.name[t]) + " moved rigidly)" : "") +
        " and its start, smoothly interpolated in between" :
        "its two ends only (no samples stored): a straight interpolation, not the path") + "</table>";
    document.querySelectorAll("#edgelist .row").forEach((r) => r.classList.toggle("sel", +r.dataset.edge === e));
    const frames = keyframes(e);
    anim = { e: e, frames: frames, knots: knots(frames), buf: new Float64Array(J * 3), playing: true,
      t0: performance.now(), busy: false };
    const box = bounds(curveFrames(frames));
    V.box = box;
    V.animating = true;
    body.dataset.view3d = "path " + ed.id[e];
    $("anim").hidden = false; $("a-play").textContent = "pause";
    highlight();
    return draw3d(frames[0], box, nd.name[s] + " \u2192 " + nd.name[t] + " (" + word(D.events[ed.event[e]]) + ")")
      .then(function () { if (anim && anim.e === e) anim.raf = requestAnimationFrame(tick); });
  }
  V.selectEdge = selectEdge;
  // tests: the frame the animation shows at u (0..1 of the path), as joints x 3
  V.frameAt = (u) => (anim ? Array.from(catmull(anim.frames, u, new Float64Array(J * 3))) : null);
  $("a-play").addEventListener("click", function () {
    if (!anim) return;
    anim.playing = !anim.playing; V.animating = anim.playing;
    this.textContent = anim.playing ? "pause" : "play";
    if (anim.playing) { anim.t0 = performance.now() - PERIOD * $("a-pos").value / 1000; anim.raf = requestAnimationFrame(tick); }
  });
  $("a-pos").addEventListener("input", function () {
    if (!anim) return;
    anim.playing = false; V.animating = false; $("a-play").textContent = "play";
    showAt(this.value / 1000);
  });
  $("edgelist").addEventListener("click", function (ev) {
    const r = ev.target.closest(".row");
    if (r) selectEdge(+r.dataset.edge, true);
  });

  // ---- wiring
  function onClick(ev) {
    const p = ev.points && ev.points[0];
    if (!p) return;
    const role = roles[p.curveNumber];
    if (!role || !role[1]) return;
    const k = role[1][p.pointIndex !== undefined ? p.pointIndex : p.pointNumber];
    if (role[0] === "node") selectNode(k); else if (role[0] === "handle") selectEdge(k);
  }
  function goTo() {
    const i = byName.get($("f-goto").value.trim().toLowerCase());
    if (i === undefined) { $("f-goto").style.background = "#fdd"; return; }
    $("f-goto").style.background = "";
    const fl = gd._fullLayout, w = Math.max(0.15, 0.5 * (fl.xaxis.range[1] - fl.xaxis.range[0]) / 4);
    const h = w * (fl.yaxis.range[1] - fl.yaxis.range[0]) / (fl.xaxis.range[1] - fl.xaxis.range[0]);
    Plotly.relayout(gd, { "xaxis.range": [X[i] - w, X[i] + w], "yaxis.range": [Y[i] - h, Y[i] + h] });
    selectNode(i);
  }
  let pending = null;
  function redraw() { if (pending) clearTimeout(pending); pending = setTimeout(function () { pending = null; draw(false); }, 60); }
  $("filters").addEventListener("change", function (ev) { if (ev.target.id !== "f-goto") redraw(); });
  $("f-goto").addEventListener("keydown", function (ev) { if (ev.key === "Enter") goTo(); });
  $("f-reset").addEventListener("click", function () {
    document.querySelectorAll("[data-kind],[data-event]").forEach((c) => { c.checked = true; });
    resetRanges(); $("f-orbit").value = ""; $("f-reps").checked = false; $("f-handles").checked = HANDLES; $("f-names").checked = NAMES; draw(false);
  });

  $("title").textContent = D.title;
  const S = D.summary;
  const RE = D.reach || {};
  $("summary").textContent = S.nodes.toLocaleString() + " nodes, " + S.edges.toLocaleString() + " directed paths; " +
    M.joints + " joints, " + M.bars.length + " bars" + (RE.reached !== undefined ? "; reached depth " + RE.reached +
    (RE.depth !== undefined && RE.depth !== null ? " of " + RE.depth : "") : "") +
    (D.grid.samples_dropped ? "; " + D.grid.samples_dropped.toLocaleString() + " samples left out of the page (size)" : "");
  // why it stopped there: the limits that bit (limits.py), or that nothing was left to expand
  $("stopped").textContent = (RE.stopped || []).length ? RE.stopped.join("; ") :
    (RE.depth !== undefined && RE.depth !== null && RE.reached < RE.depth ? "complete: no new node past depth " + RE.reached :
      RE.depth !== undefined && RE.depth !== null ? "complete to the depth asked for" : "");
  $("stopped").classList.toggle("limit", (RE.stopped || []).length > 0);
  draw(true).then(function () {
    gd.on("plotly_click", onClick);
    requestAnimationFrame(function () {
      drawEdges();
      V.ready = true;
      body.dataset.loadMs = Math.round(performance.now());
      body.dataset.scriptMs = Math.round(performance.now() - T0);
      body.dataset.ready = "1";
    });
  });
})();
