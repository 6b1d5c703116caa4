/* hosedrogue fly: the live page. It draws the frames its server streams (Server-Sent Events on
 * /events) with three.js, shows the pilot's head-up display, and sends the pilot's command, from
 * the keyboard or a gamepad (the Gamepad API), to /input; /control starts, pauses and ends flights.
 * The libraries come as the global HDV (vendor.min.js, as in the viewer).
 *
 * Frames: the data are in S_p (x forward, y right, z down); three.js draws in (X forward, Y up,
 * Z right), the same right-handed frame turned: X = x, Y = -z, Z = y (as viewer.js).
 */
(function () {
  "use strict";
  const H = window.HDV;
  const F = JSON.parse(document.getElementById("hd-facts").textContent);
  const PROBE_MAST_M = 1.5; // drawn length of the probe aft of its tip [m] (a marker, as in the viewer)
  const BASKET_DEPTH_M = 0.6; // drawn depth of the drogue's cone [m] (a marker; its diameter is the model's)
  const HOSE_COLOR = "#1f5fae";
  const CLOSURE_STEP = 0.25; // closure speed set point step of E / Q [m/s]
  const DEAD_ZONE = 0.12; // gamepad stick dead zone [-]
  const HEARTBEAT_MS = 250; // the command is sent again this often while nothing changes [ms]
  const CHART_POINTS = 6000; // samples kept on the chart (2 minutes at 50 Hz)

  // ---- state ----------------------------------------------------------------------------------
  let frame = null, status = { state: "connecting", flights: [] }, frames = 0, drawn = 0, dirty = true;
  let setpoint = F.closure_speed_m_s; // closure speed command [m/s]
  const keys = new Set();
  let lastSent = "", seqBase = Math.round((performance.timeOrigin + performance.now()) * 1000), seqCount = 0;
  let source = "keyboard", serverGone = false, loadedAt = null;

  // ---- the 3D scene ---------------------------------------------------------------------------
  const canvas = document.getElementById("view3d"), stage = document.getElementById("stage");
  function softwareGL() {
    try {
      const gl = document.createElement("canvas").getContext("webgl2") || document.createElement("canvas").getContext("webgl");
      const ext = gl.getExtension("WEBGL_debug_renderer_info");
      const name = String(gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
      const lose = gl.getExtension("WEBGL_lose_context");
      if (lose) lose.loseContext();
      return /swiftshader|llvmpipe|software/i.test(name);
    } catch (err) {
      return false;
    }
  }
  let renderer = null;
  try {
    renderer = new H.WebGLRenderer({ canvas, antialias: !softwareGL() });
  } catch (err) {
    stage.insertAdjacentHTML("beforeend", '<p class="chart-note" style="position:absolute;top:60%;left:10%">' +
      "WebGL is not available in this browser, so the 3D view is off; the head-up display works.</p>");
  }
  const toThree = (v, x, y, z) => v.set(x, -z, y);
  const scene = new H.Scene();
  scene.background = new H.Color("#dfe7f0");
  scene.add(new H.AmbientLight(0xffffff, 1.6));
  const sun = new H.DirectionalLight(0xffffff, 2.0);
  sun.position.set(-3, 10, 6);
  scene.add(sun);
  const mat = (color, opts) => new H.MeshLambertMaterial(Object.assign({ color: new H.Color(color) }, opts || {}));
  const UP = new H.Vector3(0, 1, 0);
  const tA = new H.Vector3(), tB = new H.Vector3(), tD = new H.Vector3(), tS = new H.Vector3();
  const tQ = new H.Quaternion(), tM = new H.Matrix4();

  let hose = null, capacity = 0;
  function hoseMesh(links) { // instanced links; grown when a remesh adds links
    if (hose && links <= capacity) return hose;
    if (hose) { scene.remove(hose); hose.geometry.dispose(); }
    capacity = Math.max(links * 2, 32);
    hose = new H.InstancedMesh(new H.CylinderGeometry(1, 1, 1, 8, 1, false), mat(HOSE_COLOR), capacity);
    hose.instanceMatrix.setUsage(H.DynamicDrawUsage);
    hose.frustumCulled = false;
    scene.add(hose);
    return hose;
  }
  const tow = new H.Mesh(new H.SphereGeometry(0.12, 16, 12), mat("#333a44"));
  const drogue = new H.Group();
  const rD = F.drogue_diameter_m / 2;
  const cone = new H.Mesh(new H.ConeGeometry(rD, BASKET_DEPTH_M, 32, 1, true),
    mat(HOSE_COLOR, { transparent: true, opacity: 0.45, side: H.DoubleSide, depthWrite: false }));
  cone.rotation.x = Math.PI;
  cone.position.y = BASKET_DEPTH_M / 2;
  const ring = new H.Mesh(new H.TorusGeometry(rD, 0.02, 8, 48), mat(HOSE_COLOR));
  ring.rotation.x = Math.PI / 2;
  ring.position.y = BASKET_DEPTH_M;
  drogue.add(cone, ring);
  const probe = new H.Group();
  const mast = new H.Mesh(new H.CylinderGeometry(0.04, 0.05, PROBE_MAST_M, 12), mat("#59606b"));
  mast.rotation.z = Math.PI / 2;
  mast.position.x = -PROBE_MAST_M / 2;
  const tip = new H.Mesh(new H.SphereGeometry(0.07, 16, 12), mat("#d0342c"));
  probe.add(mast, tip);
  scene.add(tow, drogue, probe);
  const COUPLED = new H.Color("#1f9d55"), FREE = new H.Color("#d0342c");
  let grid = null;

  function bytes(b64) {
    const s = atob(b64);
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u;
  }

  function updateScene(f) {
    const J = new Float32Array(bytes(f.joints).buffer), n = f.count, r = F.hose_diameter_m / 2;
    const mesh = hoseMesh(n - 1);
    for (let j = 0; j + 1 < n; j++) {
      toThree(tA, J[3 * j], J[3 * j + 1], J[3 * j + 2]);
      toThree(tB, J[3 * j + 3], J[3 * j + 4], J[3 * j + 5]);
      tD.subVectors(tB, tA);
      const len = tD.length();
      tQ.setFromUnitVectors(UP, tD.multiplyScalar(1 / Math.max(len, 1e-12)));
      tM.compose(tA.add(tB).multiplyScalar(0.5), tQ, tS.set(r, len, r));
      mesh.setMatrixAt(j, tM);
    }
    mesh.count = n - 1;
    mesh.instanceMatrix.needsUpdate = true;
    toThree(tow.position, J[0], J[1], J[2]);
    toThree(tA, J[3 * n - 6], J[3 * n - 5], J[3 * n - 4]);
    toThree(tB, J[3 * n - 3], J[3 * n - 2], J[3 * n - 1]);
    drogue.position.copy(tB);
    drogue.quaternion.setFromUnitVectors(UP, tD.subVectors(tB, tA).normalize());
    toThree(probe.position, f.probe[0], f.probe[1], f.probe[2]);
    tip.material.color.copy(f.coupled ? COUPLED : FREE);
    if (!grid) placeScene(J, n, f.probe);
  }

  // ---- cameras ----------------------------------------------------------------------------------
  const camera = new H.PerspectiveCamera(40, 1, 0.05, 5000);
  const controls = renderer ? new H.OrbitControls(camera, canvas) : null;
  let cameraName = "cockpit", center = new H.Vector3(), extent = new H.Vector3(10, 4, 4);

  /** The fixed cameras' frame and the grid, from the first frame: the hose and the probe. */
  function placeScene(J, n, p) {
    const lo = new H.Vector3(Infinity, Infinity, Infinity), hi = new H.Vector3(-Infinity, -Infinity, -Infinity);
    const take = (x, y, z) => { toThree(tA, x, y, z); lo.min(tA); hi.max(tA); };
    for (let j = 0; j < n; j++) take(J[3 * j], J[3 * j + 1], J[3 * j + 2]);
    take(p[0] - PROBE_MAST_M, p[1], p[2]);
    center = lo.clone().add(hi).multiplyScalar(0.5);
    extent = hi.clone().sub(lo);
    const reach = Math.max(Math.abs(lo.x), Math.abs(hi.x), Math.abs(lo.z), Math.abs(hi.z), 5);
    const size = 2 * Math.ceil(reach + 3);
    grid = new H.GridHelper(size, size, 0x7d8da2, 0xbac5d2);
    grid.position.set(0, lo.y - 0.5, 0);
    scene.add(grid);
    setCamera(cameraName);
  }

  function fit(w, h) {
    const tv = Math.tan((camera.fov * Math.PI) / 360), aspect = (canvas.clientWidth || 1) / (canvas.clientHeight || 1);
    return 1.15 * Math.max(h / 2 / tv, w / 2 / (tv * aspect));
  }

  function cockpit() { // 4 m aft of the probe tip and 0.6 m above it, looking 8 m ahead of it
    const p = probe.position;
    camera.up.set(0, 1, 0);
    camera.position.set(p.x - 4, p.y + 0.6, p.z);
    camera.lookAt(p.x + 8, p.y, p.z);
  }

  function setCamera(name) {
    if (!["cockpit", "side", "above", "orbit"].includes(name)) throw new Error("camera: " + name);
    cameraName = name;
    if (controls) controls.enabled = name !== "cockpit";
    if (grid && name !== "side") { grid.rotation.set(0, 0, 0); grid.position.set(0, center.y - extent.y / 2 - 0.5, 0); }
    if (name === "cockpit") cockpit();
    else {
      let offset;
      if (name === "side") offset = new H.Vector3(0, 0, fit(extent.x + 2, extent.y + 2) + extent.z / 2);
      else if (name === "above") offset = new H.Vector3(-1e-3, fit(extent.z + 2, extent.x + 2) + extent.y / 2, 0);
      else offset = new H.Vector3(-0.55, 0.45, 0.7).normalize().multiplyScalar(fit(extent.length(), extent.length() * 0.7));
      if (grid) {
        if (name === "side") { grid.rotation.set(Math.PI / 2, 0, 0); grid.position.set(0, 0, center.z - extent.z / 2 - 1); }
        else { grid.rotation.set(0, 0, 0); grid.position.set(0, center.y - extent.y / 2 - 0.5, 0); }
      }
      camera.up.set(0, 1, 0);
      camera.position.copy(center).add(offset);
      camera.lookAt(center);
      if (controls) { controls.target.copy(center); controls.update(); }
    }
    for (const b of document.querySelectorAll("[data-camera]")) b.classList.toggle("on", b.dataset.camera === name);
    dirty = true;
  }

  // ---- the head-up display and the reticle ------------------------------------------------------------
  const hud = document.getElementById("hud"), reticle = document.getElementById("reticle");
  const banner = document.getElementById("banner"), stateBox = document.getElementById("state");
  const num = (v, d, sign) => (v === null || v === undefined || Number.isNaN(v) ? "-" : (sign && v >= 0 ? "+" : "") + v.toFixed(d));

  function outcomeText(o) {
    if (!o || !o.result || o.result === "no contact") return "no contact yet";
    let s = o.result; // a miss or a failed latch says its figure; a capture does not
    if (o.contact_time_s !== null && o.contact_time_s !== undefined) s += ` at ${o.contact_time_s.toFixed(2)} s`;
    if (o.result === "captured" && o.miss_distance_m !== null && o.miss_distance_m !== undefined) s += `, miss ${o.miss_distance_m.toFixed(3)} m`;
    if (o.closure_speed_m_s !== null && o.closure_speed_m_s !== undefined) s += `, closure ${o.closure_speed_m_s.toFixed(2)} m/s`;
    return s;
  }

  /** The outcome in a HUD line: its kind, time, miss and closure. */
  function outcomeShort(o) {
    if (!o || !o.result || o.result === "no contact") return "no contact yet";
    let s = o.result.split(":")[0];
    if (o.contact_time_s !== null && o.contact_time_s !== undefined) s += ` at ${o.contact_time_s.toFixed(2)} s`;
    if (o.miss_distance_m !== null && o.miss_distance_m !== undefined) s += `, miss ${o.miss_distance_m.toFixed(3)} m`;
    if (o.closure_speed_m_s !== null && o.closure_speed_m_s !== undefined) s += `, closure ${o.closure_speed_m_s.toFixed(2)} m/s`;
    return s;
  }

  function hudHtml(f) {
    const esc = (s) => String(s).replace(/[&<>]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;" })[c]);
    const w = F.closure_window_m_s, c = f.command;
    const rows = [
      `t        ${f.t.toFixed(2)} / ${F.duration_s.toFixed(2)} s`,
      `range    ${num(f.range_m, 3)} m    probe tip to drogue along x`,
      `closure  ${num(f.closure_m_s, 2)} m/s  capture window ${w[0]}-${w[1]} m/s`,
      `miss     ${num(f.miss_m, 3)} m    straight on, at the coupler plane; capture ${F.capture_radius_m} m`,
      `offset   y ${num(f.offset_m[1], 3, true)}  z ${num(f.offset_m[2], 3, true)} m  drogue - probe (y right, z down)`,
      `command  ${num(c[0], 2)} ${num(c[1], 2, true)} ${num(c[2], 2, true)} m/s  (${esc(f.source)})`,
      `hose     ${f.links} links, ${f.length_m.toFixed(2)} m; exit tension ${Math.round(f.tension_n)} N; probe load ${Math.round(f.probe_load_n)} N`,
      `outcome  ${esc(outcomeShort(f.outcome))}${f.coupled ? "  (coupled)" : ""}`,
    ];
    let pace = `real time x${f.ratio.toFixed(2)}` + (f.capacity ? ` (could run x${f.capacity.toFixed(1)})` : "");
    if (f.late_samples > 0) pace = `<span class="behind">BEHIND: ${f.late_samples} late samples, ${f.lost_s.toFixed(2)} s lost</span>; ` + pace;
    rows.push(pace);
    return rows.join("\n");
  }

  function drawReticle(f) {
    const g = reticle.getContext("2d"), W = reticle.width, Hh = reticle.height, s = W / 2 / 1.0; // 1 m to the edge
    g.clearRect(0, 0, W, Hh);
    g.strokeStyle = "#7d8da2"; g.lineWidth = 1;
    g.beginPath(); g.moveTo(W / 2, 0); g.lineTo(W / 2, Hh); g.moveTo(0, Hh / 2); g.lineTo(W, Hh / 2); g.stroke();
    g.strokeStyle = "#1f9d55"; g.setLineDash([4, 3]);
    g.beginPath(); g.arc(W / 2, Hh / 2, F.capture_radius_m * s, 0, 2 * Math.PI); g.stroke();
    g.setLineDash([]);
    if (f) { // the drogue relative to the probe tip: right is right, down is down
      const x = W / 2 + Math.max(-1.2, Math.min(1.2, f.offset_m[1])) * s;
      const y = Hh / 2 + Math.max(-1.2, Math.min(1.2, f.offset_m[2])) * s;
      g.strokeStyle = f.miss_m <= F.capture_radius_m ? "#1f9d55" : HOSE_COLOR; g.lineWidth = 3;
      g.beginPath(); g.arc(x, y, rD * s, 0, 2 * Math.PI); g.stroke();
    }
    g.fillStyle = "#d0342c"; g.beginPath(); g.arc(W / 2, Hh / 2, 4, 0, 2 * Math.PI); g.fill();
    g.fillStyle = "#1d2430"; g.font = "11px sans-serif";
    g.fillText("drogue seen from the probe (1 m)", 6, Hh - 6);
  }

  // ---- the chart ------------------------------------------------------------------------------------
  const series = { t: [], y: [], z: [], miss: [] };
  let chart = null, chartDirty = false;
  function makeChart() {
    const box = document.createElement("div");
    box.className = "chart";
    box.innerHTML = '<div class="chart-title">drogue - probe tip [m] <span class="chart-key">y solid, z dashed, miss dotted</span></div>';
    document.getElementById("charts").insertBefore(box, document.getElementById("keys"));
    chart = new H.uPlot({
      width: 300, height: 170, legend: { show: false }, scales: { x: { time: false } },
      axes: [{ label: "t [s]", labelSize: 16, size: 34 }, { label: "m", labelSize: 16, size: 50 }],
      cursor: { show: false },
      series: [{ label: "t [s]" }, { label: "y", stroke: HOSE_COLOR, width: 1.4 },
        { label: "z", stroke: "#d9731a", width: 1.4, dash: [7, 4] }, { label: "miss", stroke: "#2e8b57", width: 1.4, dash: [2, 3] }],
    }, [[], [], [], []], box);
    new ResizeObserver(() => chart.setSize({ width: Math.max(200, box.clientWidth - 8), height: 170 })).observe(box);
  }
  makeChart();
  function chartAdd(f) {
    if (series.t.length && f.t < series.t[series.t.length - 1]) for (const k in series) series[k].length = 0; // a new flight
    series.t.push(f.t); series.y.push(f.offset_m[1]); series.z.push(f.offset_m[2]); series.miss.push(f.miss_m);
    if (series.t.length > CHART_POINTS) for (const k in series) series[k].splice(0, series[k].length - CHART_POINTS);
    chartDirty = true;
  }
  setInterval(() => { if (chartDirty) { chartDirty = false; chart.setData([series.t, series.y, series.z, series.miss]); } }, 100);

  // ---- the server's stream --------------------------------------------------------------------------
  const events = new EventSource("/events");
  events.addEventListener("frame", (e) => {
    frame = JSON.parse(e.data);
    frames++;
    updateScene(frame);
    chartAdd(frame);
    dirty = true;
  });
  events.addEventListener("status", (e) => {
    const before = status.state;
    status = JSON.parse(e.data);
    if (status.state === "ready" && before !== "ready") { setpoint = F.closure_speed_m_s; lastSent = ""; }
    showStatus();
  });
  events.addEventListener("bye", () => { serverGone = true; events.close(); showStatus(); });
  events.onerror = () => { if (events.readyState === EventSource.CLOSED) { serverGone = true; showStatus(); } };

  function post(path, body) {
    return fetch(path, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
      keepalive: true }).catch(() => null);
  }
  const control = (action) => post("/control", { action });

  function showStatus() {
    const s = serverGone ? "closed" : status.state;
    stateBox.textContent = serverGone ? "server stopped" : s;
    stateBox.className = "state " + s;
    const last = status.flights && status.flights.length ? status.flights[status.flights.length - 1] : null;
    banner.textContent = serverGone ? "The server has stopped: this page is no longer live."
      : s === "ready" ? `Flight ${status.flight}: press Enter (or start) to fly`
      : s === "paused" ? "Paused: P to resume"
      : s === "ended" && last ? `Flight ${last.number}: ${outcomeText(last)}. Enter: fly again; R: replay` : "";
    document.getElementById("start").disabled = s !== "ready";
    document.getElementById("pause").disabled = s !== "flying" && s !== "paused";
    document.getElementById("pause").textContent = s === "paused" ? "resume" : "pause";
    document.getElementById("end").disabled = s !== "flying" && s !== "paused";
    document.getElementById("again").disabled = s !== "ended";
    document.getElementById("replay").disabled = !last;
    const list = document.getElementById("flight-list");
    list.innerHTML = "";
    for (const fl of status.flights || []) {
      const li = document.createElement("li");
      const a = document.createElement("a");
      a.href = fl.replay; a.target = "_blank"; a.rel = "noopener"; a.textContent = "replay";
      li.textContent = `${outcomeText(fl)}; ${fl.flown_s.toFixed(2)} s, ended: ${fl.ended}; ${fl.folder} `;
      li.appendChild(a);
      list.appendChild(li);
    }
    document.getElementById("note").textContent = `${F.scenario}: ${F.description || ""}`;
  }

  // ---- the pilot's command ------------------------------------------------------------------------------
  const held = (...codes) => codes.some((c) => keys.has(c));
  const deadZone = (a) => (Math.abs(a) < DEAD_ZONE ? 0 : (a - Math.sign(a) * DEAD_ZONE) / (1 - DEAD_ZONE));
  function gamepad() {
    const pads = navigator.getGamepads ? Array.from(navigator.getGamepads()).filter((p) => p && p.connected) : [];
    return pads.length ? pads[0] : null;
  }
  const padButtons = {};
  function padPressed(pad, i) { // true once per press
    const down = !!(pad.buttons[i] && pad.buttons[i].pressed), was = padButtons[i];
    padButtons[i] = down;
    return down && !was;
  }
  function adjustSetpoint(dv) {
    const vmax = F.max_speed_m_s[0];
    setpoint = Math.max(-vmax, Math.min(vmax, Math.round((setpoint + dv) / CLOSURE_STEP) * CLOSURE_STEP));
    sendCommand(true);
  }

  /** The command now: (v_x, v_y, v_z) [m/s] in S_p, and what gave it. */
  function command() {
    const vm = F.max_speed_m_s, share = held("ShiftLeft", "ShiftRight") ? 1 : 0.5;
    let vy = 0, vz = 0;
    source = "keyboard";
    if (held("ArrowRight", "KeyD")) vy += share * vm[1];
    if (held("ArrowLeft", "KeyA")) vy -= share * vm[1];
    if (held("ArrowDown", "KeyS")) vz += share * vm[2];
    if (held("ArrowUp", "KeyW")) vz -= share * vm[2];
    const pad = gamepad();
    if (pad) {
      const ax = deadZone(pad.axes[0] || 0), ay = deadZone(pad.axes[1] || 0);
      if (ax || ay) { vy = ax * vm[1]; vz = ay * vm[2]; source = "gamepad"; } // stick up (negative) is up (-z)
    }
    return [setpoint, vy, vz];
  }

  function sendCommand(force) {
    const v = command(), text = JSON.stringify(v) + source;
    if (!force && text === lastSent) return;
    lastSent = text;
    post("/input", { v, source, seq: seqBase + ++seqCount });
    document.getElementById("setpoint").textContent = `closure ${setpoint.toFixed(2)} m/s`;
  }
  setInterval(() => { if (status.state === "flying") sendCommand(true); }, HEARTBEAT_MS);

  function pollGamepad() {
    const pad = gamepad();
    if (!pad) return;
    if (padPressed(pad, 5) || padPressed(pad, 12)) adjustSetpoint(CLOSURE_STEP);
    if (padPressed(pad, 4) || padPressed(pad, 13)) adjustSetpoint(-CLOSURE_STEP);
    if (padPressed(pad, 0)) control(status.state === "ended" ? "again" : "start");
    if (padPressed(pad, 9)) control(status.state === "paused" ? "resume" : "pause");
    sendCommand(false);
  }

  function replayLast() {
    const last = status.flights && status.flights.length ? status.flights[status.flights.length - 1] : null;
    if (last) window.open(last.replay, "_blank", "noopener");
  }

  const FLIGHT_KEYS = new Set(["ArrowLeft", "ArrowRight", "ArrowUp", "ArrowDown", "KeyA", "KeyD", "KeyW", "KeyS",
    "ShiftLeft", "ShiftRight"]);
  document.addEventListener("keydown", (e) => {
    const tag = e.target && e.target.tagName;
    if (tag === "INPUT" || tag === "SELECT" || tag === "TEXTAREA") return;
    if (FLIGHT_KEYS.has(e.code)) { e.preventDefault(); keys.add(e.code); sendCommand(false); return; }
    if (e.repeat) return;
    if (e.code === "Enter") { e.preventDefault(); control(status.state === "ended" ? "again" : "start"); }
    else if (e.code === "KeyP") control(status.state === "paused" ? "resume" : "pause");
    else if (e.code === "Escape") control("end");
    else if (e.code === "KeyE" || e.key === "+") adjustSetpoint(CLOSURE_STEP);
    else if (e.code === "KeyQ" || e.key === "-") adjustSetpoint(-CLOSURE_STEP);
    else if (e.code === "KeyR") replayLast();
    else if (/^Digit[1-4]$/.test(e.code)) setCamera(["cockpit", "side", "above", "orbit"][Number(e.code[5]) - 1]);
  });
  document.addEventListener("keyup", (e) => { if (keys.delete(e.code)) sendCommand(false); });
  window.addEventListener("blur", () => { if (keys.size) { keys.clear(); sendCommand(false); } });
  document.addEventListener("visibilitychange", () => { if (document.hidden && status.state === "flying") control("pause"); });
  window.addEventListener("pagehide", () => navigator.sendBeacon("/bye", "{}"));

  document.getElementById("start").addEventListener("click", () => control("start"));
  document.getElementById("pause").addEventListener("click", () => control(status.state === "paused" ? "resume" : "pause"));
  document.getElementById("end").addEventListener("click", () => control("end"));
  document.getElementById("again").addEventListener("click", () => control("again"));
  document.getElementById("replay").addEventListener("click", replayLast);
  for (const b of document.querySelectorAll("[data-camera]")) b.addEventListener("click", () => { setCamera(b.dataset.camera); b.blur(); });
  for (const b of document.querySelectorAll("#controls button")) b.addEventListener("mouseup", () => b.blur());
  if (controls) controls.addEventListener("change", () => { dirty = true; });

  // ---- drawing --------------------------------------------------------------------------------------
  function render() {
    if (!renderer) return;
    const w = canvas.clientWidth, h = canvas.clientHeight, pr = renderer.getPixelRatio();
    if (canvas.width !== Math.floor(w * pr) || canvas.height !== Math.floor(h * pr)) renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
    renderer.render(scene, camera);
  }
  function tick() {
    pollGamepad();
    if (dirty) {
      dirty = false;
      if (cameraName === "cockpit") cockpit();
      render();
      if (frame) hud.innerHTML = hudHtml(frame);
      drawReticle(frame);
      drawn++;
      if (frame && loadedAt === null) loadedAt = performance.now();
      document.documentElement.dataset.hdDrawn = String(drawn);
    }
    requestAnimationFrame(tick);
  }
  document.getElementById("title").textContent = F.title;
  document.getElementById("setpoint").textContent = `closure ${setpoint.toFixed(2)} m/s`;
  new ResizeObserver(() => { dirty = true; }).observe(stage);
  showStatus();
  setCamera("cockpit");
  requestAnimationFrame(tick);

  /** For tests and benchmarks: what the page holds and does. */
  window.hdLive = {
    get frame() { return frame; }, get frames() { return frames; }, get drawn() { return drawn; },
    get status() { return status; }, get camera() { return cameraName; }, get setpoint() { return setpoint; },
    get serverGone() { return serverGone; }, get command() { return command(); },
    /** ms from the navigation's start to the first live frame drawn (null before). */
    get firstFrameMs() { return loadedAt; },
    setCamera, control,
  };
})();
