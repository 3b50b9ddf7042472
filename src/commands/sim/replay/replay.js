// mapc replay player: draws the run kept in #data on the level pictures of `mapc render`.
// Plain DOM and SVG, no library. URL hash: #t=SECONDS&level=NAME&speed=X&play=1&robot=NAME
"use strict";
(function () {
  const errors = document.getElementById("errors");
  const report = (m) => { errors.textContent += m + "\n"; };
  window.addEventListener("error", (e) => report("error: " + e.message));
  window.addEventListener("unhandledrejection", (e) => report("error: " + e.reason));
  const started = performance.now();
  const D = JSON.parse(document.getElementById("data").textContent);
  const TICK = D.tick, END = D.end;
  const $ = (id) => document.getElementById(id);
  const PALETTE = ["#e53935", "#1e88e5", "#43a047", "#8e24aa", "#fb8c00", "#00acc1", "#6d4c41", "#3949ab"];
  const MODES = ["idle", "charging", "moving", "paused", "waiting", "emergency", "going home",
    "docking", "adapter error", "cleaning", "performing action", "action completed"];
  const DOOR_MODES = ["closed", "moving", "open", "offline", "unknown"];
  const esc = (s) => String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  const hms = (t) => {
    t = Math.max(0, Math.round(t));
    const h = Math.floor(t / 3600), m = Math.floor(t / 60) % 60, s = t % 60;
    return h + ":" + String(m).padStart(2, "0") + ":" + String(s).padStart(2, "0");
  };

  // Value of a change list [tick, v, tick, v, ...] at time t (def before the first change).
  function at(list, t, def) {
    const k = t / TICK;
    let lo = 0, hi = list.length / 2 - 1, best = -1;
    while (lo <= hi) {
      const mid = (lo + hi) >> 1;
      if (list[2 * mid] <= k) { best = mid; lo = mid + 1; } else { hi = mid - 1; }
    }
    return best < 0 ? def : list[2 * best + 1];
  }

  // Robots: decode the delta tracks into arrays of seconds, metres and degrees.
  for (const r of D.robots) {
    const n = r.track.length / 4 + 1;
    r.T = new Float64Array(n); r.X = new Float64Array(n); r.Y = new Float64Array(n); r.A = new Float64Array(n);
    let [t, x, y, a] = r.first;
    r.T[0] = t * TICK; r.X[0] = x / 100; r.Y[0] = y / 100; r.A[0] = a;
    for (let i = 0, j = 1; i < r.track.length; i += 4, j++) {
      t += r.track[i]; x += r.track[i + 1]; y += r.track[i + 2]; a += r.track[i + 3];
      r.T[j] = t * TICK; r.X[j] = x / 100; r.Y[j] = y / 100; r.A[j] = a;
    }
    r.colour = PALETTE[(r.fleet < 0 ? 0 : r.fleet) % PALETTE.length];
  }
  function pose(r, t) {
    const T = r.T, n = T.length;
    if (t <= T[0]) return [r.X[0], r.Y[0], r.A[0]];
    if (t >= T[n - 1]) return [r.X[n - 1], r.Y[n - 1], r.A[n - 1]];
    let lo = 0, hi = n - 1;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid; }
    const f = (t - T[lo]) / (T[hi] - T[lo]);
    return [r.X[lo] + f * (r.X[hi] - r.X[lo]), r.Y[lo] + f * (r.Y[hi] - r.Y[lo]), r.A[lo] + f * (r.A[hi] - r.A[lo])];
  }

  // Levels: the pictures, each with a layer for the robots inside its map area.
  const mapEl = $("map");
  D.levels.forEach((L) => {
    const div = document.createElement("div");
    div.className = "level";
    div.innerHTML = L.svg;
    mapEl.appendChild(div);
    L.div = div;
    L.svg = div.querySelector("svg");
    const [k, minX, maxY, left, top] = L.view;
    L.px = (x, y) => [left + (x - minX) * k, top + (maxY - y) * k];
    L.k = k;
    L.doors = new Map();
    for (const g of div.querySelectorAll("g.door")) L.doors.set(g.dataset.door, g);
    L.cabins = new Map();
    for (const g of div.querySelectorAll("g.lift-cabin")) L.cabins.set(g.dataset.lift, g);
    L.cabinLabels = new Map();
    L.liftDoors = [...div.querySelectorAll("line.lift-door")];
  });
  const NS = D.levels.length ? D.levels[0].svg.namespaceURI : "";
  const el = (tag, attrs) => {
    const e = document.createElementNS(NS, tag);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    return e;
  };
  D.levels.forEach((L) => {
    L.layer = el("g", { class: "robots" });
    L.svg.querySelector("g.map").appendChild(L.layer);
    // Where each cabin is: a label at the cabin's centre (from its polygon's points).
    for (const [name, g] of L.cabins) {
      const poly = g.querySelector("polygon");
      const pts = (poly ? poly.getAttribute("points") : "").trim().split(/\s+/).map((p) => p.split(",").map(Number));
      const cx = pts.reduce((a, p) => a + p[0], 0) / Math.max(1, pts.length);
      const cy = pts.reduce((a, p) => a + p[1], 0) / Math.max(1, pts.length);
      const text = el("text", { x: cx.toFixed(1), y: (cy + 16).toFixed(1), "font-size": 11, "text-anchor": "middle",
        fill: "#1a237e", stroke: "#fff", "stroke-width": 3, "paint-order": "stroke", class: "cabin-label" });
      L.svg.querySelector("g.map").appendChild(text);
      L.cabinLabels.set(name, text);
    }
  });

  // People (from /rmf_obstacles, one sample per tick): positions in metres per sample.
  const P = D.people;
  if (P) {
    P.X = []; P.Y = []; P.g = [];
    const L = D.levels[P.level] || D.levels[0];
    const layer = el("g", { class: "people" });
    if (L) L.svg.querySelector("g.map").insertBefore(layer, L.layer);
    P.first.forEach(([x0, y0], i) => {
      const n = P.track[i].length / 2 + 1;
      const X = new Float64Array(n), Y = new Float64Array(n);
      let x = x0, y = y0;
      X[0] = x / 100; Y[0] = y / 100;
      for (let j = 1; j < n; j++) { x += P.track[i][2 * j - 2]; y += P.track[i][2 * j - 1]; X[j] = x / 100; Y[j] = y / 100; }
      P.X.push(X); P.Y.push(Y);
      const c = el("circle", { class: "person", r: 3, fill: "#8e24aa", "fill-opacity": 0.8, stroke: "#fff", "stroke-width": 1 });
      layer.appendChild(c);
      P.g.push(c);
    });
    P.L = L;
  }
  function drawPeople(t) {
    if (!P || !P.L) return;
    const s = t / TICK - P.start;
    P.g.forEach((c, i) => {
      const X = P.X[i], Y = P.Y[i], n = X.length;
      const a = Math.max(0, Math.min(n - 1, Math.floor(s))), b = Math.min(n - 1, a + 1);
      const f = Math.max(0, Math.min(1, s - a));
      const [px, py] = P.L.px(X[a] + f * (X[b] - X[a]), Y[a] + f * (Y[b] - Y[a]));
      c.setAttribute("cx", px.toFixed(1));
      c.setAttribute("cy", py.toFixed(1));
      c.setAttribute("r", Math.max(3, P.r[i] * P.L.k).toFixed(1));
    });
  }

  let selected = -1;
  for (const [i, r] of D.robots.entries()) {
    const g = el("g", { class: "robot" });
    g.appendChild(el("circle", { class: "sel", r: 1, fill: "none", stroke: "#ffca28", "stroke-width": 4 }));
    g.appendChild(el("circle", { class: "body", r: 1, fill: r.colour, "fill-opacity": 0.75, stroke: "#000", "stroke-width": 1 }));
    g.appendChild(el("line", { class: "heading", x1: 0, y1: 0, x2: 1, y2: 0, stroke: "#000", "stroke-width": 2 }));
    g.appendChild(el("rect", { class: "item", x: -4, y: -4, width: 8, height: 8, fill: "#fdd835", stroke: "#000", visibility: "hidden" }));
    const label = el("text", { class: "name", x: 0, y: 0, "font-size": 11, "font-weight": "bold", fill: "#000",
      stroke: "#fff", "stroke-width": 3, "paint-order": "stroke" });
    label.textContent = r.name;
    g.appendChild(label);
    g.addEventListener("click", (e) => { e.stopPropagation(); select(i); });
    r.g = g;
    r.levelShown = -2;
  }
  function select(i) {
    if (selected >= 0) D.robots[selected].g.classList.remove("selected");
    selected = i;
    if (i >= 0) D.robots[i].g.classList.add("selected");
    draw();
  }

  // Controls.
  const state = { t: 0, playing: false, speed: 60, level: 0 };
  $("title").textContent = D.building;
  const slider = $("time");
  slider.max = END;
  slider.addEventListener("input", () => { state.t = +slider.value; draw(); });
  $("speed").addEventListener("change", () => { state.speed = +$("speed").value; });
  const play = $("play");
  function setPlaying(p) {
    state.playing = p;
    play.innerHTML = p ? "&#10074;&#10074;" : "&#9654;";
    if (p) { last = null; requestAnimationFrame(frame); }
  }
  play.addEventListener("click", () => {
    if (!state.playing && state.t >= END) state.t = 0;
    setPlaying(!state.playing);
  });
  document.addEventListener("keydown", (e) => {
    if (e.key === " " && e.target.tagName !== "INPUT") { e.preventDefault(); play.click(); }
  });
  const levelButtons = D.levels.map((L, i) => {
    const b = document.createElement("button");
    b.addEventListener("click", () => { state.level = i; draw(); });
    $("levels").appendChild(b);
    return b;
  });
  let last = null;
  function frame(now) {
    if (!state.playing) return;
    if (last !== null) state.t = Math.min(END, state.t + (now - last) / 1000 * state.speed);
    last = now;
    draw();
    if (state.t >= END) setPlaying(false); else requestAnimationFrame(frame);
  }

  function draw() {
    const t = state.t;
    slider.value = t;
    $("clock").textContent = hms(t);
    const counts = D.levels.map(() => 0);
    drawPeople(t);
    for (const r of D.robots) {
      const lv = at(r.level, t, -1);
      if (lv < 0 || lv >= D.levels.length) { r.g.remove(); r.levelShown = -1; continue; }
      counts[lv]++;
      const L = D.levels[lv];
      if (r.levelShown !== lv) { L.layer.appendChild(r.g); r.levelShown = lv; }
      const [x, y, a] = pose(r, t);
      const [px, py] = L.px(x, y);
      const rad = Math.max(5, r.r * L.k);
      r.g.setAttribute("transform", "translate(" + px.toFixed(1) + "," + py.toFixed(1) + ")");
      const c = r.g.childNodes;
      c[0].setAttribute("r", rad + 3);
      c[1].setAttribute("r", rad);
      const ang = -a * Math.PI / 180;
      c[2].setAttribute("x2", (Math.cos(ang) * rad).toFixed(1));
      c[2].setAttribute("y2", (Math.sin(ang) * rad).toFixed(1));
      c[3].setAttribute("visibility", at(r.carry, t, 0) ? "visible" : "hidden");
      c[4].setAttribute("x", rad + 2);
      c[4].setAttribute("y", -rad - 2);
    }
    levelButtons.forEach((b, i) => {
      b.textContent = D.levels[i].name + " (" + counts[i] + ")";
      b.classList.toggle("on", i === state.level);
    });
    D.levels.forEach((L, i) => L.div.classList.toggle("on", i === state.level));
    for (const d of D.doors) {
      const mode = at(d.modes, t, 0);
      for (const L of D.levels) {
        const g = L.doors.get(d.name);
        if (!g) continue;
        g.classList.toggle("open", mode === 2);
        g.classList.toggle("moving", mode === 1);
      }
    }
    for (const lift of D.lifts) {
      const s = lift.state;
      let i = -1;
      for (let lo = 0, hi = s.length / 5 - 1; lo <= hi;) {
        const mid = (lo + hi) >> 1;
        if (s[5 * mid] <= t / TICK) { i = mid; lo = mid + 1; } else { hi = mid - 1; }
      }
      const floor = i < 0 ? -1 : s[5 * i + 1], door = i < 0 ? 0 : s[5 * i + 2];
      const motion = i < 0 ? 0 : s[5 * i + 3], dest = i < 0 ? -1 : s[5 * i + 4];
      const name = (k) => (k >= 0 && k < D.levels.length ? D.levels[k].name : "?");
      D.levels.forEach((L, li) => {
        const g = L.cabins.get(lift.name);
        if (g) {
          g.classList.toggle("away", i >= 0 && floor !== li);
          g.classList.toggle("moving", motion !== 0);
        }
        const label = L.cabinLabels.get(lift.name);
        if (label) {
          label.textContent = i < 0 ? "" : motion !== 0 ? name(floor) + " \u2192 " + name(dest)
            : floor !== li ? "cabin at " + name(floor) : door === 2 ? "open" : "";
        }
        for (const ld of L.liftDoors) {
          if (ld.dataset.lift === lift.name) ld.classList.toggle("open", floor === li && door === 2);
        }
      });
    }
    for (const c of document.querySelectorAll("line.cursor")) {
      const x = c.dataset.x0 * 1 + (t / Math.max(END, 1)) * c.dataset.w;
      c.setAttribute("x1", x); c.setAttribute("x2", x);
    }
    info(t);
  }

  function info(t) {
    if (selected < 0) return;
    const r = D.robots[selected];
    const lv = at(r.level, t, -1);
    const task = at(r.task, t, -1);
    const tk = task >= 0 ? D.tasks[task] : null;
    let s = r.name + " (" + (D.fleets[r.fleet] || "?") + ")\n";
    s += "level " + (lv >= 0 ? D.levels[lv].name : "?") + ", " + (MODES[at(r.mode, t, 0)] || "?");
    s += ", battery " + at(r.battery, t, "?") + " %" + (at(r.carry, t, 0) ? ", carrying an item" : "") + "\n";
    if (tk) {
      s += "task " + tk.id + " (" + tk.cat + "), started " + hms(tk.s || 0);
      s += tk.e != null && tk.e <= t ? ", " + (tk.ok ? "completed" : "failed") + " at " + hms(tk.e) : ", in progress";
      if (tk.detail) s += "\n" + tk.detail;
    } else {
      s += "no task";
    }
    $("info").textContent = s;
  }

  // Charts: plain SVG strings; time charts carry a cursor line moved by draw().
  const W = 440;
  const axis = (x0, y0, w, h) => '<line x1="' + x0 + '" y1="' + (y0 + h) + '" x2="' + (x0 + w) + '" y2="' + (y0 + h) +
    '" stroke="#999"/><line x1="' + x0 + '" y1="' + y0 + '" x2="' + x0 + '" y2="' + (y0 + h) + '" stroke="#999"/>';
  const txt = (x, y, s, a) => '<text x="' + x + '" y="' + y + '" font-size="10" fill="#444"' + (a ? ' text-anchor="' + a + '"' : "") + ">" + esc(s) + "</text>";
  const cursor = (x0, y0, w, h) => '<line class="cursor" data-x0="' + x0 + '" data-w="' + w + '" x1="' + x0 + '" y1="' + y0 +
    '" x2="' + x0 + '" y2="' + (y0 + h) + '" stroke="#d32f2f" stroke-width="1.5"/>';
  const timeAxis = (x0, y, w) => txt(x0, y, "0:00:00") + txt(x0 + w, y, hms(END), "end");
  const chart = (id, h, body) => { $(id).innerHTML = '<svg width="' + W + '" height="' + h + '">' + body + "</svg>"; };

  for (const t of D.tasks) if (!t.cat) t.cat = "other";
  const CATS = [...new Set(D.tasks.map((t) => t.cat))];
  (function gantt() {
    const x0 = 90, w = W - x0 - 10, row = 13, h = D.robots.length * row + 44;
    let s = axis(x0, 4, w, h - 40);
    D.robots.forEach((r, i) => { s += txt(x0 - 4, 4 + i * row + 10, r.name, "end"); });
    const sx = (t) => x0 + t / Math.max(END, 1) * w;
    for (const tk of D.tasks) {
      if (tk.robot < 0 || tk.s == null) continue;
      const e = tk.e != null ? tk.e : END;
      const col = PALETTE[(CATS.indexOf(tk.cat) + 3) % PALETTE.length];
      s += '<rect x="' + sx(tk.s).toFixed(1) + '" y="' + (5 + tk.robot * row) + '" width="' + Math.max(1, sx(e) - sx(tk.s)).toFixed(1) +
        '" height="' + (row - 3) + '" fill="' + col + '"' + (tk.ok === false ? ' stroke="#d32f2f" stroke-width="1.5"' : "") +
        "><title>" + esc(tk.id + " " + tk.cat + " " + hms(tk.s) + "-" + hms(e)) + "</title></rect>";
    }
    s += timeAxis(x0, h - 24, w) + cursor(x0, 4, w, h - 40);
    CATS.forEach((c, i) => {
      s += '<rect x="' + (x0 + i * 90) + '" y="' + (h - 12) + '" width="8" height="8" fill="' + PALETTE[(i + 3) % PALETTE.length] + '"/>' + txt(x0 + 11 + i * 90, h - 4, c);
    });
    chart("gantt", h + 4, s);
  })();

  (function latency() {
    const v = D.tasks.filter((t) => t.ok && t.q != null && t.e != null).map((t) => t.e - t.q).sort((a, b) => a - b);
    const h = 130, x0 = 40, w = W - x0 - 10, y0 = 8, ph = h - 36;
    let s = axis(x0, y0, w, ph);
    if (v.length) {
      const max = Math.max(v[v.length - 1], 1), bins = 20, counts = new Array(bins).fill(0);
      for (const x of v) counts[Math.min(bins - 1, Math.floor(x / max * bins))]++;
      const cmax = Math.max(...counts);
      counts.forEach((c, i) => {
        const bh = c / cmax * ph;
        s += '<rect x="' + (x0 + i * w / bins + 1).toFixed(1) + '" y="' + (y0 + ph - bh).toFixed(1) + '" width="' + (w / bins - 2).toFixed(1) + '" height="' + bh.toFixed(1) + '" fill="#1e88e5"/>';
      });
      s += txt(x0, h - 16, "0") + txt(x0 + w, h - 16, hms(max), "end") + txt(x0 - 4, y0 + 8, cmax, "end");
      s += txt(x0 + w / 2, h - 4, v.length + " tasks, median " + hms(v[v.length >> 1]), "middle");
    } else {
      s += txt(x0 + w / 2, y0 + ph / 2, "no completed task", "middle");
    }
    chart("latency", h, s);
  })();

  (function utilisation() {
    const row = 13, x0 = 90, w = W - x0 - 50, h = D.robots.length * row + 8;
    let s = "";
    D.robots.forEach((r, i) => {
      let busy = 0;
      for (let j = 0; j < r.task.length; j += 2) {
        if (r.task[j + 1] < 0) continue;
        const a = r.task[j] * TICK, b = j + 2 < r.task.length ? r.task[j + 2] * TICK : END;
        busy += b - a;
      }
      const f = END > 0 ? busy / END : 0;
      s += txt(x0 - 4, 4 + i * row + 10, r.name, "end");
      s += '<rect x="' + x0 + '" y="' + (5 + i * row) + '" width="' + (f * w).toFixed(1) + '" height="' + (row - 3) + '" fill="' + r.colour + '"/>';
      s += txt(x0 + f * w + 4, 4 + i * row + 10, Math.round(f * 100) + " %");
    });
    chart("util", h, s);
  })();

  (function waits() {
    const series = D.doors.map((d) => ({ name: d.name, w: d.waits })).concat(D.lifts.map((l) => ({ name: l.name + " (lift)", w: l.waits })))
      .filter((x) => x.w.length);
    const x0 = 40, w = W - x0 - 10, y0 = 8, ph = 110;
    let max = 1;
    for (const x of series) for (let i = 1; i < x.w.length; i += 2) max = Math.max(max, x.w[i]);
    let s = axis(x0, y0, w, ph) + txt(x0 - 4, y0 + 8, Math.round(max) + " s", "end") + txt(x0 - 4, y0 + ph, "0", "end");
    series.forEach((x, k) => {
      const col = PALETTE[k % PALETTE.length];
      for (let i = 0; i < x.w.length; i += 2) {
        s += '<circle cx="' + (x0 + x.w[i] / Math.max(END, 1) * w).toFixed(1) + '" cy="' + (y0 + ph - x.w[i + 1] / max * ph).toFixed(1) + '" r="2" fill="' + col + '"/>';
      }
    });
    s += timeAxis(x0, y0 + ph + 12, w) + cursor(x0, y0, w, ph);
    let y = y0 + ph + 26;
    series.forEach((x, k) => {
      let m = 0, sum = 0;
      for (let i = 1; i < x.w.length; i += 2) { m = Math.max(m, x.w[i]); sum += x.w[i]; }
      s += '<rect x="' + x0 + '" y="' + (y - 8) + '" width="8" height="8" fill="' + PALETTE[k % PALETTE.length] + '"/>' +
        txt(x0 + 12, y, x.name + ": " + x.w.length / 2 + " waits, mean " + (sum / (x.w.length / 2)).toFixed(1) + " s, max " + m.toFixed(1) + " s");
      y += 13;
    });
    if (!series.length) s += txt(x0 + w / 2, y0 + ph / 2, "no door or lift was used", "middle");
    chart("waits", y + 4, s);
  })();

  (function battery() {
    const x0 = 40, w = W - x0 - 10, y0 = 8, ph = 110;
    let s = axis(x0, y0, w, ph) + txt(x0 - 4, y0 + 8, "100 %", "end") + txt(x0 - 4, y0 + ph, "0", "end");
    for (const r of D.robots) {
      const b = r.battery;
      if (!b.length) continue;
      let pts = "";
      for (let i = 0; i < b.length; i += 2) {
        pts += (x0 + b[i] * TICK / Math.max(END, 1) * w).toFixed(1) + "," + (y0 + ph - b[i + 1] / 100 * ph).toFixed(1) + " ";
      }
      pts += (x0 + w) + "," + (y0 + ph - b[b.length - 1] / 100 * ph).toFixed(1);
      s += '<polyline points="' + pts + '" fill="none" stroke="' + r.colour + '" stroke-width="1"><title>' + esc(r.name) + "</title></polyline>";
    }
    s += timeAxis(x0, y0 + ph + 12, w) + cursor(x0, y0, w, ph);
    chart("battery", ph + 26, s);
  })();

  // Start: time, level and robot from the URL hash (so tests and links can choose them).
  const hash = new URLSearchParams(location.hash.slice(1));
  if (hash.has("t")) state.t = Math.min(END, Math.max(0, +hash.get("t") || 0));
  if (hash.has("speed")) { state.speed = +hash.get("speed") || 60; $("speed").value = String(state.speed); }
  const named = D.levels.findIndex((L) => L.name === hash.get("level"));
  if (named >= 0) state.level = named;
  else if (D.robots.length) state.level = Math.max(0, at(D.robots[0].level, state.t, 0));
  const rsel = D.robots.findIndex((r) => r.name === hash.get("robot"));
  mapEl.addEventListener("click", () => select(-1));
  draw();
  if (rsel >= 0) select(rsel);
  if (hash.get("play") === "1") setPlaying(true);
  // performance.now() counts from the start of navigation: reading the file included.
  $("status").textContent = "ready in " + Math.round(performance.now()) + " ms (script " +
    Math.round(performance.now() - started) + " ms)";
  document.body.dataset.ready = "1";
})();
