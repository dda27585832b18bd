"use strict";
// Draws the report's data (the JSON in #report-data): one timeline canvas
// with a row per node, one plot canvas per traffic plot (bus load, frames
// per second per node, raw bytes of unmapped PDOs) and per PDO field, a
// shared time axis
// (wheel zooms, drag pans, double-click shows the whole log) and a tooltip
// on hover. What was drawn is published on <body data-*> and in #selftest
// so a headless browser can check the page rendered.
(function () {
  var status = { rendered: false, errors: [], series: 0, plots: 0, points: 0, marks: 0, rows: 0 };
  function publish() {
    var b = document.body;
    b.dataset.rendered = status.rendered ? "ok" : "no";
    b.dataset.errors = String(status.errors.length);
    b.dataset.series = String(status.series);
    b.dataset.plots = String(status.plots);
    b.dataset.points = String(status.points);
    b.dataset.marks = String(status.marks);
    b.dataset.rows = String(status.rows);
    document.getElementById("selftest").textContent = JSON.stringify(status);
  }
  window.addEventListener("error", function (e) {
    status.errors.push(String(e.message || e));
    publish();
  });

  var data = JSON.parse(document.getElementById("report-data").textContent);
  var span = data.span > 0 ? data.span : 1;
  var view = { t0: 0, t1: span };
  var LEFT = 160, RIGHT = 16, ROW = 26, AXIS = 22;
  var drawers = [];
  var tooltip = document.getElementById("tooltip");

  var STATE_COLOURS = {
    "operational": "#4caf50", "pre-operational": "#ffc107", "stopped": "#e53935",
    "boot-up": "#42a5f5"
  };
  var MARKS = {
    "boot-up": ["#1e63c6", "boot-up"], "emcy": ["#d50000", "EMCY"],
    "emcy-reset": ["#2e7d32", "EMCY error reset"], "sdo": ["#607d8b", "SDO transfer"],
    "sdo-abort": ["#ff6d00", "SDO abort"], "sdo-incomplete": ["#ffab00", "SDO incomplete"],
    "guard": ["#8e24aa", "node-guarding request"], "nmt": ["#000000", "NMT command"]
  };

  function width() {
    return Math.max(640, Math.min(document.documentElement.clientWidth - 40, 1800));
  }
  function setup(canvas, h) {
    var dpr = window.devicePixelRatio || 1, w = width();
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
    canvas.style.width = w + "px";
    canvas.style.height = h + "px";
    var c = canvas.getContext("2d");
    c.setTransform(dpr, 0, 0, dpr, 0, 0);
    c.clearRect(0, 0, w, h);
    return { c: c, w: w, h: h };
  }
  function xOf(t, w) { return LEFT + (t - view.t0) / (view.t1 - view.t0) * (w - LEFT - RIGHT); }
  function tOf(px, w) { return view.t0 + (px - LEFT) / (w - LEFT - RIGHT) * (view.t1 - view.t0); }
  function niceStep(range, n) {
    var raw = range / n, p = Math.pow(10, Math.floor(Math.log10(raw))), m = raw / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
  }
  function fmt(v) {
    var a = Math.abs(v);
    if (a !== 0 && (a >= 1e6 || a < 1e-3)) return v.toExponential(3);
    return String(Math.round(v * 1000) / 1000);
  }
  function timeAxis(c, w, top, bottom) {
    var step = niceStep(view.t1 - view.t0, 8), t = Math.ceil(view.t0 / step) * step;
    c.strokeStyle = "#eee"; c.fillStyle = "#666"; c.font = "11px sans-serif"; c.textAlign = "center";
    for (; t <= view.t1; t += step) {
      var x = xOf(t, w);
      c.beginPath(); c.moveTo(x, top); c.lineTo(x, bottom); c.stroke();
      c.fillText(fmt(t) + " s", x, bottom + 14);
    }
    c.textAlign = "left";
  }
  // First index i with arr[i] >= t.
  function lowerBound(arr, t) {
    var lo = 0, hi = arr.length;
    while (lo < hi) { var mid = (lo + hi) >> 1; if (arr[mid] < t) lo = mid + 1; else hi = mid; }
    return lo;
  }
  function showTip(e, text) {
    if (!text) { tooltip.hidden = true; return; }
    tooltip.textContent = text;
    tooltip.hidden = false;
    tooltip.style.left = (e.clientX + 12) + "px";
    tooltip.style.top = (e.clientY + 12) + "px";
  }
  function redrawAll() { drawers.forEach(function (d) { d(); }); }
  function interact(canvas, hover) {
    var drag = null;
    canvas.addEventListener("wheel", function (e) {
      e.preventDefault();
      var w = canvas.clientWidth, t = tOf(e.offsetX, w), f = Math.exp(e.deltaY * 0.0015);
      var t0 = t - (t - view.t0) * f, t1 = t + (view.t1 - t) * f;
      if (t1 - t0 < 1e-6) return;
      view.t0 = Math.max(-span * 0.05, t0); view.t1 = Math.min(span * 1.05, t1);
      redrawAll();
    }, { passive: false });
    canvas.addEventListener("mousedown", function (e) { drag = { x: e.clientX, t0: view.t0, t1: view.t1 }; });
    window.addEventListener("mouseup", function () { drag = null; });
    canvas.addEventListener("mousemove", function (e) {
      if (drag) {
        var w = canvas.clientWidth, dt = (drag.x - e.clientX) / (w - LEFT - RIGHT) * (drag.t1 - drag.t0);
        view.t0 = drag.t0 + dt; view.t1 = drag.t1 + dt;
        redrawAll();
        return;
      }
      showTip(e, hover(e.offsetX, e.offsetY, canvas.clientWidth));
    });
    canvas.addEventListener("mouseleave", function () { tooltip.hidden = true; });
    canvas.addEventListener("dblclick", function () { view.t0 = 0; view.t1 = span; redrawAll(); });
  }

  // ---- the timeline ----
  function drawMark(c, kind, x, y) {
    var col = (MARKS[kind] || ["#000"])[0];
    c.fillStyle = col; c.strokeStyle = col;
    c.beginPath();
    if (kind === "emcy") { c.moveTo(x, y - 7); c.lineTo(x + 6, y + 5); c.lineTo(x - 6, y + 5); c.closePath(); c.fill(); }
    else if (kind === "boot-up") { c.arc(x, y, 5, 0, 2 * Math.PI); c.fill(); }
    else if (kind === "sdo-abort" || kind === "emcy-reset") { c.moveTo(x, y - 6); c.lineTo(x + 5, y); c.lineTo(x, y + 6); c.lineTo(x - 5, y); c.closePath(); c.fill(); }
    else if (kind === "nmt") { c.rect(x - 4, y - 4, 8, 8); c.fill(); }
    else { c.lineWidth = 2; c.moveTo(x, y - 8); c.lineTo(x, y + 8); c.stroke(); c.lineWidth = 1; }
  }
  function timeline() {
    var canvas = document.getElementById("timeline-canvas");
    var rows = data.rows, h = rows.length * ROW + AXIS + 8;
    function draw() {
      var g = setup(canvas, h), c = g.c, w = g.w, drawn = 0;
      timeAxis(c, w, 0, h - AXIS);
      rows.forEach(function (r, i) {
        var top = i * ROW + 4, mid = top + ROW / 2 - 2;
        c.fillStyle = "#222"; c.font = "12px sans-serif";
        c.fillText(r.label, 4, mid + 4);
        // NMT states as bars: each state from its change to the next.
        for (var k = 0; k < r.states.length; k++) {
          var a = r.states[k][0], b = k + 1 < r.states.length ? r.states[k + 1][0] : span;
          var x0 = Math.max(LEFT, xOf(a, w)), x1 = Math.min(w - RIGHT, xOf(b, w));
          if (x1 <= x0) continue;
          c.fillStyle = STATE_COLOURS[r.states[k][1]] || "#bdbdbd";
          c.globalAlpha = 0.35; c.fillRect(x0, top + 4, x1 - x0, ROW - 12); c.globalAlpha = 1;
        }
        // Heartbeat silences: a red band with its edges.
        r.silences.forEach(function (s) {
          var x0 = Math.max(LEFT, xOf(s[0], w)), x1 = Math.min(w - RIGHT, xOf(s[1] === null ? span : s[1], w));
          drawn++;
          if (x1 < x0) return;
          c.fillStyle = "rgba(229,57,53,0.35)"; c.fillRect(x0, top + 2, Math.max(2, x1 - x0), ROW - 8);
        });
        r.marks.forEach(function (m) {
          drawn++;
          var x = xOf(m[0], w);
          if (x < LEFT - 6 || x > w - RIGHT + 6) return;
          drawMark(c, m[1], x, mid);
        });
      });
      if (!status.rendered) status.marks = drawn;
    }
    drawers.push(draw);
    interact(canvas, function (px, py, w) {
      var i = Math.floor((py - 4) / ROW), r = rows[i];
      if (!r) return "";
      var best = null, bestDx = 6;
      r.marks.forEach(function (m) {
        var dx = Math.abs(xOf(m[0], w) - px);
        if (dx < bestDx) { bestDx = dx; best = m; }
      });
      var t = tOf(px, w);
      if (best) return r.label + " at " + fmt(best[0]) + " s\n" + (MARKS[best[1]] || [0, best[1]])[1] + ": " + best[2];
      for (var s = 0; s < r.silences.length; s++) {
        var a = r.silences[s][0], b = r.silences[s][1];
        if (t >= a && (b === null || t <= b)) return r.label + ": heartbeat silent from " + fmt(a) + " s" + (b === null ? " until the end" : " to " + fmt(b) + " s");
      }
      var k = lowerBound(r.states.map(function (x) { return x[0]; }), t + 1e-9) - 1;
      return k >= 0 ? r.label + " at " + fmt(t) + " s: " + r.states[k][1] : r.label;
    });
    status.rows = rows.length;
    var legend = document.getElementById("legend");
    Object.keys(MARKS).forEach(function (k) {
      var s = document.createElement("span"), i = document.createElement("i");
      i.style.background = MARKS[k][0]; s.appendChild(i); s.appendChild(document.createTextNode(MARKS[k][1])); legend.appendChild(s);
    });
    var notes = [];
    rows.forEach(function (r) {
      r.not_drawn.forEach(function (n) { notes.push(r.label + ": " + n[1] + " more " + (MARKS[n[0]] || [0, n[0]])[1] + " marks not drawn"); });
      if (r.states_not_drawn > 0) notes.push(r.label + ": " + r.states_not_drawn + " more state changes not drawn");
    });
    document.getElementById("not-drawn").textContent = notes.length ? notes.join("; ") + " (the summary counts them all)" : "";
  }

  // ---- one plot per field or traffic plot ----
  function plot(s, where) {
    var box = document.createElement("div"), title = document.createElement("h3"), canvas = document.createElement("canvas");
    box.className = "plot";
    title.textContent = s.label + " ";
    var meta = document.createElement("span");
    meta.className = "meta";
    meta.textContent = "(" + s.samples + " samples" + (s.invalid ? ", " + s.invalid + " without a value" : "") +
      (s.exact ? "" : "; drawn as the lowest and highest value per column") + ")";
    title.appendChild(meta);
    box.appendChild(title); box.appendChild(canvas);
    document.getElementById(where).appendChild(box);
    var steps = s.raw || s.step;
    var H = 150, PAD = 10, lo = Infinity, hi = -Infinity;
    s.v.forEach(function (v) { if (v < lo) lo = v; if (v > hi) hi = v; });
    if (!isFinite(lo)) { lo = 0; hi = 1; }
    if (hi === lo) { hi += 1; lo -= 1; }
    var m = (hi - lo) * 0.06; lo -= m; hi += m;
    function yOf(v) { return PAD + (hi - v) / (hi - lo) * (H - AXIS - 2 * PAD); }
    function draw() {
      var g = setup(canvas, H), c = g.c, w = g.w;
      timeAxis(c, w, 0, H - AXIS);
      var step = niceStep(hi - lo, 4), v0 = Math.ceil(lo / step) * step;
      c.fillStyle = "#666"; c.font = "11px sans-serif"; c.textAlign = "right";
      for (var v = v0; v <= hi; v += step) {
        var y = yOf(v);
        c.strokeStyle = "#eee"; c.beginPath(); c.moveTo(LEFT, y); c.lineTo(w - RIGHT, y); c.stroke();
        c.fillText(fmt(v) + (s.unit ? " " + s.unit : ""), LEFT - 6, y + 4);
      }
      c.textAlign = "left";
      c.save(); c.beginPath(); c.rect(LEFT, 0, w - LEFT - RIGHT, H - AXIS); c.clip();
      var i = Math.max(0, lowerBound(s.t, view.t0) - 1), end = Math.min(s.t.length, lowerBound(s.t, view.t1) + 1);
      var gi = lowerBound(s.gaps, s.t[i]), prev = null;
      c.strokeStyle = s.raw ? "#6a1b9a" : s.step ? "#00796b" : "#1565c0"; c.lineWidth = 1.2; c.beginPath();
      for (; i < end; i++) {
        var x = xOf(s.t[i], w), y = yOf(s.v[i]), broken = false;
        while (gi < s.gaps.length && s.gaps[gi] <= s.t[i]) { broken = true; gi++; }
        if (prev === null || broken) c.moveTo(x, y);
        else if (steps) { c.lineTo(x, prev); c.lineTo(x, y); }
        else c.lineTo(x, y);
        prev = y;
      }
      c.stroke();
      if (s.t.length === 1) { c.fillStyle = c.strokeStyle; c.fillRect(xOf(s.t[0], w) - 2, yOf(s.v[0]) - 2, 4, 4); }
      c.restore();
      if (s.t.length === 0) { c.fillStyle = "#999"; c.fillText("no value in the log", LEFT + 8, H / 2); }
    }
    drawers.push(draw);
    interact(canvas, function (px, py, w) {
      if (s.t.length === 0) return "";
      var t = tOf(px, w), k = lowerBound(s.t, t);
      if (k >= s.t.length || (k > 0 && t - s.t[k - 1] < s.t[k] - t)) k--;
      if (Math.abs(xOf(s.t[k], w) - px) > 30) return "";
      var v = s.raw ? s.v[k] + " (0x" + s.v[k].toString(16).toUpperCase() + ")" : fmt(s.v[k]) + (s.unit ? " " + s.unit : "");
      return s.label + "\n" + fmt(s.t[k]) + " s: " + v;
    });
    if (where === "plots") status.series++; else status.plots++;
    status.points += s.t.length;
  }

  try {
    timeline();
    (data.plots || []).forEach(function (s) { plot(s, "traffic"); });
    document.getElementById("traffic-not-drawn").textContent = data.plots_not_drawn || "";
    data.series.forEach(function (s) { plot(s, "plots"); });
    if (data.series.length === 0) {
      var p = document.createElement("p");
      p.textContent = "No named PDO field in this log (give the mapping with --pdo, --eds or a role).";
      document.getElementById("plots").appendChild(p);
    }
    redrawAll();
    status.rendered = true;
  } catch (e) {
    status.errors.push(String(e && e.stack || e));
  }
  publish();
  window.addEventListener("resize", redrawAll);
})();
