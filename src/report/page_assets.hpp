// The report page's stylesheet and script, written by hand and inlined into every page.
#pragma once

namespace gm::report {

/// The page's CSS.
inline constexpr const char* kPageStyle = R"css(
body{font:14px/1.4 system-ui,sans-serif;margin:0 auto;max-width:1100px;padding:8px 16px;color:#222;background:#fff}
h1{font-size:20px;margin:8px 0}h2{font-size:16px;margin:18px 0 6px;border-bottom:1px solid #ccc}
.meta{color:#444}.note{color:#666;font-size:12px}
svg{display:block;width:100%;height:auto;background:#fff}
svg text{font:11px sans-serif;fill:#333}svg text.title{font-weight:600}
.plot{fill:none;stroke:#999}.grid{stroke:#e4e4e4}
.band{stroke-width:1;vector-effect:non-scaling-stroke;stroke-linejoin:round}
.prog{fill:none;stroke:#888;stroke-width:2.5;vector-effect:non-scaling-stroke}
.rapid{fill:none;stroke:#aaa;stroke-width:1;stroke-dasharray:4 3;vector-effect:non-scaling-stroke}
.act{fill:none;stroke-width:1.3;vector-effect:non-scaling-stroke;stroke-linejoin:round}
.cursor{stroke:#000;stroke-width:1;visibility:hidden}
#xy{max-width:640px;border:1px solid #ccc;cursor:grab}
.xybox{display:flex;gap:16px;align-items:flex-start;flex-wrap:wrap}
.legend span{display:inline-block;width:14px;height:10px;margin-right:4px;vertical-align:middle}
#cursor-info{position:sticky;top:0;background:#f6f6f6;border:1px solid #ddd;padding:4px 8px;min-height:2.8em;font-size:13px;z-index:1}
#cursor-info code{background:#fff;padding:0 4px}
table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ddd;padding:2px 8px;text-align:left}
td:nth-child(2){text-align:right;font-variant-numeric:tabular-nums}
pre{background:#f6f6f6;padding:6px;overflow:auto;font-size:12px}
button{font-size:12px}
)css";

/// The page's script: the summary table from the embedded JSON, the time cursor shared by the
/// time plots (with the source line under it; `#t=SECONDS` in the address places it), and zoom
/// and pan on the XY plot.
inline constexpr const char* kPageScript = R"js(
(function () {
  'use strict';
  const D = JSON.parse(document.getElementById('gm-data').textContent);
  const S = JSON.parse(document.getElementById('gm-summary').textContent);
  // Summary table: one row per value, nested keys joined with dots.
  const rows = [];
  (function flat(o, p) {
    for (const k of Object.keys(o)) {
      const v = o[k], n = p ? p + '.' + k : k;
      if (v !== null && typeof v === 'object') flat(v, n); else rows.push([n, v]);
    }
  })(S, '');
  const tb = document.getElementById('summary-table');
  for (const [k, v] of rows) {
    const tr = tb.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v === null ? 'n/a' : String(v);
  }
  // Time cursor.
  const info = document.getElementById('cursor-info');
  const charts = Array.from(document.querySelectorAll('svg.tchart'));
  function column(t) {
    let lo = 0, hi = D.t.length - 1;
    if (hi < 0) return -1;
    while (lo < hi) { const m = (lo + hi + 1) >> 1; if (D.t[m] <= t) lo = m; else hi = m - 1; }
    return lo;
  }
  function fmt(v) { return Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(3) : (+v.toFixed(4)).toString(); }
  function range(lo, hi) { return lo === hi ? fmt(lo) : fmt(lo) + ' … ' + fmt(hi); }
  function show(t) {
    for (const svg of charts) {
      const d = svg.dataset, c = svg.querySelector('.cursor');
      const x = +d.x0 + (t - d.t0) / (d.t1 - d.t0 || 1) * (d.x1 - d.x0);
      c.setAttribute('x1', x); c.setAttribute('x2', x); c.style.visibility = 'visible';
    }
    const i = column(t);
    if (i < 0) return;
    const line = D.line[i], text = D.src[line];
    info.innerHTML = '';
    const head = document.createElement('div');
    head.textContent = 't = ' + t.toFixed(4) + ' s · contour error ' + range(D.ce_lo[i], D.ce_hi[i]) +
      ' BLU · feed override ' + range(D.ov_lo[i], D.ov_hi[i]) + ' %' +
      (D.width > 1 ? ' · (column of ' + D.width + ' samples)' : '');
    const src = document.createElement('div');
    src.textContent = line > 0 ? D.file + ':' + line + ' ' : '(no source line)';
    if (text !== undefined) { const c = document.createElement('code'); c.textContent = text; src.appendChild(c); }
    info.appendChild(head); info.appendChild(src);
  }
  for (const svg of charts) {
    svg.addEventListener('mousemove', function (e) {
      const p = svg.createSVGPoint(); p.x = e.clientX; p.y = e.clientY;
      const q = p.matrixTransform(svg.getScreenCTM().inverse()), d = svg.dataset;
      if (q.x < +d.x0 || q.x > +d.x1) return;
      show(+d.t0 + (q.x - d.x0) / (d.x1 - d.x0) * (d.t1 - d.t0));
    });
  }
  // PAGE.html#t=2.5 opens with the cursor at 2.5 s (links into a report; the browser test).
  const at_t = /[#&]t=([0-9.eE+-]+)/.exec(location.hash);
  if (at_t) show(+at_t[1]);
  // XY plot: wheel zooms about the pointer, drag pans, double click (or Reset) shows it all.
  const xy = document.getElementById('xy');
  if (!xy) return;
  const vb0 = xy.getAttribute('viewBox').split(' ').map(Number);
  let vb = vb0.slice(), drag = null;
  function set() { xy.setAttribute('viewBox', vb.join(' ')); }
  function at(e) { const p = xy.createSVGPoint(); p.x = e.clientX; p.y = e.clientY; return p.matrixTransform(xy.getScreenCTM().inverse()); }
  function zoom(f, p) { vb = [p.x - (p.x - vb[0]) * f, p.y - (p.y - vb[1]) * f, vb[2] * f, vb[3] * f]; set(); }
  xy.addEventListener('wheel', function (e) { e.preventDefault(); zoom(e.deltaY < 0 ? 0.8 : 1.25, at(e)); }, { passive: false });
  xy.addEventListener('mousedown', function (e) { drag = { x: e.clientX, y: e.clientY, vb: vb.slice() }; });
  window.addEventListener('mouseup', function () { drag = null; });
  xy.addEventListener('mousemove', function (e) {
    if (!drag) return;
    const s = drag.vb[2] / xy.getBoundingClientRect().width;
    vb = [drag.vb[0] - (e.clientX - drag.x) * s, drag.vb[1] - (e.clientY - drag.y) * s, vb[2], vb[3]]; set();
  });
  xy.addEventListener('dblclick', function () { vb = vb0.slice(); set(); });
  const centre = function () { return { x: vb[0] + vb[2] / 2, y: vb[1] + vb[3] / 2 }; };
  document.getElementById('zoom-in').onclick = function () { zoom(0.5, centre()); };
  document.getElementById('zoom-out').onclick = function () { zoom(2, centre()); };
  document.getElementById('zoom-reset').onclick = function () { vb = vb0.slice(); set(); };
})();
)js";

}  // namespace gm::report
