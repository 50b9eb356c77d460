// The replay page of `declutter show`. Reads the scene blob, builds three.js meshes,
// and moves them by interpolating the keyframes Rust computed. Writes a small report
// into #report (ready, errors, pixels painted, where the target is) for tests.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const S = JSON.parse(document.getElementById('scene').textContent);
const BACKGROUND = 0xf4f5f7;
const $ = (id) => document.getElementById(id);

// ---- renderer, camera, lights
const view = $('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(BACKGROUND);
const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(2, -3, 4);
scene.add(sun);
const grid = new THREE.GridHelper(4, 40, 0xc8cbd0, 0xdfe1e5);
grid.rotation.x = Math.PI / 2; // the world's z is up
scene.add(grid);
scene.add(new THREE.AxesHelper(0.3));

// ---- bodies
function setPose(obj, p, o = 0) {
  obj.position.set(p[o], p[o + 1], p[o + 2]);
  obj.quaternion.set(p[o + 3], p[o + 4], p[o + 5], p[o + 6]);
}

function geometry(s) {
  switch (s.type) {
    case 'box': return new THREE.BoxGeometry(s.size[0], s.size[1], s.size[2]);
    case 'cylinder': return new THREE.CylinderGeometry(s.radius, s.radius, s.length, 32);
    case 'sphere': return new THREE.SphereGeometry(s.radius, 24, 16);
    default: {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(s.vertices, 3));
      g.setIndex(s.triangles);
      // Flat shading: hulls and machined parts read better with sharp edges.
      const flat = g.toNonIndexed();
      flat.computeVertexNormals();
      return flat;
    }
  }
}

const groups = S.bodies.map((b, i) => {
  const group = new THREE.Group();
  group.userData.body = i;
  const material = new THREE.MeshStandardMaterial({ color: b.colour, roughness: 0.65, metalness: 0.05 });
  // Fixed bodies other than the floor are see-through: objects inside crates and
  // shelves stay visible.
  if (b.kind === 'fixed' && b.name !== 'table') Object.assign(material, { transparent: true, opacity: 0.45, depthWrite: false });
  for (const s of b.shapes) {
    const mesh = new THREE.Mesh(geometry(s), material);
    setPose(mesh, s.pose);
    mesh.userData.body = i;
    group.add(mesh);
  }
  if (b.kind === 'tcp') group.add(new THREE.AxesHelper(0.06));
  if (b.pose) setPose(group, b.pose);
  group.userData.material = material;
  scene.add(group);
  return group;
});

const targetIndex = S.bodies.findIndex((b) => b.role === 'target');
const targetAction = S.actions.find((a) => targetIndex >= 0 && a.object === S.bodies[targetIndex].name);
const holderTcp = targetAction ? S.bodies.findIndex((b) => b.kind === 'tcp' && S.robots[b.robot] === targetAction.robot) : -1;

// ---- violations, in red at their place
const violationMarks = S.violations.map((v) => {
  if (!v.at) return null;
  const m = new THREE.Mesh(new THREE.SphereGeometry(0.025, 16, 12),
    new THREE.MeshBasicMaterial({ color: 0xd0021b, transparent: true, opacity: 0.85, depthTest: false }));
  m.position.set(v.at[0], v.at[1], v.at[2]);
  m.renderOrder = 10;
  scene.add(m);
  return m;
});

// ---- time
let t = 0;
let playing = false;
let speed = 1;
const q0 = new THREE.Quaternion();
const q1 = new THREE.Quaternion();

function apply(time) {
  t = Math.min(Math.max(time, 0), S.duration);
  const f = S.frames > 1 ? t / S.step : 0;
  const k = Math.min(Math.floor(f), S.frames - 1);
  const k1 = Math.min(k + 1, S.frames - 1);
  const s = Math.min(f - k, 1);
  const a = S.poses[k];
  const b = S.poses[k1];
  S.bodies.forEach((body, i) => {
    const g = groups[i];
    if (body.track !== undefined) {
      const o = body.track * 7;
      g.position.set(a[o] + (b[o] - a[o]) * s, a[o + 1] + (b[o + 1] - a[o + 1]) * s, a[o + 2] + (b[o + 2] - a[o + 2]) * s);
      q0.set(a[o + 3], a[o + 4], a[o + 5], a[o + 6]);
      q1.set(b[o + 3], b[o + 4], b[o + 5], b[o + 6]);
      g.quaternion.slerpQuaternions(q0, q1, s);
    }
    if (body.released_at !== undefined) g.visible = t < body.released_at;
  });
  S.violations.forEach((v, i) => {
    const m = violationMarks[i];
    if (m) m.scale.setScalar(v.t !== undefined && Math.abs(v.t - t) < 0.5 ? 2.0 : 1.0);
  });
  updatePanel();
}

// ---- panel
const status = $('status');
status.className = S.status;
status.textContent = S.status === 'cell' ? 'The cell (no schedule given)'
  : S.status === 'verified' ? `Verified: ${S.actions.length} action${S.actions.length === 1 ? '' : 's'}`
  : `Does not verify: ${S.violations.length} violation${S.violations.length === 1 ? '' : 's'}`;

function item(list, html, onClick) {
  const li = document.createElement('li');
  li.innerHTML = html;
  if (onClick) li.addEventListener('click', onClick);
  list.appendChild(li);
  return li;
}
const esc = (s) => String(s).replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
const robotColour = (name) => {
  const mine = S.bodies.filter((b) => b.robot !== undefined && S.robots[b.robot] === name);
  const b = mine.find((x) => x.kind === 'hand') || mine[0];
  return b ? b.colour : '#999';
};

const actionItems = S.actions.map((a) => item($('actions'),
  `<span class="swatch" style="background:${robotColour(a.robot)}"></span>#${a.id} ${esc(a.robot)}: ${a.object ? 'remove ' + esc(a.object) : 'reach the target'}`
  + (a.after.length ? ` <small>(after ${a.after.map((x) => '#' + x).join(', ')})</small>` : ''),
  () => seek(a.start)));
const violationItems = S.violations.map((v) => item($('violations'), esc(v.text),
  v.t !== undefined ? () => seek(v.t) : null));
if (!S.violations.length) $('violations-box').hidden = true;
S.bodies.forEach((b, i) => {
  if (b.kind === 'tcp' || !b.shapes.length) return;
  const li = item($('bodies'), `<span class="swatch" style="background:${b.colour}"></span>${esc(b.name)}`
    + (b.role ? ` <small>(${b.role})</small>` : ''));
  li.addEventListener('mouseenter', () => highlight(i));
  li.addEventListener('mouseleave', () => highlight(-1));
});

function updatePanel() {
  const now = S.actions.filter((a) => a.start <= t && t < a.end);
  $('now').textContent = now.length ? now.map((a) => `#${a.id} ${a.robot}` + (a.object ? ` removes ${a.object}` : ' reaches the target')).join('; ') : (S.actions.length ? '—' : 'no schedule');
  S.actions.forEach((a, i) => actionItems[i].classList.toggle('current', now.includes(a)));
  S.violations.forEach((v, i) => violationItems[i].classList.toggle('current', v.t !== undefined && Math.abs(v.t - t) < 0.5));
  $('slider').value = String(t);
  $('clock').textContent = `${t.toFixed(2)} / ${S.duration.toFixed(2)} s`;
}

let highlighted = -1;
function highlight(i) {
  if (highlighted >= 0) groups[highlighted].userData.material.emissive.setHex(0x000000);
  highlighted = i;
  if (i >= 0) groups[i].userData.material.emissive.setHex(0x333300);
}

// ---- timeline controls
const slider = $('slider');
slider.max = String(S.duration);
slider.step = String(Math.max(S.duration / 1000, 0.001));
slider.addEventListener('input', () => { playing = false; setPlayLabel(); seek(parseFloat(slider.value)); });
$('speed').addEventListener('change', (e) => { speed = parseFloat(e.target.value); });
function setPlayLabel() { $('play').textContent = playing ? '❚❚' : '▶'; }
$('play').addEventListener('click', togglePlay);
function togglePlay() {
  if (!playing && t >= S.duration) t = 0;
  playing = !playing && S.duration > 0;
  setPlayLabel();
}
window.addEventListener('keydown', (e) => { if (e.code === 'Space' && e.target.tagName !== 'SELECT') { e.preventDefault(); togglePlay(); } });
for (const v of S.violations) {
  if (v.t === undefined || !(S.duration > 0)) continue;
  const m = document.createElement('span');
  m.className = 'bad';
  m.style.left = `${(100 * v.t) / S.duration}%`;
  m.title = v.text;
  $('marks').appendChild(m);
}

function seek(time) { apply(time); render(); }

// ---- hover names
const ray = new THREE.Raycaster();
const pointer = new THREE.Vector2();
const tip = $('tip');
renderer.domElement.addEventListener('pointermove', (e) => {
  const r = renderer.domElement.getBoundingClientRect();
  pointer.set(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  ray.setFromCamera(pointer, camera);
  const hit = ray.intersectObjects(groups, true).find((h) => h.object.visible && h.object.userData.body !== undefined);
  if (hit) {
    const b = S.bodies[hit.object.userData.body];
    tip.textContent = b.name + (b.role ? ` (${b.role})` : '');
    tip.style.left = `${e.clientX - r.left + 12}px`;
    tip.style.top = `${e.clientY - r.top + 12}px`;
    tip.style.display = 'block';
  } else {
    tip.style.display = 'none';
  }
});

// ---- size, camera framing, render loop
function resize() {
  const w = Math.max(view.clientWidth, 1);
  const h = Math.max(view.clientHeight, 1);
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
function frame() {
  const box = new THREE.Box3();
  groups.forEach((g, i) => { if (S.bodies[i].shapes.length && S.bodies[i].name !== 'table') box.expandByObject(g); });
  if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
  const c = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.3);
  const dist = radius / Math.sin((camera.fov * Math.PI) / 360) * 1.05;
  const cam = new URLSearchParams(location.hash.slice(1)).get('cam');
  const v = cam ? cam.split(',').map(Number) : [];
  const dir = (v.length === 3 && v.every(Number.isFinite) ? new THREE.Vector3(...v) : new THREE.Vector3(1.0, -0.8, 0.75)).normalize();
  camera.position.copy(c).addScaledVector(dir, dist);
  controls.target.copy(c);
  controls.update();
  // The floor grid just under everything (the table's top is often at z = 0).
  const all = new THREE.Box3();
  groups.forEach((g) => all.expandByObject(g));
  if (!all.isEmpty()) grid.position.z = all.min.z - 0.002;
}
function render() { renderer.render(scene, camera); }
controls.addEventListener('change', render);
window.addEventListener('resize', () => { resize(); render(); });

let last = null;
renderer.setAnimationLoop((now) => {
  if (playing) {
    if (last !== null) apply(t + ((now - last) / 1000) * speed);
    if (t >= S.duration) { playing = false; setPlayLabel(); }
    render();
  }
  last = now;
});

// ---- start: `#t=SECONDS` or `#at=FRACTION` opens paused there; otherwise play from 0.
// The hash may also hold a camera: `cam=x,y,z` (a direction to look from).
function requested() {
  const h = new URLSearchParams(location.hash.slice(1));
  if (h.has('t')) return parseFloat(h.get('t'));
  if (h.has('at')) return parseFloat(h.get('at')) * S.duration;
  return null;
}
// `#…&bare` leaves only the 3-D view (for pictures).
if (new URLSearchParams(location.hash.slice(1)).has('bare')) document.body.classList.add('bare');
resize();
apply(0);
frame();
const at = requested();
if (at !== null && Number.isFinite(at)) apply(at);
render();
playing = at === null && S.duration > 0;
setPlayLabel();

// ---- report for tests: pixels painted (not background) and where the target is
function painted() {
  const gl = renderer.getContext();
  const w = gl.drawingBufferWidth;
  const h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const bg = new THREE.Color(BACKGROUND);
  const [r0, g0, b0] = [bg.r, bg.g, bg.b].map((x) => Math.round(x * 255));
  let n = 0;
  for (let i = 0; i < px.length; i += 4) {
    if (Math.abs(px[i] - r0) + Math.abs(px[i + 1] - g0) + Math.abs(px[i + 2] - b0) > 24) n++;
  }
  return n;
}
const report = {
  ready: true, errors: window.pageErrors, t, duration: S.duration, painted: painted(), status: S.status,
  violations: S.violations.length, marked: violationMarks.filter(Boolean).length,
};
if (targetIndex >= 0) {
  const p = groups[targetIndex].position;
  const start = S.poses[0].slice(S.bodies[targetIndex].track * 7, S.bodies[targetIndex].track * 7 + 3);
  report.target = { visible: groups[targetIndex].visible, position: p.toArray(), moved: p.distanceTo(new THREE.Vector3(...start)) };
  if (holderTcp >= 0) {
    report.target.to_tcp = p.distanceTo(groups[holderTcp].position);
    report.target.grasped_at = S.bodies[targetIndex].grasped_at;
    report.target.released_at = S.bodies[targetIndex].released_at;
  }
}
$('report').textContent = JSON.stringify(report);
window.report = report;
window.ready = true;
document.body.dataset.ready = 'true';
