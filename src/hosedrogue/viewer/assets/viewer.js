/* hosedrogue viewer: the runs of the page's data (script#hd-data) in 3D (three.js) with their time
 * series (uPlot), one clock for both. The libraries come as the global HDV (vendor.min.js).
 *
 * Frames: the data are in S_p (x forward, y right, z down); three.js draws in (X forward, Y up,
 * Z right), the same right-handed frame turned: X = x, Y = -z, Z = y.
 */
(function () {
  "use strict";
  const H = window.HDV;
  const DATA = JSON.parse(document.getElementById("hd-data").textContent);
  const COLORS = ["#1f5fae", "#d9731a", "#2e8b57", "#8e44ad", "#c0392b", "#16a0a8", "#7f6a00", "#4d4d4d"];
  const PROBE_MAST_M = 1.5; // drawn length of the probe aft of its tip [m] (a marker, not modelled)
  const BASKET_DEPTH_M = 0.6; // drawn depth of the drogue's cone [m] (a marker; its diameter is the model's)

  // ---- data -------------------------------------------------------------------------------
  function bytes(b64) {
    const s = atob(b64);
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u;
  }
  const f64 = (b) => new Float64Array(bytes(b).buffer);
  const f32 = (b) => new Float32Array(bytes(b).buffer);
  const u16 = (b) => new Uint16Array(bytes(b).buffer);

  function prepare(r, i) {
    const fr = r.frames;
    const t = f64(fr.t), count = u16(fr.count);
    const offset = new Uint32Array(t.length + 1);
    let maxCount = 0;
    for (let k = 0; k < t.length; k++) {
      offset[k + 1] = offset[k] + count[k];
      maxCount = Math.max(maxCount, count[k]);
    }
    const series = {};
    for (const [k, v] of Object.entries(r.series)) series[k] = k === "t" ? f64(v) : f32(v);
    return Object.assign({}, r, {
      index: i, color: COLORS[i % COLORS.length], t, count, offset, maxCount, joints: f32(fr.joints),
      probe: fr.probe ? f32(fr.probe) : null, coupled: fr.coupled ? bytes(fr.coupled) : null, series,
      aircraft: fr.aircraft ? f32(fr.aircraft) : null,
    });
  }
  const runs = DATA.runs.map(prepare);
  const T0 = Math.min(...runs.map((r) => r.t[0]));
  const T1 = Math.max(...runs.map((r) => r.t[r.t.length - 1]));
  const SPAN = Math.max(T1 - T0, 1e-9);
  let time = T0, playing = false, speed = 1, loop = true, lastTs = null, dirty = true, dragging = false;
  let layout = runs.length > 1 && DATA.layout === "side" ? "side" : "overlay";
  let drawCount = 0, stamps = null; // stamps: draw times [ms] while the frame rate is measured

  /** Largest k with t[k] <= time (0 before the start, the last index after the end). */
  function locate(t, time) {
    let lo = 0, hi = t.length - 1;
    if (time <= t[0]) return 0;
    if (time >= t[hi]) return hi;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (t[mid] <= time) lo = mid; else hi = mid;
    }
    return lo;
  }

  /** The run's joints at `time` into `out` (S_p, flat xyz): linear between two frames of the same
   * link count, the nearer frame across a remesh. Returns the joint count and the frame used. */
  function shapeAt(run, time, out) {
    const k = locate(run.t, time);
    let k1 = k, w = 0;
    if (k + 1 < run.t.length && time > run.t[k]) {
      k1 = k + 1;
      w = (time - run.t[k]) / (run.t[k1] - run.t[k]);
    }
    const J = run.joints;
    if (k1 !== k && run.count[k1] !== run.count[k]) {
      const kk = w >= 0.5 ? k1 : k;
      const n = run.count[kk], a = run.offset[kk] * 3;
      for (let i = 0; i < 3 * n; i++) out[i] = J[a + i];
      return { n, frame: kk, w: 0 };
    }
    const n = run.count[k], a = run.offset[k] * 3, b = run.offset[k1] * 3;
    for (let i = 0; i < 3 * n; i++) out[i] = J[a + i] + w * (J[b + i] - J[a + i]);
    return { n, frame: w >= 0.5 ? k1 : k, w };
  }

  /** Row `time` of a per-frame array of `width` columns into `out` (linear between frames); false without one. */
  function rowAt(run, values, width, time, out) {
    if (!values) return false;
    const k = locate(run.t, time);
    const k1 = Math.min(k + 1, run.t.length - 1);
    const w = k1 > k && time > run.t[k] ? (time - run.t[k]) / (run.t[k1] - run.t[k]) : 0;
    for (let i = 0; i < width; i++) out[i] = values[width * k + i] + w * (values[width * k1 + i] - values[width * k + i]);
    return true;
  }

  const probeAt = (run, time, out) => rowAt(run, run.probe, 3, time, out);
  /** The receiver aircraft's x, y, z [m] and roll, pitch, yaw [rad] at `time`. */
  const aircraftAt = (run, time, out) => rowAt(run, run.aircraft, 6, time, out);

  /** The series sample nearest `time` (the last one at or before it). */
  function sampleAt(run, name, time) {
    const s = run.series[name];
    return s ? s[locate(run.series.t, time)] : undefined;
  }

  // ---- the 3D scene -------------------------------------------------------------------------
  const canvas = document.getElementById("view3d");
  const stage = document.getElementById("stage");
  /** The WebGL implementation's name, and whether it draws in software on the CPU (SwiftShader,
   * llvmpipe: headless browsers, machines without a GPU), where multisampling halves the frame rate. */
  function glInfo() {
    try {
      const gl = document.createElement("canvas").getContext("webgl2") || document.createElement("canvas").getContext("webgl");
      const ext = gl.getExtension("WEBGL_debug_renderer_info");
      const name = String(gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
      const lose = gl.getExtension("WEBGL_lose_context");
      if (lose) lose.loseContext();
      return { name, software: /swiftshader|llvmpipe|software/i.test(name) };
    } catch (err) {
      return { name: "none", software: false };
    }
  }
  const GL = glInfo();
  let renderer = null;
  try {
    renderer = new H.WebGLRenderer({ canvas, antialias: !GL.software });
  } catch (err) {
    stage.insertAdjacentHTML("beforeend", '<p class="chart-note" style="position:absolute;top:40%;left:10%">' +
      "WebGL is not available in this browser, so the 3D view is off; the charts work.</p>");
  }
  const toThree = (v, x, y, z) => v.set(x, -z, y);
  const scene = new H.Scene();
  scene.background = new H.Color("#dfe7f0");
  scene.add(new H.AmbientLight(0xffffff, 1.6));
  const sun = new H.DirectionalLight(0xffffff, 2.0);
  sun.position.set(-3, 10, 6);
  scene.add(sun);

  const UP = new H.Vector3(0, 1, 0);
  const tmpA = new H.Vector3(), tmpB = new H.Vector3(), tmpD = new H.Vector3(), tmpS = new H.Vector3();
  const tmpQ = new H.Quaternion(), tmpM = new H.Matrix4();

  function bounds() {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    const take = (x, y, z) => {
      toThree(tmpA, x, y, z);
      const p = [tmpA.x, tmpA.y, tmpA.z];
      for (let i = 0; i < 3; i++) { lo[i] = Math.min(lo[i], p[i]); hi[i] = Math.max(hi[i], p[i]); }
    };
    for (const r of runs) {
      for (let i = 0; i < r.joints.length; i += 3) take(r.joints[i], r.joints[i + 1], r.joints[i + 2]);
      if (r.probe) for (let i = 0; i < r.probe.length; i += 3) take(r.probe[i], r.probe[i + 1], r.probe[i + 2]);
      if (r.aircraft) { // the aircraft's centre of gravity and its tail, 7.5 m behind it
        for (let i = 0; i < r.aircraft.length; i += 6) {
          take(r.aircraft[i], r.aircraft[i + 1], r.aircraft[i + 2]);
          take(r.aircraft[i] - 7.5, r.aircraft[i + 1], r.aircraft[i + 2]);
        }
      }
    }
    return { lo: new H.Vector3(...lo), hi: new H.Vector3(...hi) };
  }
  const box = bounds();
  const center = box.lo.clone().add(box.hi).multiplyScalar(0.5);
  const extent = box.hi.clone().sub(box.lo);

  // a 1 m grid behind what is drawn as the camera sees it (below it, or behind it in the side
  // view), its two darker lines through the tow point (the origin of S_p)
  const reach = Math.max(...[box.lo, box.hi].flatMap((v) => [Math.abs(v.x), Math.abs(v.y), Math.abs(v.z)]));
  const gridSize = 2 * Math.ceil(reach + 3);
  const grid = new H.GridHelper(gridSize, gridSize, 0x7d8da2, 0xbac5d2);
  scene.add(grid);
  function placeGrid(name) {
    if (name === "side") {
      grid.rotation.set(Math.PI / 2, 0, 0);
      grid.position.set(0, 0, box.lo.z - 1.0);
    } else {
      grid.rotation.set(0, 0, 0);
      grid.position.set(0, box.lo.y - 0.5, 0);
    }
  }

  function material(color, opts) {
    return new H.MeshLambertMaterial(Object.assign({ color: new H.Color(color) }, opts || {}));
  }

  function runObjects(run) {
    const group = new H.Group();
    const links = Math.max(1, run.maxCount - 1);
    const hose = new H.InstancedMesh(new H.CylinderGeometry(1, 1, 1, 8, 1, false), material(run.color), links);
    hose.instanceMatrix.setUsage(H.DynamicDrawUsage);
    hose.frustumCulled = false;
    group.add(hose);
    const tow = new H.Mesh(new H.SphereGeometry(0.12, 16, 12), material("#333a44"));
    group.add(tow);
    const drogue = new H.Group();
    const rD = run.drogue_diameter_m / 2;
    const cone = new H.Mesh(new H.ConeGeometry(rD, BASKET_DEPTH_M, 32, 1, true),
      material(run.color, { transparent: true, opacity: 0.45, side: H.DoubleSide, depthWrite: false }));
    cone.rotation.x = Math.PI; // apex at the hose's end, opening aft
    cone.position.y = BASKET_DEPTH_M / 2;
    const ring = new H.Mesh(new H.TorusGeometry(rD, 0.02, 8, 48), material(run.color));
    ring.rotation.x = Math.PI / 2;
    ring.position.y = BASKET_DEPTH_M;
    drogue.add(cone, ring);
    group.add(drogue);
    let probe = null, tip = null;
    if (run.probe) {
      probe = new H.Group();
      const mast = new H.Mesh(new H.CylinderGeometry(0.04, 0.05, PROBE_MAST_M, 12), material("#59606b"));
      mast.rotation.z = Math.PI / 2; // along X, the tip forward
      mast.position.x = -PROBE_MAST_M / 2;
      tip = new H.Mesh(new H.SphereGeometry(0.07, 16, 12), material("#d0342c"));
      probe.add(mast, tip);
      group.add(probe);
    }
    const aircraft = run.aircraft ? aircraftShape() : null;
    if (aircraft) group.add(aircraft);
    scene.add(group);
    return { group, hose, tow, drogue, probe, tip, aircraft, shape: new Float32Array(3 * run.maxCount),
      p: new Float32Array(3), a: new Float32Array(6) };
  }
  /** A low-poly F-16-like receiver in body axes (x forward from the centre of gravity, y right, z
   * down; built in the scene's axes as toThree maps them): 15 m long, the nose 6.5 m ahead, 9.4 m
   * span, drawn translucent so the drogue stays visible through it. A picture, not the model's geometry. */
  function aircraftShape() {
    const g = new H.Group();
    g.matrixAutoUpdate = false;
    const skin = material("#5d6774", { transparent: true, opacity: 0.4, depthWrite: false, side: H.DoubleSide });
    const body = (geometry, x, rotZ) => {
      const m = new H.Mesh(geometry, skin);
      m.position.x = x;
      m.rotation.z = rotZ;
      g.add(m);
    };
    body(new H.CylinderGeometry(0.55, 0.5, 11.0, 16), -1.0, Math.PI / 2); // fuselage, x -6.5 .. 4.5
    body(new H.ConeGeometry(0.55, 2.0, 16), 5.5, -Math.PI / 2); // nose, its apex forward at 6.5 m
    // flat surfaces as quads of body-axis corners (x forward, y right, z down) [m]
    const quads = [];
    for (const side of [1, -1]) {
      quads.push([[1.5, 0.5, 0], [-2.5, 4.7, 0], [-3.6, 4.7, 0], [-3.5, 0.5, 0]].map(([x, y, z]) => [x, side * y, z]));
      quads.push([[-5.0, 0.5, 0], [-6.6, 2.8, 0], [-7.4, 2.8, 0], [-7.0, 0.5, 0]].map(([x, y, z]) => [x, side * y, z]));
    }
    quads.push([[-4.2, 0, -0.5], [-6.6, 0, -3.4], [-7.4, 0, -3.4], [-7.0, 0, -0.5]]); // the fin, above
    const xyz = [];
    const v = new H.Vector3();
    for (const q of quads) {
      for (const k of [0, 1, 2, 0, 2, 3]) {
        toThree(v, q[k][0], q[k][1], q[k][2]);
        xyz.push(v.x, v.y, v.z);
      }
    }
    const plates = new H.BufferGeometry();
    plates.setAttribute("position", new H.BufferAttribute(new Float32Array(xyz), 3));
    plates.computeVertexNormals();
    g.add(new H.Mesh(plates, skin));
    return g;
  }
  // the scene's axes from S_p's (toThree) as a rotation, for the aircraft's attitude
  const SP_TO_THREE = new H.Matrix4().set(1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1);
  const THREE_TO_SP = SP_TO_THREE.clone().transpose();
  const tmpEuler = { x: 0, y: 0, z: 0, order: "ZYX" }, tmpR = new H.Matrix4(), tmpP = new H.Vector3();

  /** Place the aircraft: its centre of gravity at (x, y, z) in S_p, body axes turned by yaw, pitch,
   * roll (Z-Y-X, the aircraft's Euler angles from S_p's axes): M C(yaw, pitch, roll) M^T in the scene. */
  function placeAircraft(g, a) {
    tmpEuler.x = a[3]; tmpEuler.y = a[4]; tmpEuler.z = a[5]; // three.js reads only x, y, z and order
    tmpR.makeRotationFromEuler(tmpEuler);
    tmpR.premultiply(SP_TO_THREE).multiply(THREE_TO_SP);
    toThree(tmpP, a[0], a[1], a[2]);
    tmpR.setPosition(tmpP);
    g.matrix.copy(tmpR);
    g.matrixWorldNeedsUpdate = true;
  }
  const objects = runs.map(runObjects);
  const COUPLED = new H.Color("#1f9d55"), FREE = new H.Color("#d0342c");

  function updateRun(run, obj, time) {
    const { n, frame } = shapeAt(run, time, obj.shape);
    const s = obj.shape, r = run.hose_diameter_m / 2;
    for (let j = 0; j + 1 < n; j++) {
      toThree(tmpA, s[3 * j], s[3 * j + 1], s[3 * j + 2]);
      toThree(tmpB, s[3 * j + 3], s[3 * j + 4], s[3 * j + 5]);
      tmpD.subVectors(tmpB, tmpA);
      const len = tmpD.length();
      tmpQ.setFromUnitVectors(UP, tmpD.multiplyScalar(1 / Math.max(len, 1e-12)));
      tmpM.compose(tmpA.add(tmpB).multiplyScalar(0.5), tmpQ, tmpS.set(r, len, r));
      obj.hose.setMatrixAt(j, tmpM);
    }
    obj.hose.count = n - 1;
    obj.hose.instanceMatrix.needsUpdate = true;
    toThree(obj.tow.position, s[0], s[1], s[2]);
    toThree(tmpA, s[3 * n - 6], s[3 * n - 5], s[3 * n - 4]);
    toThree(tmpB, s[3 * n - 3], s[3 * n - 2], s[3 * n - 1]);
    obj.drogue.position.copy(tmpB);
    obj.drogue.quaternion.setFromUnitVectors(UP, tmpD.subVectors(tmpB, tmpA).normalize());
    if (obj.probe && probeAt(run, time, obj.p)) {
      toThree(obj.probe.position, obj.p[0], obj.p[1], obj.p[2]);
      const coupled = run.coupled ? run.coupled[frame] : 0;
      obj.tip.material.color.copy(coupled ? COUPLED : FREE);
    }
    if (obj.aircraft && aircraftAt(run, time, obj.a)) placeAircraft(obj.aircraft, obj.a);
    return { n, frame };
  }

  // ---- cameras --------------------------------------------------------------------------------
  const camera = new H.PerspectiveCamera(35, 1, 0.05, 5000);
  const controls = renderer ? new H.OrbitControls(camera, canvas) : null;
  let cameraName = "side";
  const drogueStart = (() => {
    const v = new H.Vector3();
    for (const r of runs) {
      const n = r.count[0];
      v.add(toThree(tmpA, r.joints[3 * n - 3], r.joints[3 * n - 2], r.joints[3 * n - 1]));
    }
    return v.multiplyScalar(1 / runs.length);
  })();

  function viewAspect() {
    const w = canvas.clientWidth || 1, h = canvas.clientHeight || 1;
    return (layout === "side" && runs.length > 1 ? w / runs.length : w) / h;
  }

  /** Distance at which a w x h [m] face fills the view (15 % margin). */
  function fit(w, h) {
    const tv = Math.tan((camera.fov * Math.PI) / 360);
    return 1.15 * Math.max(h / 2 / tv, w / 2 / (tv * viewAspect()));
  }

  function setCamera(name) {
    const target = name === "behind" ? drogueStart.clone() : center.clone();
    let offset;
    if (name === "behind") offset = new H.Vector3(-12, 1.5, 0); // aft of the probe, a little above
    else if (name === "side") offset = new H.Vector3(0, 0, fit(extent.x + 2, extent.y + 2) + extent.z / 2);
    else if (name === "above") offset = new H.Vector3(-1e-3, fit(extent.z + 2, extent.x + 2) + extent.y / 2, 0);
    else if (name === "orbit") offset = new H.Vector3(-0.55, 0.45, 0.7).normalize().multiplyScalar(fit(extent.length(), extent.length() * 0.7));
    else throw new Error("camera: " + name + ": must be behind, side, above or orbit");
    cameraName = name;
    placeGrid(name);
    camera.up.set(0, 1, 0);
    camera.position.copy(target).add(offset);
    camera.lookAt(target);
    if (controls) { controls.target.copy(target); controls.update(); }
    for (const b of document.querySelectorAll("[data-camera]")) b.classList.toggle("on", b.dataset.camera === name);
    requestDraw();
  }

  // ---- layout -------------------------------------------------------------------------------
  function setLayout(name) {
    if (name !== "overlay" && name !== "side") throw new Error("layout: " + name + ": must be overlay or side");
    layout = runs.length > 1 ? name : "overlay";
    for (const b of document.querySelectorAll("[data-layout]")) b.classList.toggle("on", b.dataset.layout === layout);
    const labels = document.getElementById("labels");
    labels.innerHTML = "";
    document.body.classList.toggle("side-layout", layout === "side");
    if (layout === "side") {
      runs.forEach((r, i) => {
        const d = document.createElement("div");
        d.className = "view-label";
        d.style.left = `calc(${(100 * i) / runs.length}% + 8px)`;
        d.style.top = "auto"; d.style.bottom = "6px";
        d.style.background = r.color;
        d.textContent = r.label;
        labels.appendChild(d);
      });
    }
    requestDraw();
  }

  // ---- charts ---------------------------------------------------------------------------------
  const charts = [];
  const chartBox = document.getElementById("charts");
  const CHARTS = [
    { title: "drogue offset from its balance position [m]", key: "x dotted, y solid, z dashed", unit: "m",
      lines: [["drogue_dx_m", "x", [2, 3]], ["drogue_dy_m", "y", null], ["drogue_dz_m", "z", [7, 4]]] },
    { title: "exit tension [N]", unit: "N", lines: [["exit_tension_n", "T0", null]] },
    { title: "probe load [N]", unit: "N", lines: [["probe_load_n", "probe", null]],
      none: "no probe in these runs (the fixed-length hose)" },
  ];

  function chartData(spec) {
    const members = [];
    for (const r of runs) for (const [col, name, dash] of spec.lines) if (r.series[col]) members.push({ r, col, name, dash });
    if (!members.length) return null;
    const same = runs.every((r) => r.series.t.length === runs[0].series.t.length && r.series.t.every((v, i) => v === runs[0].series.t[i]));
    let data;
    if (same) data = [runs[0].series.t, ...members.map((m) => m.r.series[m.col])];
    else {
      const tables = members.map((m) => [Array.from(m.r.series.t), Array.from(m.r.series[m.col])]);
      data = H.uPlot.join(tables);
    }
    const series = [{ label: "t [s]" }, ...members.map((m) => ({
      label: runs.length > 1 ? `${m.r.label} ${m.name}` : m.name, stroke: m.r.color, width: 1.4,
      dash: m.dash || undefined, spanGaps: true, points: { show: false },
    }))];
    return { data, series };
  }

  let syncing = false;
  function makeChart(spec) {
    const box = document.createElement("div");
    box.className = "chart";
    box.innerHTML = `<div class="chart-title">${spec.title}${spec.key ? ` <span class="chart-key">${spec.key}</span>` : ""}</div>`;
    chartBox.appendChild(box);
    const cd = chartData(spec);
    if (!cd) {
      box.insertAdjacentHTML("beforeend", `<div class="chart-note">${spec.none}</div>`);
      return;
    }
    const opts = {
      width: 300, height: 150, legend: { show: false }, series: cd.series, // the page's header is the legend
      scales: { x: { time: false } },
      axes: [{ label: "t [s]", labelSize: 16, size: 34 }, { label: spec.unit, labelSize: 16, size: 56 }],
      cursor: { drag: { x: true, y: false }, points: { show: false }, y: false },
      hooks: { setScale: [(u, key) => {
        if (key !== "x" || syncing) return;
        syncing = true;
        for (const c of charts) if (c.u !== u) c.u.setScale("x", { min: u.scales.x.min, max: u.scales.x.max });
        syncing = false;
        placeCursors();
      }] },
    };
    const u = new H.uPlot(opts, cd.data, box);
    const line = document.createElement("div");
    line.className = "hd-cursor";
    u.over.appendChild(line);
    let down = null;
    u.over.addEventListener("mousedown", (e) => { down = e.clientX; });
    u.over.addEventListener("mouseup", (e) => {
      if (down !== null && Math.abs(e.clientX - down) < 3) {
        const rect = u.over.getBoundingClientRect();
        setTime(u.posToVal(e.clientX - rect.left, "x"));
      }
      down = null;
    });
    charts.push({ u, line, box, spec });
  }
  CHARTS.forEach(makeChart);

  function placeCursors() {
    for (const c of charts) {
      const x = c.u.valToPos(time, "x");
      const inside = x >= 0 && x <= c.u.over.clientWidth;
      c.line.style.display = inside ? "block" : "none";
      c.line.style.left = `${x}px`;
    }
  }

  function sizeCharts() {
    const boxes = Array.from(chartBox.children);
    const notes = boxes.filter((b) => !charts.some((c) => c.box === b));
    const free = chartBox.clientHeight - notes.reduce((a, b) => a + b.offsetHeight, 0) - 4 * (boxes.length - 1);
    const each = free / Math.max(1, charts.length);
    for (const c of charts) {
      const title = c.box.querySelector(".chart-title").offsetHeight;
      const legend = c.box.querySelector(".u-legend");
      const height = each - title - (legend ? legend.offsetHeight : 0) - 6;
      c.u.setSize({ width: Math.max(200, c.box.clientWidth - 8), height: Math.max(90, Math.floor(height)) });
    }
    placeCursors();
  }

  // ---- clock, HUD, drawing ----------------------------------------------------------------------
  const hud = document.getElementById("hud"), clock = document.getElementById("clock");
  const scrub = document.getElementById("scrub"), playButton = document.getElementById("play");
  const fmt = (v, d) => (v === undefined || v === null || Number.isNaN(v) ? "-" : (v >= 0 ? "+" : "") + v.toFixed(d));

  function hudText(states) {
    const rows = [`t = ${time.toFixed(3)} s   ${speed}x${playing ? "" : "  (paused)"}`];
    runs.forEach((r, i) => {
      const end = r.t[r.t.length - 1];
      let row = `${r.label}: ${states[i].n - 1} links  drogue ${fmt(sampleAt(r, "drogue_dx_m", time), 3)} ` +
        `${fmt(sampleAt(r, "drogue_dy_m", time), 3)} ${fmt(sampleAt(r, "drogue_dz_m", time), 3)} m  ` +
        `T0 ${Math.round(sampleAt(r, "exit_tension_n", time))} N`;
      if (r.series.probe_load_n) row += `  probe ${Math.round(sampleAt(r, "probe_load_n", time))} N`;
      if (r.coupled) row += r.coupled[states[i].frame] ? "  coupled" : "";
      if (time > end + 1e-9) row += `  (ended at ${end.toFixed(3)} s)`;
      rows.push(row);
    });
    return rows.join("\n");
  }

  function render() {
    if (!renderer) return;
    const w = canvas.clientWidth, h = canvas.clientHeight;
    const pr = renderer.getPixelRatio();
    if (canvas.width !== Math.floor(w * pr) || canvas.height !== Math.floor(h * pr)) renderer.setSize(w, h, false);
    if (layout === "side" && runs.length > 1) {
      const vw = w / runs.length;
      renderer.setScissorTest(true);
      camera.aspect = vw / h;
      camera.updateProjectionMatrix();
      objects.forEach((o, i) => {
        objects.forEach((p, j) => { p.group.visible = i === j; });
        renderer.setViewport(i * vw, 0, vw, h);
        renderer.setScissor(i * vw, 0, vw, h);
        renderer.render(scene, camera);
      });
      renderer.setScissorTest(false);
      objects.forEach((p) => { p.group.visible = true; });
    } else {
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      renderer.setViewport(0, 0, w, h);
      renderer.render(scene, camera);
    }
  }

  function draw() {
    const states = runs.map((r, i) => updateRun(r, objects[i], time));
    render();
    hud.textContent = hudText(states);
    clock.textContent = `t = ${time.toFixed(3)} s`;
    if (!dragging) scrub.value = String(Math.round((1000 * (time - T0)) / SPAN));
    const icon = playing ? "\u275A\u275A" : "\u25B6";
    if (playButton.textContent !== icon) playButton.textContent = icon;
    placeCursors();
    drawCount++;
    if (stamps) stamps.push(performance.now());
    document.documentElement.dataset.hdDrawn = String(drawCount);
  }

  function requestDraw() { dirty = true; }

  function setTime(t) {
    time = Math.min(T1, Math.max(T0, Number(t)));
    requestDraw();
  }

  function tick(ts) {
    if (playing) {
      if (lastTs !== null) {
        time += ((ts - lastTs) / 1000) * speed;
        if (time > T1) {
          if (loop) time = T0 + ((time - T0) % SPAN);
          else { time = T1; playing = false; }
        }
      }
      lastTs = ts;
      dirty = true;
    }
    if (dirty) { dirty = false; draw(); }
    requestAnimationFrame(tick);
  }

  function play() { if (time >= T1 && !loop) time = T0; playing = true; lastTs = null; requestDraw(); }
  function pause() { playing = false; requestDraw(); }

  // ---- controls -------------------------------------------------------------------------------
  playButton.addEventListener("click", () => (playing ? pause() : play()));
  scrub.addEventListener("input", () => { dragging = true; setTime(T0 + (SPAN * Number(scrub.value)) / 1000); });
  scrub.addEventListener("change", () => { dragging = false; });
  document.getElementById("speed").addEventListener("change", (e) => { speed = Number(e.target.value); requestDraw(); });
  document.getElementById("loop").addEventListener("change", (e) => { loop = e.target.checked; });
  for (const b of document.querySelectorAll("[data-camera]")) b.addEventListener("click", () => setCamera(b.dataset.camera));
  for (const b of document.querySelectorAll("[data-layout]")) b.addEventListener("click", () => { setLayout(b.dataset.layout); setCamera(cameraName); });
  if (runs.length < 2) document.getElementById("layout-group").style.display = "none";
  if (controls) controls.addEventListener("change", requestDraw);
  const step = () => (runs[0].t.length > 1 ? (runs[0].t[runs[0].t.length - 1] - runs[0].t[0]) / (runs[0].t.length - 1) : 0.01);
  document.addEventListener("keydown", (e) => {
    const tag = e.target && e.target.tagName;
    if (tag === "INPUT" || tag === "SELECT" || tag === "BUTTON" || tag === "TEXTAREA") return;
    if (e.key === " ") { e.preventDefault(); playing ? pause() : play(); }
    else if (e.key === "ArrowRight") setTime(time + step());
    else if (e.key === "ArrowLeft") setTime(time - step());
    else if (e.key === "Home") setTime(T0);
    else if (e.key === "End") setTime(T1);
    else if ("1234".includes(e.key) && e.key.length === 1) setCamera(["behind", "side", "above", "orbit"][Number(e.key) - 1]);
  });

  // header: title and one legend entry per run
  document.getElementById("title").textContent = DATA.title;
  const legend = document.getElementById("legend");
  for (const r of runs) {
    const li = document.createElement("li");
    const o = r.outcome || {};
    let note = r.model === "engagement" ? "engagement" : "fixed-length hose";
    if (o.result) note += `: ${o.result}`;
    if (o.miss_distance_m !== undefined && o.miss_distance_m !== null) note += `, miss ${o.miss_distance_m.toFixed(3)} m`;
    if (o.contact_time_s !== undefined && o.contact_time_s !== null) note += ` at ${o.contact_time_s.toFixed(2)} s`;
    li.innerHTML = `<span class="swatch" style="background:${r.color}"></span><b></b> <span class="note"></span>`;
    li.querySelector("b").textContent = r.label;
    li.querySelector(".note").textContent = note;
    if (!r.completed) {
      const bad = document.createElement("span");
      bad.className = "bad";
      bad.textContent = ` incomplete: ${r.message}`;
      li.appendChild(bad);
    }
    li.title = r.source || "";
    legend.appendChild(li);
  }

  new ResizeObserver(() => { sizeCharts(); requestDraw(); }).observe(document.getElementById("app"));
  setLayout(layout);
  sizeCharts();
  setCamera(runs.some((r) => r.probe) ? "behind" : "side");
  requestAnimationFrame(tick);

  /** For tests and benchmarks: the clock, the cameras, the layout, what is drawn, the frame rate. */
  window.hdViewer = {
    get time() { return time; }, get playing() { return playing; }, get drawCount() { return drawCount; },
    span: [T0, T1], labels: runs.map((r) => r.label), gl: { name: GL.name, antialias: !GL.software }, get camera() { return cameraName; }, get layout() { return layout; },
    setTime, play, pause, setCamera, setLayout, setSpeed(s) { speed = Number(s); requestDraw(); },
    setLoop(on) { loop = !!on; },
    /** Per run: the frame shown and its joint count (after the last draw). */
    frames() { return runs.map((r) => { const k = locate(r.t, time); return { label: r.label, frame: k, joints: r.count[k] }; }); },
    /** Play for `ms` milliseconds and count the frames drawn: {frames, seconds, fps}. */
    measureFrameRate(ms) {
      return new Promise((resolve) => {
        stamps = [];
        play();
        setTimeout(() => {
          const s = stamps;
          stamps = null;
          const seconds = s.length > 1 ? (s[s.length - 1] - s[0]) / 1000 : 0;
          resolve({ frames: s.length, seconds, fps: seconds > 0 ? (s.length - 1) / seconds : 0 });
        }, ms);
      });
    },
  };
})();
