// bullet_sim's live viewer: draws what the simulator's WebSocket (/ws) sends (a scene, then frames and camera
// images) and sends back pause, resume, reset, teleop and the camera to watch. World frame: x east, y north, z up.
import * as THREE from './three/build/three.module.js';
import { OrbitControls } from './three/examples/jsm/controls/OrbitControls.js';

const POSITION_UNIT = 1e-4;  // [m] of a geometry's integer positions
const TELEOP_PERIOD = 100;   // [ms] between commands while a pad button is held
const TURN_PER_SPEED = 1.5;  // [rad/s per m/s] of the pad's turns
const RECONNECT_DELAY = 2000;  // [ms]
const MIN_VIEW_SIZE = 1.5;     // [m] the first view frames at least this much around a small robot

const $ = (id) => document.getElementById(id);

// What the page knows, for people at the console and for tests.
const state = {
  connected: false, control: false, frames: 0, images: 0, revision: 0,
  time: null, rtf: null, paused: null, robots: {}, message: '',
};
window.bulletSim = state;

// The 3D view, lit as bullet_sim's own renderer lights its snapshots.
const canvas = $('view');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const world = new THREE.Scene();
world.background = new THREE.Color(0.78, 0.84, 0.9);
world.add(new THREE.AmbientLight(0xffffff, 0.45));
const sun = new THREE.DirectionalLight(0xffffff, 0.55);
sun.position.set(-0.4, 0.3, 1);
world.add(sun);
world.add(groundGrid(20));
const camera = new THREE.PerspectiveCamera(45, 1, 0.05, 500);
camera.up.set(0, 0, 1);
camera.position.set(-4, -4, 3);
const controls = new OrbitControls(camera, canvas);
controls.addEventListener('change', requestDraw);
const hitsGeometry = new THREE.BufferGeometry();
const hits = new THREE.Points(hitsGeometry, new THREE.PointsMaterial({ color: 0xff0000, size: 4, sizeAttenuation: false }));
hits.frustumCulled = false;
world.add(hits);

// Lines every metre on the ground, out to `half` metres, as 1 m segments: some WebGL implementations
// (SwiftShader) drop a whole line that passes behind the camera.
function groundGrid(half) {
  const points = [];
  for (let i = -half; i <= half; ++i) {
    for (let j = -half; j < half; ++j) points.push(i, j, 0, i, j + 1, 0, j, i, 0, j + 1, i, 0);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(points), 3));
  const grid = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0x595959 }));
  grid.position.z = 0.002;  // above the ground plane, not in it
  return grid;
}

let layout = null;     // the scene message drawn now
let bodies = [];       // a THREE.Group per body of the layout
let framed = false;    // the camera was placed for the first scene
let socket = null;
let drawPending = false;

function requestDraw() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => {
    drawPending = false;
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.floor(width * window.devicePixelRatio)) renderer.setSize(width, height, false);
    camera.aspect = width / Math.max(1, height);
    camera.updateProjectionMatrix();
    renderer.render(world, camera);
    state.draws = (state.draws || 0) + 1;
  });
}
window.addEventListener('resize', requestDraw);

function setPose(object, values, at) {
  object.position.set(values[at], values[at + 1], values[at + 2]);
  object.quaternion.set(values[at + 3], values[at + 4], values[at + 5], values[at + 6]);
}

function makeGeometry(message, parts) {
  const geometry = new THREE.BufferGeometry();
  const positions = new Float32Array(message.positions.length);
  for (let i = 0; i < positions.length; ++i) positions[i] = message.positions[i] * POSITION_UNIT;
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(message.indices), 1));
  geometry.computeVertexNormals();
  parts.forEach(([first, count], i) => geometry.addGroup(3 * first, 3 * count, i));
  return geometry;
}

function material([, , r, g, b, a]) {
  return new THREE.MeshPhongMaterial({
    color: new THREE.Color(r, g, b), flatShading: true, shininess: 0, specular: 0x000000,
    side: THREE.DoubleSide, transparent: a < 1, opacity: a,
  });
}

function clearLayout() {
  for (const body of bodies) {
    world.remove(body);
    body.traverse((object) => { if (object.material) object.material.forEach((m) => m.dispose()); });
  }
  const geometries = new Set();
  for (const body of bodies) body.traverse((object) => { if (object.geometry) geometries.add(object.geometry); });
  geometries.forEach((geometry) => geometry.dispose());
  bodies = [];
}

function applyScene(message) {
  clearLayout();
  layout = message;
  bodies = message.bodies.map((body) => {
    const group = new THREE.Group();
    group.name = body.name;
    setPose(group, body.pose, 0);
    world.add(group);
    return group;
  });
  const geometries = [];
  for (const mesh of message.meshes) {
    if (!geometries[mesh.geometry]) geometries[mesh.geometry] = makeGeometry(message.geometries[mesh.geometry], mesh.parts);
    const object = new THREE.Mesh(geometries[mesh.geometry], mesh.parts.map(material));
    setPose(object, mesh.pose, 0);
    bodies[mesh.body].add(object);
  }
  state.revision = message.revision;
  fillSelect($('robot'), message.robots.filter((robot) => robot.teleop).map((robot) => robot.name), null);
  fillSelect($('camera'), message.cameras, 'none');
  if (!framed) frameView(message);
  updateRobots();
  requestDraw();
}

function fillSelect(select, names, noneLabel) {
  const chosen = select.value;
  select.innerHTML = '';
  if (noneLabel) select.add(new Option(noneLabel, ''));
  for (const name of names) select.add(new Option(name, name));
  if ([...select.options].some((option) => option.value === chosen)) select.value = chosen;
  select.dispatchEvent(new Event('change'));
}

// Looks at the first robot from behind its left shoulder, or at the whole world when there is none.
function frameView(message) {
  const robot = message.robots[0];
  let target, size;
  if (robot) {
    const box = new THREE.Box3().setFromObject(robotObject(robot));
    target = box.getCenter(new THREE.Vector3());
    size = Math.max(box.getSize(new THREE.Vector3()).length(), MIN_VIEW_SIZE);
  } else if (message.bounds) {
    const [x0, y0, z0, x1, y1, z1] = message.bounds;
    target = new THREE.Vector3((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
    size = Math.hypot(x1 - x0, y1 - y0, z1 - z0);
  } else {
    return;
  }
  controls.target.copy(target);
  camera.position.copy(target).add(new THREE.Vector3(-1.2, -1.6, 1.2).multiplyScalar(size * 1.1));
  controls.update();
  framed = true;
}

// The bodies of a robot, as one object for bounds.
function robotObject(robot) {
  const group = new THREE.Group();
  const prefix = robot.name + '::';
  bodies.filter((body) => body.name.startsWith(prefix)).forEach((body) => group.add(body.clone()));
  return group;
}

function updateRobots() {
  if (!layout) return;
  state.robots = {};
  for (const robot of layout.robots) {
    const body = bodies[robot.body];
    const yaw = new THREE.Euler().setFromQuaternion(body.quaternion, 'ZYX').z;
    state.robots[robot.name] = { x: body.position.x, y: body.position.y, z: body.position.z, yaw };
  }
}

let lastFollowed = null;
function follow() {
  const name = $('robot').value;
  const robot = $('follow').checked && layout && layout.robots.find((each) => each.name === name);
  if (!robot) { lastFollowed = null; return; }
  const position = bodies[robot.body].position;
  if (lastFollowed) {
    const moved = position.clone().sub(lastFollowed);
    camera.position.add(moved);
    controls.target.add(moved);
    controls.update();
  }
  lastFollowed = position.clone();
}

function applyFrame(frame) {
  if (!layout || frame.revision !== layout.revision) return;
  for (let i = 0; i < frame.poses.length; i += 8) setPose(bodies[frame.poses[i]], frame.poses, i + 1);
  hitsGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(frame.hits), 3));
  hitsGeometry.computeBoundingSphere();
  Object.assign(state, { frames: state.frames + 1, time: frame.time, rtf: frame.rtf, paused: frame.paused });
  $('time').textContent = frame.time.toFixed(3) + ' s';
  $('rtf').textContent = frame.rtf.toFixed(2);
  $('state').textContent = frame.paused ? 'paused' : 'running';
  updateRobots();
  follow();
  requestDraw();
}

// A binary message: a 4-byte little-endian header length, the JSON header, then the pixels.
function applyImage(buffer) {
  const length = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
  if (header.camera !== $('camera').value) return;
  const pixels = new Uint8Array(buffer, 4 + length);
  const image = $('image');
  image.width = header.width;
  image.height = header.height;
  const context = image.getContext('2d');
  const rgba = context.createImageData(header.width, header.height);
  toRgba(header, pixels, rgba.data);
  context.putImageData(rgba, 0, 0);
  state.images += 1;
}

function toRgba(header, pixels, out) {
  const { width, height, step, encoding } = header;
  const view = new DataView(pixels.buffer, pixels.byteOffset, pixels.byteLength);
  for (let row = 0; row < height; ++row) {
    for (let column = 0; column < width; ++column) {
      const o = 4 * (row * width + column), at = row * step;
      let rgb;
      if (encoding === 'rgb8') rgb = [pixels[at + 3 * column], pixels[at + 3 * column + 1], pixels[at + 3 * column + 2]];
      else if (encoding === 'bgr8') rgb = [pixels[at + 3 * column + 2], pixels[at + 3 * column + 1], pixels[at + 3 * column]];
      else if (encoding === 'mono8') rgb = Array(3).fill(pixels[at + column]);
      else if (encoding === '32FC1') rgb = Array(3).fill(depthGrey(view.getFloat32(at + 4 * column, true)));
      else if (encoding === '16UC1') rgb = Array(3).fill(depthGrey(view.getUint16(at + 2 * column, true) / 1000));
      else rgb = [255, 0, 255];
      out.set([rgb[0], rgb[1], rgb[2], 255], o);
    }
  }
}

// Depth [m] as grey: white near, black at 10 m and where nothing is seen.
function depthGrey(metres) {
  return Number.isFinite(metres) && metres > 0 ? Math.round(255 * Math.max(0, 1 - metres / 10)) : 0;
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function onMessage(event) {
  if (event.data instanceof ArrayBuffer) {
    applyImage(event.data);
    send({ type: 'ack' });  // the server sends the next frame or image only when this one is taken in
    return;
  }
  const message = JSON.parse(event.data);
  if (message.type === 'hello') {
    state.control = message.control;
    document.body.classList.toggle('readonly', !message.control);
  } else if (message.type === 'scene') {
    applyScene(message);
  } else if (message.type === 'frame') {
    applyFrame(message);
    send({ type: 'ack' });
  } else if (message.type === 'error') {
    state.message = message.message;
    $('message').textContent = message.message;
  }
}

function connect() {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  socket = new WebSocket(scheme + '//' + location.host + '/ws');
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => {
    state.connected = true;
    $('state').textContent = 'connected';
    send({ type: 'camera', name: $('camera').value });
  };
  socket.onmessage = onMessage;
  socket.onclose = () => {
    state.connected = false;
    $('state').textContent = 'disconnected: retrying';
    setTimeout(connect, RECONNECT_DELAY);
  };
}

// Teleop: a pad button or an arrow key held sends its command every TELEOP_PERIOD; letting go stops the robot.
let held = null;
let teleopTimer = null;
function teleop(linear, angular) {
  const robot = $('robot').value;
  const speed = Number($('speed').value);
  if (robot) send({ type: 'teleop', robot, linear: linear * speed, angular: angular * speed * TURN_PER_SPEED });
}
function hold(button) {
  release();
  held = button;
  button.classList.add('held');
  const go = () => teleop(Number(button.dataset.linear), Number(button.dataset.angular));
  go();
  teleopTimer = setInterval(go, TELEOP_PERIOD);
}
function release() {
  if (!held) return;
  clearInterval(teleopTimer);
  held.classList.remove('held');
  held = null;
  teleop(0, 0);
}
for (const button of document.querySelectorAll('#pad button')) {
  button.addEventListener('pointerdown', (event) => { event.preventDefault(); hold(button); });
  button.addEventListener('pointerup', release);
  button.addEventListener('pointerleave', release);
}
const KEYS = { ArrowUp: 'forward', ArrowDown: 'back', ArrowLeft: 'left', ArrowRight: 'right' };
window.addEventListener('keydown', (event) => {
  if (!KEYS[event.key] || event.repeat || event.target.tagName === 'SELECT') return;
  hold($(KEYS[event.key]));
  event.preventDefault();
});
window.addEventListener('keyup', (event) => { if (KEYS[event.key]) release(); });
window.addEventListener('blur', release);

$('pause').addEventListener('click', () => send({ type: 'pause' }));
$('resume').addEventListener('click', () => send({ type: 'resume' }));
$('reset').addEventListener('click', () => send({ type: 'reset' }));
$('speed').addEventListener('input', () => { $('speed_value').textContent = $('speed').value + ' m/s'; });
$('camera').addEventListener('change', () => {
  send({ type: 'camera', name: $('camera').value });
  $('image').width = $('image').height = 0;
});
$('follow').addEventListener('change', () => { lastFollowed = null; follow(); });

// For tests and the console: the camera and its controls (call view.draw() after moving them).
state.view = { camera, controls, draw: requestDraw };
// For tests: where a world point appears in the view, in CSS pixels from the page's top-left corner.
state.project = (x, y, z) => {
  const point = new THREE.Vector3(x, y, z).project(camera);
  return [(point.x + 1) / 2 * canvas.clientWidth, (1 - point.y) / 2 * canvas.clientHeight];
};
// The screen box [left, top, right, bottom] of a robot's meshes, in CSS pixels.
state.screenBox = (name) => {
  const box = new THREE.Box3().setFromObject(robotObject({ name }));
  const corners = [];
  for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y]) for (const z of [box.min.z, box.max.z]) {
    corners.push(state.project(x, y, z));
  }
  const xs = corners.map((c) => c[0]), ys = corners.map((c) => c[1]);
  return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
};

connect();
requestDraw();
