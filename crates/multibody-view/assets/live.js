// multibody live: the model's files and the engine (WebAssembly, embedded
// compressed in #mb-live) are in this page. A panel lists the model's own
// parameters and start values and the stop time; each change runs the model
// again here, and the view and plots follow. A value the model refuses gets
// the message `multibody run` prints for it, and the last good run stays.
//
// Query parameters (for tests and links), on top of the viewer's:
// live=NAME=VALUE;NAME=VALUE... sets each value as if typed (each runs);
// livebench=N runs N more times, alternating a value, and logs the times;
// livestep=DT&liveinput=NAME=V0@T1=V1 steps the run by DT up to the stop
// time at once (not in real time), the input NAME at V0 until T1, then V1;
// realtime starts a run in real time when the page opens.
"use strict";
(function () {
  var viewer = window.__multibody;
  var report = window.__multibodyReport || function (m) { console.log("multibody-view error: " + m); };
  var spec = JSON.parse(document.getElementById("mb-live").textContent);
  var query = new URLSearchParams(window.location.search);

  // ------------------------------------------------------------ inflate
  // Raw DEFLATE (RFC 1951), synchronous so that the page is ready when it
  // has loaded. Canonical Huffman codes decoded bit by bit, as in zlib's puff.
  var LBASE = [3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258];
  var LEXT = [0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0];
  var DBASE = [1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073,
    4097, 6145, 8193, 12289, 16385, 24577];
  var DEXT = [0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13];
  var ORDER = [16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15];

  function inflate(data, size) {
    var out = new Uint8Array(size), op = 0, pos = 0, bitBuf = 0, bitCount = 0;
    function bits(n) {
      while (bitCount < n) {
        if (pos >= data.length) throw new Error("the embedded module is truncated");
        bitBuf |= data[pos++] << bitCount;
        bitCount += 8;
      }
      var v = bitBuf & ((1 << n) - 1);
      bitBuf >>>= n;
      bitCount -= n;
      return v;
    }
    function huffman(lengths, n) {
      var count = new Uint16Array(16), offset = new Uint16Array(16), symbol = new Uint16Array(n);
      for (var i = 0; i < n; i++) count[lengths[i]]++;
      count[0] = 0;
      for (i = 1; i < 15; i++) offset[i + 1] = offset[i] + count[i];
      for (i = 0; i < n; i++) if (lengths[i]) symbol[offset[lengths[i]]++] = i;
      return { count: count, symbol: symbol };
    }
    function decode(h) {
      var code = 0, first = 0, index = 0;
      for (var len = 1; len < 16; len++) {
        code |= bits(1);
        var c = h.count[len];
        if (code - c < first) return h.symbol[index + (code - first)];
        index += c; first = (first + c) << 1; code <<= 1;
      }
      throw new Error("the embedded module is corrupt (bad code)");
    }
    var fixedLit = null, fixedDist = null;
    var last;
    do {
      last = bits(1);
      var type = bits(2), lit, dist;
      if (type === 0) {
        bitBuf = 0; bitCount = 0;
        var len = data[pos] | (data[pos + 1] << 8);
        pos += 4;
        out.set(data.subarray(pos, pos + len), op);
        pos += len; op += len;
        continue;
      } else if (type === 1) {
        if (!fixedLit) {
          var l = new Uint8Array(288);
          for (var i = 0; i < 288; i++) l[i] = i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8;
          fixedLit = huffman(l, 288);
          var d = new Uint8Array(30).fill(5);
          fixedDist = huffman(d, 30);
        }
        lit = fixedLit; dist = fixedDist;
      } else if (type === 2) {
        var nlen = bits(5) + 257, ndist = bits(5) + 1, ncode = bits(4) + 4;
        var lengths = new Uint8Array(320);
        for (i = 0; i < ncode; i++) lengths[ORDER[i]] = bits(3);
        var codes = huffman(lengths, 19);
        lengths = new Uint8Array(320);
        for (i = 0; i < nlen + ndist;) {
          var sym = decode(codes);
          if (sym < 16) { lengths[i++] = sym; continue; }
          var value = 0, repeat;
          if (sym === 16) { value = lengths[i - 1]; repeat = 3 + bits(2); }
          else if (sym === 17) repeat = 3 + bits(3);
          else repeat = 11 + bits(7);
          while (repeat--) lengths[i++] = value;
        }
        lit = huffman(lengths.subarray(0, nlen), nlen);
        dist = huffman(lengths.subarray(nlen, nlen + ndist), ndist);
      } else {
        throw new Error("the embedded module is corrupt (block type 3)");
      }
      for (;;) {
        var s = decode(lit);
        if (s < 256) { out[op++] = s; continue; }
        if (s === 256) break;
        s -= 257;
        var length = LBASE[s] + bits(LEXT[s]);
        var ds = decode(dist);
        var from = op - (DBASE[ds] + bits(DEXT[ds]));
        while (length--) out[op++] = out[from++];
      }
    } while (!last);
    if (op !== size) throw new Error("the embedded module has " + op + " bytes, not " + size);
    return out;
  }

  // ------------------------------------------------------------ the module
  var engine = null;
  function start() {
    var s = atob(spec.module);
    var packed = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) packed[i] = s.charCodeAt(i);
    var instance = new WebAssembly.Instance(new WebAssembly.Module(inflate(packed, spec.moduleBytes)), {});
    engine = instance.exports;
  }
  // One request, one reply (JSON both ways, through the module's memory).
  function call(request) {
    var bytes = new TextEncoder().encode(JSON.stringify(request));
    var at = engine.mb_alloc(bytes.length);
    new Uint8Array(engine.memory.buffer, at, bytes.length).set(bytes);
    var length;
    try {
      length = engine.mb_call(at, bytes.length);
    } catch (e) {
      // A trap: the engine panicked. Its message is kept; a new instance
      // starts clean for the next change.
      // mb_panic moves the message into the reply (it may grow the memory): read after it.
      var n = engine.mb_panic(), p = engine.mb_reply();
      var message = new TextDecoder().decode(new Uint8Array(engine.memory.buffer, p, n));
      start();
      call(loadRequest());
      return { ok: false, error: "the engine failed (" + (message || e) + "); please report it with the model file" };
    }
    engine.mb_free(at, bytes.length);
    var reply = engine.mb_reply();
    var text = new TextDecoder().decode(new Uint8Array(engine.memory.buffer, reply, length));
    return JSON.parse(text);
  }
  function loadRequest() {
    return { op: "load", files: spec.files, analysis: spec.analysis || null, model: spec.model || null, signals: spec.signals };
  }

  // ------------------------------------------------------------ the panel
  var main = document.getElementById("mb-main");
  var panel = document.createElement("aside");
  panel.id = "mb-live";
  main.insertBefore(panel, main.firstChild);
  function element(tag, className, text, parent) {
    var e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }
  element("h2", null, "Model values", panel);
  var status = element("div", "mb-live-status", "Starting the engine\u2026", panel);
  var errorBox = element("pre", "mb-live-error", "", panel);
  errorBox.hidden = true;
  var fields = element("div", "mb-live-fields", undefined, panel);

  // What the user typed, by path; sent with every run (so a value stays
  // changed until it is changed back). Start values and parameters apart.
  var typed = {};
  var rows = {};
  var lastChanged = null;
  var last = null;
  var queued = false;

  function values() {
    var params = [], initials = [];
    Object.keys(typed).forEach(function (path) {
      var row = rows[path];
      var line = path + "=" + typed[path];
      if (row && row.kind === "start") initials.push(line); else params.push(line);
    });
    function extra(box, list) {
      box.value.split(/[\s,;]+/).forEach(function (w) { if (w) list.push(w); });
    }
    extra(moreParams, params);
    extra(moreInitials, initials);
    return { params: params, initials: initials };
  }

  function run() {
    var v = values();
    var request = { op: "run", params: v.params, initials: v.initials, stop: stopField.value.trim() };
    var began = performance.now();
    var reply = call(request);
    var ms = performance.now() - began;
    if (reply.ok) {
      viewer.setScene(reply.scene);
      var drawn = performance.now() - began;
      last = { final: reply.final, ms: ms, drawnMs: drawn, request: request, warnings: reply.warnings };
      cleared();
      status.textContent = "t = 0 \u2026 " + reply.stop + " s, run in " + ms.toFixed(0) + " ms" +
        (reply.warnings.length ? " \u2014 " + reply.warnings.join("; ") : "");
      console.log("multibody-live: ran " + request.params.concat(request.initials).join(" ") + " stop=" + reply.stop +
        " ms=" + ms.toFixed(2));
    } else {
      if (lastChanged && rows[lastChanged]) rows[lastChanged].text.classList.add("mb-live-bad");
      refused(reply.error);
    }
    window.__multibodyLive.last = last;
    return reply;
  }
  // Slider drags come faster than runs: one run is queued at a time, and
  // it reads the values as they are when it starts.
  function schedule() {
    // A changed value ends a run in real time: the whole run shows it.
    if (stepping) stopRealTime("");
    if (queued) return;
    queued = true;
    setTimeout(function () { queued = false; run(); }, 0);
  }

  function shortest(x) {
    var s = String(x);
    return s.length > 12 ? String(Number(x.toPrecision(6))) : s;
  }

  function addRow(box, t) {
    var row = element("div", "mb-live-row", undefined, box);
    var label = element("label", null, t.path, row);
    if (t.unit) element("span", "mb-live-unit", " [" + t.unit + "]", label);
    label.title = (t.doc ? t.doc + "\n" : "") + (t.kind === "start" ? "start value" : "parameter") +
      (t.derived ? " (computed from other values: a value here replaces that)" : "") +
      (t.min !== null && t.min !== undefined ? "\nmin " + t.min : "") + (t.max !== null && t.max !== undefined ? "\nmax " + t.max : "");
    var text = element("input", "mb-live-text", undefined, row);
    text.type = "text";
    text.inputMode = "decimal";
    text.spellcheck = false;
    text.setAttribute("aria-label", t.path);
    var given = given0[t.path];
    text.value = given !== undefined ? given : shortest(t.value);
    if (given !== undefined) typed[t.path] = given;
    var slider = element("input", "mb-live-slider", undefined, row);
    slider.type = "range";
    var span = Math.abs(t.value) > 0 ? Math.abs(t.value) : 1;
    var lo = t.min !== null && t.min !== undefined ? t.min : (t.value > 0 ? 0 : t.value - span);
    var hi = t.max !== null && t.max !== undefined ? t.max : t.value + span;
    if (!(hi > lo)) hi = lo + 1;
    slider.min = String(lo);
    slider.max = String(hi);
    slider.step = t.integer ? "1" : String((hi - lo) / 200);
    slider.value = String(parseFloat(text.value));
    slider.setAttribute("aria-label", t.path + " slider");
    rows[t.path] = { kind: t.kind, text: text, slider: slider, value: t.value };
    text.addEventListener("change", function () {
      typed[t.path] = text.value;
      lastChanged = t.path;
      var x = parseFloat(text.value);
      if (isFinite(x)) slider.value = String(x);
      schedule();
    });
    slider.addEventListener("input", function () {
      text.value = shortest(parseFloat(slider.value));
      typed[t.path] = text.value;
      lastChanged = t.path;
      schedule();
    });
  }

  // The command line's values, by path: the panel starts with them.
  var given0 = {};
  (spec.params || []).concat(spec.initials || []).forEach(function (line) {
    var k = line.indexOf("=");
    if (k > 0) given0[line.slice(0, k).trim()] = line.slice(k + 1).trim();
  });

  var stopField, moreParams, moreInitials;
  function buildPanel(model) {
    var groups = [["parameter", "Parameters"], ["start", "Start values"]];
    groups.forEach(function (g) {
      var list = model.tunables.filter(function (t) { return t.kind === g[0]; });
      if (!list.length) return;
      element("h3", null, g[1], fields);
      list.forEach(function (t) { addRow(fields, t); });
    });
    element("h3", null, "Run", fields);
    var row = element("div", "mb-live-row", undefined, fields);
    element("label", null, "stop time [s]", row);
    stopField = element("input", "mb-live-text", undefined, row);
    stopField.type = "text";
    stopField.inputMode = "decimal";
    stopField.setAttribute("aria-label", "stop time");
    stopField.value = spec.stop !== undefined ? shortest(spec.stop) : shortest(model.stop);
    stopField.addEventListener("change", function () { lastChanged = null; schedule(); });
    // Any other value by its path, as the command line takes it.
    [["--param", "body.m=2 link1.d=0.5"], ["--initial", "rev.phi=0.3"]].forEach(function (o, k) {
      var more = element("div", "mb-live-row mb-live-more", undefined, fields);
      element("label", null, o[0], more);
      var box = element("input", "mb-live-text", undefined, more);
      box.type = "text";
      box.placeholder = o[1];
      box.spellcheck = false;
      box.setAttribute("aria-label", "more " + o[0]);
      var extra = Object.keys(given0).filter(function (p) { return !rows[p]; }).filter(function (p) {
        var line = p + "=" + given0[p];
        return (k === 0 ? spec.params || [] : spec.initials || []).some(function (l) { return l.replace(/\s/g, "") === line.replace(/\s/g, ""); });
      });
      box.value = extra.map(function (p) { return p + "=" + given0[p]; }).join(" ");
      box.addEventListener("change", function () { lastChanged = null; schedule(); });
      if (k === 0) moreParams = box; else moreInitials = box;
    });
    // Real time: the page steps the model as the clock goes, and the
    // model's inputs (its top-level RealInputs) act while it runs.
    element("h3", null, model.inputs.length ? "Real time, with the inputs" : "Real time", fields);
    model.inputs.forEach(addInputRow);
    realTimeButton = element("button", null, "Run in real time \u25b6", fields);
    realTimeButton.type = "button";
    realTimeButton.addEventListener("click", function () { if (stepping) stopRealTime(""); else startRealTime(); });
    element("br", null, undefined, fields);
    var reset = element("button", null, "Back to the file's values", fields);
    reset.type = "button";
    reset.addEventListener("click", function () {
      typed = {};
      Object.keys(rows).forEach(function (p) {
        rows[p].text.value = shortest(rows[p].value);
        rows[p].slider.value = String(rows[p].value);
      });
      moreParams.value = ""; moreInitials.value = "";
      stopField.value = shortest(model.stop);
      lastChanged = null;
      schedule();
    });
  }

  // ------------------------------------------------------------ real time
  var inputs = {}, inputRows = {}, touchedInputs = {};
  var stepping = null, realTimeButton = null;
  function addInputRow(name) {
    var row = element("div", "mb-live-row", undefined, fields);
    element("label", null, name + " (input)", row);
    var text = element("input", "mb-live-text", undefined, row);
    text.type = "text";
    text.inputMode = "decimal";
    text.value = "0";
    text.setAttribute("aria-label", name);
    var slider = element("input", "mb-live-slider", undefined, row);
    slider.type = "range";
    slider.min = "-10";
    slider.max = "10";
    slider.step = "0.01";
    slider.value = "0";
    slider.setAttribute("aria-label", name + " slider");
    inputs[name] = 0;
    inputRows[name] = { text: text, slider: slider };
    text.addEventListener("change", function () {
      var x = parseFloat(text.value);
      if (!isFinite(x)) { text.classList.add("mb-live-bad"); return; }
      text.classList.remove("mb-live-bad");
      // A typed value beyond the slider widens it.
      if (x < parseFloat(slider.min)) slider.min = String(x);
      if (x > parseFloat(slider.max)) slider.max = String(x);
      slider.value = String(x);
      inputs[name] = x;
      touchedInputs[name] = true;
    });
    slider.addEventListener("input", function () {
      inputs[name] = parseFloat(slider.value);
      touchedInputs[name] = true;
      text.value = shortest(inputs[name]);
      text.classList.remove("mb-live-bad");
    });
  }
  function setInput(name, value) {
    inputs[name] = value;
    if (inputRows[name]) { inputRows[name].text.value = shortest(value); inputRows[name].slider.value = String(value); }
  }
  function startRealTime() {
    var v = values();
    var reply = call({ op: "start", params: v.params, initials: v.initials, stop: stopField.value.trim() });
    if (!reply.ok) { refused(reply.error); return null; }
    cleared();
    // The model's own input values, where the user set none.
    reply.inputs.forEach(function (i) { if (!touchedInputs[i.name]) setInput(i.name, i.value); });
    stepping = { wall: performance.now(), start: describedModel.start, steps: 0, slowest: 0, frame: 0 };
    realTimeButton.textContent = "Stop \u25a0";
    viewer.pause();
    if (!query.has("livestep")) stepping.frame = window.requestAnimationFrame(stepFrame);
    return reply;
  }
  function stopRealTime(why) {
    if (stepping && stepping.frame) window.cancelAnimationFrame(stepping.frame);
    stepping = null;
    if (realTimeButton) realTimeButton.textContent = "Run in real time \u25b6";
    if (why) status.textContent = why;
  }
  // One step to `until`, with the inputs as they are now.
  function stepTo(until) {
    var began = performance.now();
    if (!stepping) return { ok: false, error: "no run in real time is going: start one first" };
    var reply = call({ op: "step", until: until, inputs: inputs });
    var ms = performance.now() - began;
    if (!reply.ok) { stopRealTime(""); refused(reply.error); return reply; }
    cleared();
    stepping.steps++;
    stepping.slowest = Math.max(stepping.slowest, ms);
    viewer.setScene(reply.scene, true);
    viewer.setTime(reply.stop);
    last = { final: reply.final, ms: ms, drawnMs: performance.now() - began, request: { inputs: inputs }, warnings: reply.warnings };
    window.__multibodyLive.last = last;
    status.textContent = "t = " + reply.stop.toFixed(2) + " s, in real time (" + stepping.steps + " steps, the slowest " +
      stepping.slowest.toFixed(0) + " ms)";
    if (reply.stop >= describedStop() - 1e-12) stopRealTime("Reached the stop time after " + stepping.steps + " steps.");
    return reply;
  }
  function stepFrame(now) {
    if (!stepping) return;
    // A frame's time may come before the click that started the run.
    var until = stepping.start + (now - stepping.wall) / 1000;
    if (until > stepping.start) stepTo(until);
    if (stepping) stepping.frame = window.requestAnimationFrame(stepFrame);
  }
  function describedStop() {
    var x = parseFloat(stopField.value);
    return isFinite(x) ? x : describedModel.stop;
  }
  function cleared() {
    errorBox.hidden = true;
    panel.classList.remove("mb-live-failed");
    Object.keys(rows).forEach(function (p) { rows[p].text.classList.remove("mb-live-bad"); });
    window.__multibodyLive.error = null;
  }
  function refused(error) {
    errorBox.textContent = error;
    errorBox.hidden = false;
    panel.classList.add("mb-live-failed");
    status.textContent = "Not run: see below. The view shows the last good run.";
    console.log("multibody-live: refused " + JSON.stringify(error));
    window.__multibodyLive.error = error;
  }

  window.__multibodyLive = {
    last: null,
    error: null,
    // Types `text` into the field of `path` (the stop time for "stop", the
    // `--param` field for a path not in the panel) and runs at once.
    set: function (path, text) {
      if (path === "stop") { stopField.value = text; lastChanged = null; return run(); }
      var row = rows[path];
      if (!row) {
        // Not in the panel: as typed into the `--param` field.
        moreParams.value = (moreParams.value + " " + path + "=" + text).trim();
        lastChanged = null;
        return run();
      }
      row.text.value = text;
      typed[path] = text;
      lastChanged = path;
      return run();
    },
    run: function () { return run(); },
    // Real time, driven by hand: start, then step to a time with an input set.
    start: function () { return startRealTime(); },
    step: function (until) { return stepTo(until); },
    setInput: setInput
  };
  var describedModel = null;

  try {
    var began = performance.now();
    start();
    var loaded = call(loadRequest());
    if (!loaded.ok) throw new Error(loaded.error);
    describedModel = loaded.model;
    buildPanel(loaded.model);
    status.textContent = "Ready (engine started in " + (performance.now() - began).toFixed(0) +
      " ms): change a value and the model runs again.";
    window.__multibodyLive.model = loaded.model;
    console.log("multibody-live: ready in " + (performance.now() - began).toFixed(1) + " ms, " +
      loaded.model.tunables.length + " values");
  } catch (e) {
    status.textContent = "The live engine could not start: " + e.message + ". The page still plays the first run.";
    report("live: " + e.message);
    return;
  }

  if (query.has("live")) {
    query.get("live").split(";").forEach(function (item) {
      var k = item.indexOf("=");
      if (k > 0) window.__multibodyLive.set(item.slice(0, k), item.slice(k + 1));
    });
    var r = window.__multibodyLive;
    if (r.error === null && r.last) {
      var finals = Object.keys(r.last.final).filter(function (n) { return /\.(phi|w|s|v)$/.test(n); });
      console.log("multibody-live: final " + finals.map(function (n) { return n + "=" + r.last.final[n]; }).join(" "));
    }
  }
  if (query.has("realtime")) startRealTime();
  if (query.has("livestep")) {
    var dt = parseFloat(query.get("livestep"));
    var plan = (query.get("liveinput") || "").match(/^([^=]+)=([^@]+)@([^=]+)=(.+)$/);
    if (startRealTime()) {
      var stop = describedStop(), k = 0, reply;
      for (;;) {
        var t = describedModel.start + (++k) * dt;
        if (t > stop) t = stop;
        // The input for the step that ends at t: V0 up to T1, V1 after.
        if (plan) setInput(plan[1], t <= parseFloat(plan[3]) + 1e-9 ? parseFloat(plan[2]) : parseFloat(plan[4]));
        reply = stepTo(t);
        if (!reply.ok || t >= stop) break;
      }
      if (reply.ok) {
        console.log("multibody-live: stepped " + k + " final " + Object.keys(reply.final).map(function (n) {
          return n + "=" + reply.final[n];
        }).join(" "));
      }
    }
  }
  if (query.has("livebench")) {
    var n = Math.max(1, parseInt(query.get("livebench"), 10) || 10);
    var path = Object.keys(rows)[0] || "stop";
    var base = path === "stop" ? describedStop() : rows[path].value;
    var times = [];
    for (var b = 0; b < n; b++) {
      window.__multibodyLive.set(path, shortest(base * (1 + 0.01 * ((b % 2) ? 1 : -1))));
      times.push(window.__multibodyLive.last.drawnMs);
    }
    window.__multibodyLive.set(path, shortest(base));
    times.sort(function (a, b) { return a - b; });
    console.log("multibody-live: bench runs=" + n + " median_ms=" + times[n >> 1].toFixed(2) + " max_ms=" +
      times[n - 1].toFixed(2));
  }
})();
