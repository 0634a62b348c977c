// ClothLab viewer: plays the runs in window.CLOTHLAB_RUNS (runs.js, written by
// `clothlab view`) with three.js. Every run gets its own scene; all share one camera, so side
// by side and overlaid views compare the same viewpoint.
"use strict";

const SWATCHES = [0x4fc3f7, 0xffb74d, 0xaed581, 0xf06292];
const BACKGROUND = 0x1d2026;
const COLLIDER_COLOUR = 0xc8b89a;
const params = new URLSearchParams(location.search);

function decodeBytes(base64) {
  return Uint8Array.from(atob(base64), (c) => c.charCodeAt(0)).buffer;
}
const decodeFloats = (base64) => new Float32Array(decodeBytes(base64));

// The frame shown at time t: the last one at or before t.
function frameAt(times, t) {
  let lo = 0, hi = times.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t + 1e-9) lo = mid; else hi = mid - 1;
  }
  return lo;
}

// Blue (rest length) through green and yellow to red (the largest stretch of all runs).
function stretchColour(s, max, out, k) {
  const u = Math.min(1, Math.max(0, (s - 1) / Math.max(1e-6, max - 1)));
  const colour = new THREE.Color().setHSL(0.66 * (1 - u), 0.85, 0.5);
  out[k] = colour.r; out[k + 1] = colour.g; out[k + 2] = colour.b;
}

const runs = (window.CLOTHLAB_RUNS || []).map((data, i) => ({
  ...data,
  swatch: SWATCHES[i % SWATCHES.length],
  // The frames' triangles, 3 vertex indices each, as the core triangulates the grid.
  triangles: new Uint32Array(decodeBytes(data.triangles)),
  positions: data.positions.map(decodeFloats),
  stretch: data.stretch.map(decodeFloats),
  colliders: data.colliders || [],
  collider_poses: data.collider_poses || [],
}));
const duration = Math.max(...runs.map((run) => run.times[run.times.length - 1]));
const maxStretch = Math.max(1.05, ...runs.flatMap((run) => run.stretch.map((s) => s.reduce((a, b) => Math.max(a, b), 1))));

// Where collider `i` of a run is in frame `index`: its position and orientation.
function colliderPose(run, index, i) {
  const p = run.collider_poses[index].slice(7 * i, 7 * i + 7);
  return { position: new THREE.Vector3(p[0], p[1], p[2]), orientation: new THREE.Quaternion(p[4], p[5], p[6], p[3]) };
}
// The largest distance of a bounded collider's surface from its origin; 0 for a plane.
function colliderReach(shape) {
  if (shape.shape === "sphere") return shape.radius;
  if (shape.shape === "capsule") return shape.half_length + Math.max(shape.radius, shape.end_radius);
  if (shape.shape === "box") return Math.hypot(...shape.half_extents);
  return 0;
}

// Bounds over every frame of every run, cloth and bounded colliders: the camera frames them all.
const bounds = new THREE.Box3();
for (const run of runs) {
  for (const frame of run.positions)
    for (let k = 0; k < frame.length; k += 3)
      bounds.expandByPoint(new THREE.Vector3(frame[k], frame[k + 1], frame[k + 2]));
  run.colliders.forEach((shape, i) => {
    const reach = colliderReach(shape);
    if (reach > 0)
      for (let index = 0; index < run.times.length; ++index)
        bounds.expandByPoint(colliderPose(run, index, i).position.addScalar(reach))
          .expandByPoint(colliderPose(run, index, i).position.addScalar(-reach));
  });
}
const centre = bounds.getCenter(new THREE.Vector3());
const radius = Math.max(1e-3, bounds.getSize(new THREE.Vector3()).length() / 2);

// A collider's shape in its own frame (clothlab/ext/colliders.h): a tapered capsule is drawn as
// its two end spheres joined by a truncated cone along x, a plane as a square of the view's
// size in y = 0.
function colliderObject(shape, material) {
  if (shape.shape === "sphere") return new THREE.Mesh(new THREE.SphereGeometry(shape.radius, 48, 24), material);
  if (shape.shape === "box") {
    const [x, y, z] = shape.half_extents;
    return new THREE.Mesh(new THREE.BoxGeometry(2 * x, 2 * y, 2 * z), material);
  }
  if (shape.shape === "capsule") {
    const group = new THREE.Group(), h = shape.half_length;
    const start = new THREE.Mesh(new THREE.SphereGeometry(shape.radius, 32, 16), material);
    const end = new THREE.Mesh(new THREE.SphereGeometry(shape.end_radius, 32, 16), material);
    start.position.x = -h;
    end.position.x = h;
    const side = new THREE.Mesh(new THREE.CylinderGeometry(shape.end_radius, shape.radius, 2 * h, 32, 1, true), material);
    side.rotation.z = -Math.PI / 2;  // the cylinder's +y axis onto +x
    group.add(start, end, side);
    return group;
  }
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(4 * radius, 4 * radius), material);
  plane.rotation.x = -Math.PI / 2;  // its +z normal onto +y
  return plane;
}

const view = document.getElementById("view");
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setClearColor(BACKGROUND);
renderer.autoClear = false;
view.appendChild(renderer.domElement);

for (const [i, run] of runs.entries()) {
  run.scene = new THREE.Scene();
  run.scene.add(new THREE.AmbientLight(0xffffff, 0.45));
  const light = new THREE.DirectionalLight(0xffffff, 0.9);
  light.position.set(1, 2, 3);
  run.scene.add(light);
  const geometry = new THREE.BufferGeometry();
  geometry.setIndex(new THREE.BufferAttribute(run.triangles, 1));
  geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(run.positions[0]), 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(new Float32Array(run.positions[0].length), 3));
  run.solid = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
  run.wire = new THREE.MeshBasicMaterial({ color: run.swatch, wireframe: true });
  run.mesh = new THREE.Mesh(geometry, run.solid);
  run.scene.add(run.mesh);
  const colliderMaterial = new THREE.MeshLambertMaterial({ color: COLLIDER_COLOUR, side: THREE.DoubleSide });
  run.colliderObjects = run.colliders.map((shape) => {
    const placed = new THREE.Object3D();
    placed.add(colliderObject(shape, colliderMaterial));
    placed.visible = params.get("colliders") !== "0";
    run.scene.add(placed);
    return placed;
  });
  run.label = document.createElement("div");
  run.label.className = "label";
  run.label.textContent = `${i + 1}: ${run.run.integrator} on ${run.run.scenario}`;
  view.appendChild(run.label);
  run.shown = -1;
}

// Orbit camera: drag to rotate about the scene's centre, wheel to zoom. It starts looking along
// the normal of the cloth's mean plane over every frame of every run (framing.js), at the
// distance that fits the bounds into the pane, whatever its aspect.
const camera = new THREE.PerspectiveCamera(40, 1, radius / 100, radius * 100);
const orbit = { ...ClothLabFraming.orbitAlong(ClothLabFraming.meanPlaneNormal(runs.flatMap((run) => run.positions))), zoom: 1 };
function placeCamera() {
  const { azimuth, elevation, zoom } = orbit;
  const fitted = ClothLabFraming.fitDistance(bounds.min.toArray(), bounds.max.toArray(), orbit,
                                             THREE.MathUtils.degToRad(camera.fov), camera.aspect);
  const direction = ClothLabFraming.orbitDirection(azimuth, elevation);
  camera.position.copy(centre).addScaledVector(new THREE.Vector3(...direction), Math.max(radius / 50, fitted) * zoom);
  camera.lookAt(centre);
  // Read by the browser tests (chromium --dump-dom), which need the camera's right axis.
  document.documentElement.dataset.orbit = JSON.stringify({ azimuth, elevation });
}
let drag = null;
view.addEventListener("pointerdown", (e) => { drag = { x: e.clientX, y: e.clientY }; view.setPointerCapture(e.pointerId); });
view.addEventListener("pointerup", () => { drag = null; });
view.addEventListener("pointermove", (e) => {
  if (!drag) return;
  orbit.azimuth -= (e.clientX - drag.x) * 0.01;
  orbit.elevation = Math.max(-1.5, Math.min(1.5, orbit.elevation + (e.clientY - drag.y) * 0.01));
  drag = { x: e.clientX, y: e.clientY };
  render();
});
view.addEventListener("wheel", (e) => { e.preventDefault(); orbit.zoom *= Math.exp(e.deltaY * 0.001); render(); }, { passive: false });

const ui = Object.fromEntries(["play", "scrub", "clock", "speed", "colour", "layout", "legend", "energy", "runs"]
  .map((id) => [id, document.getElementById(id)]));
const state = {
  t: Math.min(duration, Math.max(0, Number(params.get("t") || 0))),
  playing: params.get("paused") !== "1",
  speed: Number(params.get("speed") || 1),
};
ui.scrub.max = duration;
ui.speed.value = String(state.speed);
if (params.get("colour")) ui.colour.value = params.get("colour");
ui.layout.value = params.get("layout") || (runs.length > 1 ? "side" : "overlay");
ui.play.textContent = state.playing ? "Pause" : "Play";
ui.play.onclick = () => { state.playing = !state.playing; ui.play.textContent = state.playing ? "Pause" : "Play"; };
ui.scrub.oninput = () => { state.t = Number(ui.scrub.value); render(); };
ui.speed.onchange = () => { state.speed = Number(ui.speed.value); };
ui.colour.onchange = () => { for (const run of runs) run.shown = -1; render(); };
ui.layout.onchange = () => { for (const run of runs) run.shown = -1; render(); };
ui.legend.style.background = "linear-gradient(to right, hsl(238,85%,50%), hsl(120,85%,50%), hsl(60,85%,50%), hsl(0,85%,50%))";
ui.legend.append(element("span", "", "stretch 1.00"), element("span", "", maxStretch.toFixed(2)));

// The run panels. Every string from a run (its folder name, plugin ids, verdict, parameters)
// goes in as text, never as markup: a folder may be named anything.
function element(tag, className, text) {
  const node = document.createElement(tag);
  if (className) node.className = className;
  if (text !== undefined) node.textContent = text;
  return node;
}
function describeRuns() {
  for (const [i, run] of runs.entries()) {
    const info = run.run, summary = info.summary || {};
    const stable = summary.stable && !summary.interrupted;
    const verdict = summary.verdict || `no verdict (run.json status: ${info.status})`;
    const swatch = element("span", "swatch");
    swatch.style.background = "#" + run.swatch.toString(16).padStart(6, "0");
    const heading = element("h3");
    heading.append(swatch, `${i + 1}: ${info.integrator} on ${info.scenario}`);
    const div = element("div", "run");
    div.append(heading, element("div", "", run.name),
      element("div", "", `${info.rows ? `${info.rows}×${info.cols}` : `${run.vertices} vertices`}, ${info.precision}, dt ${info.dt} s, ${run.times.length} frames` +
        (summary.ms_per_step ? `, ${summary.ms_per_step.median.toFixed(3)} ms/step` : "")),
      element("div", `verdict ${stable ? "good" : "bad"}`, verdict),
      element("pre", "", `integrator ${JSON.stringify(info.integrator_params)}\nscenario ${JSON.stringify(info.scenario_params)}`));
    ui.runs.appendChild(div);
  }
}

// Total energy of each run over time, with the current time as a line.
function drawEnergy() {
  const canvas = ui.energy, g = canvas.getContext("2d");
  const w = canvas.width, h = canvas.height, left = 52, bottom = 22, top = 16;
  g.clearRect(0, 0, w, h);
  const totals = runs.map((run) => run.energy.map((e) => e[0] + e[1] + e[2]));
  let lo = Math.min(...totals.flat()), hi = Math.max(...totals.flat());
  if (!(hi > lo)) { lo -= 1; hi += 1; }
  const x = (t) => left + (w - left - 6) * (duration > 0 ? t / duration : 0);
  const y = (e) => top + (h - top - bottom) * (1 - (e - lo) / (hi - lo));
  g.fillStyle = "#bbb"; g.font = "11px sans-serif";
  g.fillText("total energy (J)", left, 11);
  g.fillText(hi.toPrecision(3), 2, top + 8);
  g.fillText(lo.toPrecision(3), 2, h - bottom);
  g.fillText("0", left, h - 6);
  g.fillText(`${duration.toFixed(2)} s`, w - 44, h - 6);
  g.strokeStyle = "#555"; g.strokeRect(left, top, w - left - 6, h - top - bottom);
  for (const [i, run] of runs.entries()) {
    g.strokeStyle = "#" + run.swatch.toString(16).padStart(6, "0");
    g.beginPath();
    totals[i].forEach((e, k) => (k ? g.lineTo(x(run.times[k]), y(e)) : g.moveTo(x(run.times[k]), y(e))));
    g.stroke();
  }
  g.strokeStyle = "#fff"; g.beginPath(); g.moveTo(x(state.t), top); g.lineTo(x(state.t), h - bottom); g.stroke();
}

function showFrame(run, overlaid) {
  const index = frameAt(run.times, state.t);
  if (index === run.shown) return;
  run.shown = index;
  const geometry = run.mesh.geometry;
  geometry.attributes.position.array.set(run.positions[index]);
  geometry.attributes.position.needsUpdate = true;
  geometry.computeVertexNormals();
  const colours = geometry.attributes.color.array, stretch = run.stretch[index];
  const plain = new THREE.Color(run.swatch);
  for (let v = 0; v < stretch.length; ++v) {
    if (ui.colour.value === "stretch") stretchColour(stretch[v], maxStretch, colours, 3 * v);
    else { colours[3 * v] = plain.r; colours[3 * v + 1] = plain.g; colours[3 * v + 2] = plain.b; }
  }
  geometry.attributes.color.needsUpdate = true;
  run.mesh.material = overlaid ? run.wire : run.solid;
  run.colliderObjects.forEach((placed, i) => {
    const pose = colliderPose(run, index, i);
    placed.position.copy(pose.position);
    placed.quaternion.copy(pose.orientation);
  });
}

function render() {
  const width = view.clientWidth, height = view.clientHeight;
  renderer.setSize(width, height, false);
  renderer.domElement.style.width = width + "px";
  renderer.domElement.style.height = height + "px";
  const side = ui.layout.value === "side" && runs.length > 1;
  const panes = side ? runs.length : 1;
  const paneWidth = Math.floor(width / panes);
  camera.aspect = paneWidth / height;
  camera.updateProjectionMatrix();
  placeCamera();
  renderer.setScissorTest(true);
  renderer.setViewport(0, 0, width, height);
  renderer.setScissor(0, 0, width, height);
  renderer.clear();
  for (const [i, run] of runs.entries()) {
    showFrame(run, !side && i > 0);
    const pane = side ? i : 0;
    renderer.setViewport(pane * paneWidth, 0, paneWidth, height);
    renderer.setScissor(pane * paneWidth, 0, paneWidth, height);
    renderer.render(run.scene, camera);
    run.label.style.left = `${pane * paneWidth + 6}px`;
    run.label.style.top = `${6 + (side ? 0 : 22 * i)}px`;
  }
  ui.scrub.value = state.t;
  ui.clock.textContent = `${state.t.toFixed(3)} s`;
  drawEnergy();
  document.title = `ClothLab viewer t=${state.t.toFixed(3)}`;
}

let last = null;
function tick(now) {
  if (state.playing && last !== null) {
    state.t += ((now - last) / 1000) * state.speed;
    if (state.t > duration) state.t = 0;
    render();
  }
  last = now;
  requestAnimationFrame(tick);
}

describeRuns();
window.addEventListener("resize", render);
render();
requestAnimationFrame(tick);
