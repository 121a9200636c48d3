// penalty's browser viewer (docs/viewer.md): reads run.json, topology.u32, positions.f32 and
// contacts.f32 from the directory the page is served from and draws the run with three.js.
import * as THREE from './three.module.min.js';
import { OrbitControls } from './OrbitControls.js';

const $ = (id) => document.getElementById(id);
const BACKGROUND = 0x1e2228;
// Body colours: muted (CIELAB chroma about 28, lightness 60–72), ten hues around the circle, so
// that the vivid contact colours below stand out on every one of them (docs/viewer.md, "Colours").
const PALETTE = [0x5d9dc4, 0xd2a180, 0x84aa7f, 0xc58397, 0x9f95c6, 0x5eb4ae, 0xbfb07d, 0xcc8a83, 0xb082aa, 0x77b89d];

// ---------------------------------------------------------------------------------------------
// Data

async function fetchChecked(name, kind) {
  const response = await fetch(name, { cache: 'no-store' });
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  return kind === 'json' ? response.json() : response.arrayBuffer();
}

async function loadRun() {
  const [run, topology, positions, contacts] = await Promise.all([
    fetchChecked('run.json', 'json'), fetchChecked('topology.u32'), fetchChecked('positions.f32'),
    fetchChecked('contacts.f32'),
  ]);
  if (run.format !== 'penalty-viewer') throw new Error('run.json is not a penalty viewer manifest');
  const frames = run.frames.count;
  if (frames === 0) throw new Error('the run has no frame (it stopped before writing one)');
  const positionArray = new Float32Array(positions);
  // Version 2 (topological changes): the states' sizes and the shapes' elements change from one
  // layout to the next; a version 1 run has one layout and frames of frame_floats floats each.
  if (!run.layouts) {
    run.layouts = [{ frame_floats: run.frame_floats, states: run.states, shapes: run.shapes }];
    run.frames.layout = new Array(frames).fill(0);
    run.frames.position_offset = Array.from({ length: frames }, (_, f) => f * run.frame_floats);
  }
  const needed = run.frames.position_offset[frames - 1] + run.layouts[run.frames.layout[frames - 1]].frame_floats;
  if (positionArray.length < needed)
    throw new Error(`positions.f32 holds ${positionArray.length} floats, ${frames} frames need ${needed}`);
  // Contacts of frame f: floats [offset[f], offset[f + 1]) of contacts.f32, 10 per contact.
  const contactOffset = new Array(frames + 1);
  contactOffset[0] = 0;
  for (let f = 0; f < frames; f++) contactOffset[f + 1] = contactOffset[f] + run.frames.contacts[f] * run.contact_floats;
  // Tunnelling-guard crossings (docs/no-tunnelling.md), when the run has some: 3 floats each.
  let crossings = new Float32Array(0);
  const crossingOffset = new Array(frames + 1).fill(0);
  if (run.frames.crossings) {
    crossings = new Float32Array(await fetchChecked('crossings.f32'));
    for (let f = 0; f < frames; f++) crossingOffset[f + 1] = crossingOffset[f] + 3 * run.frames.crossings[f];
  }
  return { run, topology: new Uint32Array(topology), positions: positionArray, contacts: new Float32Array(contacts),
           contactOffset, crossings, crossingOffset };
}

// ---------------------------------------------------------------------------------------------
// Colour map of the normal force: 0 → green, ⅓ → yellow, ⅔ → orange, 1 → magenta. Every colour of
// it is saturated and bright (CIELAB chroma ≥ 77): at least ΔE 49 from every body colour of the
// palette under any lighting (0.35× to 1.4× brightness) and from the background; the browser test
// checks both, and the pixels of drawn contacts against the bodies under them.

const RAMP = [[0.1, 1.0, 0.3], [1.0, 1.0, 0.0], [1.0, 0.45, 0.0], [1.0, 0.0, 0.8]];
function forceColor(u, out) {
  const x = Math.min(Math.max(u, 0), 1) * (RAMP.length - 1);
  const i = Math.min(Math.floor(x), RAMP.length - 2);
  const t = x - i;
  for (let k = 0; k < 3; k++) out[k] = RAMP[i][k] * (1 - t) + RAMP[i + 1][k] * t;
  return out;
}

/// forceColor in linear light, for vertex colours: three.js renders in linear light and converts to
/// sRGB on output (as it does for every material colour), so the drawn contact has the sRGB colour
/// of the map and of the colour bar. A table of 256 entries.
const FORCE_COLOR_LINEAR = (() => {
  const table = new Float32Array(256 * 3);
  const rgb = [0, 0, 0];
  const toLinear = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);
  for (let j = 0; j < 256; j++) {
    forceColor(j / 255, rgb);
    for (let k = 0; k < 3; k++) table[3 * j + k] = toLinear(rgb[k]);
  }
  return table;
})();

/// A white disc on transparent black: points are drawn as round dots (alphaTest cuts the corners).
/// With `ring`, the disc has a dark rim (the vertex colour tints the white centre only), which
/// separates a contact dot from a light surface as its colour does from a dark one.
const discTextures = new Map();
function disc(ring = false) {
  if (discTextures.has(ring)) return discTextures.get(ring);
  const c = document.createElement('canvas');
  c.width = c.height = 64;
  const g = c.getContext('2d');
  g.fillStyle = ring ? '#101010' : '#fff';
  g.beginPath();
  g.arc(32, 32, 30, 0, 2 * Math.PI);
  g.fill();
  if (ring) {
    g.fillStyle = '#fff';
    g.beginPath();
    g.arc(32, 32, 19, 0, 2 * Math.PI);
    g.fill();
  }
  const texture = new THREE.CanvasTexture(c);
  discTextures.set(ring, texture);
  return texture;
}

function formatNumber(x) {
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e4 || a < 1e-2 ? x.toExponential(2) : x.toPrecision(4).replace(/(\.\d*?)0+$/, '$1').replace(/\.$/, '');
}

// ---------------------------------------------------------------------------------------------
// Scene objects, one per shape

class ShapeView {
  constructor(shape, state, run, topology, color) {
    this.shape = shape;
    this.state = state;
    this.stride = state.type === 'Rigid3d' ? 7 : 3;
    this.indices = topology.subarray(shape.index_offset, shape.index_offset + shape.index_count);
    this.color = color;
    const material = (extra) => new THREE.MeshPhongMaterial({ color, flatShading: true, side: THREE.DoubleSide,
                                                              shininess: 20, ...extra });
    if (shape.kind === 'triangles' || shape.kind === 'lines' || shape.kind === 'points') {
      this.geometry = new THREE.BufferGeometry();
      this.positionAttribute = new THREE.BufferAttribute(new Float32Array(state.dofs * 3), 3);
      this.positionAttribute.setUsage(THREE.DynamicDrawUsage);
      this.geometry.setAttribute('position', this.positionAttribute);
      this.geometry.setIndex(new THREE.BufferAttribute(this.indices, 1));
      if (shape.kind === 'triangles') {
        this.object = new THREE.Mesh(this.geometry, material({ polygonOffset: true, polygonOffsetFactor: 1,
                                                               polygonOffsetUnits: 1 }));
        this.edges = new THREE.LineSegments(new THREE.WireframeGeometry(this.geometry),
                                            new THREE.LineBasicMaterial({ color: 0x000000, transparent: true,
                                                                          opacity: 0.35 }));
        this.edges.visible = false;
        this.object.add(this.edges);
      } else if (shape.kind === 'lines') {
        this.object = new THREE.LineSegments(this.geometry, new THREE.LineBasicMaterial({ color }));
      } else {
        this.object = new THREE.Points(this.geometry, new THREE.PointsMaterial({ color, size: 7, sizeAttenuation: false, map: disc(),
                                                                                alphaTest: 0.5 }));
      }
    } else {
      const n = shape.index_count;
      const geometry = shape.kind === 'spheres' ? new THREE.SphereGeometry(1, 32, 20)
                                                : new THREE.CylinderGeometry(1, 1, 1, 32, 1);
      this.object = new THREE.InstancedMesh(geometry, material({ flatShading: false, shininess: 40 }), n);
      this.object.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      // Cylinders: three's cylinder runs along y; turn it onto the shape's local axis.
      this.align = [];
      if (shape.kind === 'cylinders') {
        for (let e = 0; e < n; e++) {
          const axis = new THREE.Vector3(...shape.axis[e]).normalize();
          this.align.push(new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis));
        }
      }
    }
    this.object.name = shape.name;
    this.object.frustumCulled = false;  // moving geometry: bounding volumes would go stale
  }

  /// Copies the shape's state at frame f (positions: the run's Float32Array) into the GPU buffers.
  update(positions, frameOffset) {
    const base = frameOffset + this.state.offset;
    if (this.positionAttribute) {
      this.positionAttribute.array.set(positions.subarray(base, base + this.state.dofs * 3));
      this.positionAttribute.needsUpdate = true;
      if (this.edges && this.edges.visible) {
        this.edges.geometry.dispose();
        this.edges.geometry = new THREE.WireframeGeometry(this.geometry);
      }
      return;
    }
    const m = new THREE.Matrix4();
    const p = new THREE.Vector3();
    const q = new THREE.Quaternion();
    const s = new THREE.Vector3();
    for (let e = 0; e < this.indices.length; e++) {
      const i = base + this.indices[e] * this.stride;
      p.set(positions[i], positions[i + 1], positions[i + 2]);
      if (this.stride === 7) q.set(positions[i + 3], positions[i + 4], positions[i + 5], positions[i + 6]);
      else q.identity();
      const r = this.shape.radius[e];
      if (this.shape.kind === 'cylinders') {
        q.multiply(this.align[e]);
        s.set(r, this.shape.height[e], r);
      } else {
        s.set(r, r, r);
      }
      this.object.setMatrixAt(e, m.compose(p, q, s));
    }
    this.object.instanceMatrix.needsUpdate = true;
  }

  setWireframe(on) {
    if (this.edges) {
      this.edges.visible = on;
      this.edges.geometry.dispose();
      this.edges.geometry = new THREE.WireframeGeometry(this.geometry);
    }
  }

  dispose() {
    this.object.geometry.dispose();
    if (this.edges) this.edges.geometry.dispose();
  }
}

// ---------------------------------------------------------------------------------------------
// Contacts: segments point1 → point2 and points at both ends, coloured by |f·n|; normals optional.

class ContactView {
  constructor(capacity, maxForce, normalLength) {
    this.capacity = Math.max(capacity, 1);
    this.maxForce = maxForce > 0 ? maxForce : 1;
    this.normalLength = normalLength;
    const make = (count) => {
      const geometry = new THREE.BufferGeometry();
      const position = new THREE.BufferAttribute(new Float32Array(count * 3), 3).setUsage(THREE.DynamicDrawUsage);
      const color = new THREE.BufferAttribute(new Float32Array(count * 3), 3).setUsage(THREE.DynamicDrawUsage);
      geometry.setAttribute('position', position);
      geometry.setAttribute('color', color);
      geometry.setDrawRange(0, 0);
      return geometry;
    };
    this.segments = new THREE.LineSegments(make(2 * this.capacity),
                                           new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false }));
    this.ends = new THREE.Points(this.segments.geometry,
                                 new THREE.PointsMaterial({ vertexColors: true, size: 8, sizeAttenuation: false,
                                                            depthTest: false, map: disc(true), alphaTest: 0.5 }));
    this.normals = new THREE.LineSegments(make(2 * this.capacity),
                                          new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false }));
    this.normals.visible = false;
    this.group = new THREE.Group();
    this.group.add(this.segments, this.ends, this.normals);
    this.group.renderOrder = 10;
    for (const o of [this.segments, this.ends, this.normals]) { o.frustumCulled = false; o.renderOrder = 10; }
  }

  update(contacts, begin, end) {
    const count = Math.min((end - begin) / 10, this.capacity);
    const pos = this.segments.geometry.attributes.position.array;
    const col = this.segments.geometry.attributes.color.array;
    const npos = this.normals.geometry.attributes.position.array;
    for (let c = 0; c < count; c++) {
      const i = begin + 10 * c;
      for (let k = 0; k < 6; k++) pos[6 * c + k] = contacts[i + k];
      const entry = 3 * Math.round(255 * Math.min(Math.abs(contacts[i + 9]) / this.maxForce, 1));
      for (let k = 0; k < 6; k++) col[6 * c + k] = FORCE_COLOR_LINEAR[entry + (k % 3)];
      for (let k = 0; k < 3; k++) {
        npos[6 * c + k] = contacts[i + k];
        npos[6 * c + 3 + k] = contacts[i + k] + this.normalLength * contacts[i + 6 + k];
      }
    }
    this.segments.geometry.setDrawRange(0, 2 * count);
    this.normals.geometry.setDrawRange(0, 2 * count);
    this.segments.geometry.attributes.position.needsUpdate = true;
    this.segments.geometry.attributes.color.needsUpdate = true;
    this.normals.geometry.attributes.position.needsUpdate = true;
  }
}

// ---------------------------------------------------------------------------------------------
// Plots under the view: series over time, the current frame marked; a click seeks.

class Plot {
  constructor(canvas, title, unit, times, series) {
    this.canvas = canvas;
    this.title = title;
    this.unit = unit;
    this.times = times;
    this.series = series;  // [{label, color, values}]
    this.background = null;
  }

  layout() {
    const ratio = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.canvas.clientWidth * ratio));
    const h = Math.max(1, Math.round(this.canvas.clientHeight * ratio));
    this.canvas.width = w;
    this.canvas.height = h;
    this.ratio = ratio;
    let lo = Infinity, hi = -Infinity;
    for (const s of this.series) for (const v of s.values) if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (!Number.isFinite(lo)) { lo = 0; hi = 1; }
    lo = Math.min(lo, 0);
    if (hi <= lo) hi = lo + 1;
    this.lo = lo;
    this.hi = hi;
    this.t0 = this.times[0] ?? 0;
    this.t1 = this.times[this.times.length - 1] ?? 1;
    if (this.t1 <= this.t0) this.t1 = this.t0 + 1;
    // The static part (axes, series, legend) is drawn once per size into an offscreen canvas.
    const off = document.createElement('canvas');
    off.width = w;
    off.height = h;
    const g = off.getContext('2d');
    g.font = `${11 * ratio}px system-ui, sans-serif`;
    // the value axis' labels fit left of the plot area, however long
    const labels = Math.max(g.measureText(formatNumber(hi)).width, g.measureText(formatNumber(lo)).width);
    this.area = { left: Math.max(48 * ratio, labels + 8 * ratio), right: w - 8 * ratio, top: 20 * ratio,
                  bottom: h - 18 * ratio };
    const a = this.area;
    g.fillStyle = '#8b94a3';
    g.strokeStyle = '#3a414c';
    g.lineWidth = ratio;
    g.strokeRect(a.left, a.top, a.right - a.left, a.bottom - a.top);
    g.textAlign = 'right';
    g.fillText(formatNumber(hi), a.left - 4 * ratio, a.top + 8 * ratio);
    g.fillText(formatNumber(lo), a.left - 4 * ratio, a.bottom);
    g.textAlign = 'left';
    g.fillText(`${this.t0.toPrecision(3)} s`, a.left, h - 4 * ratio);
    g.textAlign = 'right';
    g.fillText(`${this.t1.toPrecision(3)} s`, a.right, h - 4 * ratio);
    g.textAlign = 'left';
    g.fillStyle = '#d8dde6';
    g.fillText(`${this.title} (${this.unit})`, a.left, 13 * ratio);
    let x = a.left + g.measureText(`${this.title} (${this.unit})`).width + 12 * ratio;
    for (const s of this.series) {
      g.strokeStyle = s.color;
      g.lineWidth = 1.5 * ratio;
      g.beginPath();
      let pen = false;  // null (not finite) values break the line
      for (let i = 0; i < s.values.length; i++) {
        if (!Number.isFinite(s.values[i])) { pen = false; continue; }
        const px = this.xOf(this.times[i]), py = this.yOf(s.values[i]);
        if (pen) g.lineTo(px, py); else g.moveTo(px, py);
        pen = true;
      }
      g.stroke();
      if (this.series.length > 1) {
        g.fillStyle = s.color;
        g.fillText(s.label, x, 13 * ratio);
        x += g.measureText(s.label).width + 10 * ratio;
      }
    }
    this.background = off;
  }

  xOf(t) { return this.area.left + (t - this.t0) / (this.t1 - this.t0) * (this.area.right - this.area.left); }
  yOf(v) { return this.area.bottom - (v - this.lo) / (this.hi - this.lo) * (this.area.bottom - this.area.top); }
  timeAt(clientX) {
    const r = this.canvas.getBoundingClientRect();
    const x = (clientX - r.left) * this.ratio;
    return this.t0 + (x - this.area.left) / (this.area.right - this.area.left) * (this.t1 - this.t0);
  }

  draw(frame) {
    if (!this.background) this.layout();
    const g = this.canvas.getContext('2d');
    g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    g.drawImage(this.background, 0, 0);
    const x = this.xOf(this.times[frame]);
    g.strokeStyle = '#ffffff';
    g.lineWidth = this.ratio;
    g.beginPath();
    g.moveTo(x, this.area.top);
    g.lineTo(x, this.area.bottom);
    g.stroke();
  }
}

// ---------------------------------------------------------------------------------------------
// The viewer

class Viewer {
  constructor(data) {
    this.data = data;
    const { run } = data;
    this.frames = run.frames.count;
    this.frame = 0;
    this.playing = false;
    this.speed = 1;

    const view = $('view');
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(BACKGROUND);
    this.renderer.domElement.className = 'three';
    view.prepend(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404850, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(0.5, 1, 0.8);
    this.camera.add(sun);
    this.scene.add(this.camera);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.requestRender());
    // Until the user moves the camera, a resize frames the run again for the new aspect ratio.
    this.cameraMoved = false;
    this.controls.addEventListener('start', () => { this.cameraMoved = true; });

    // Bodies: one colour per node holding collision models.
    this.palette = PALETTE;
    this.contactColor = (u) => forceColor(u, [0, 0, 0]);  // for the browser tests: the map, 0…1 → rgb 0…1
    this.nodeColor = new Map();
    for (const state of run.states)
      if (!this.nodeColor.has(state.node_path)) this.nodeColor.set(state.node_path, PALETTE[this.nodeColor.size % PALETTE.length]);
    this.shapes = [];
    this.layoutIndex = -1;
    this.wireframe = false;
    this.hiddenNodes = new Set();
    this.hiddenShapes = new Set();
    this.applyLayout(0);
    this.bounds = this.computeRunBounds();
    const diagonal = this.bounds.getSize(new THREE.Vector3()).length() || 1;
    let maxContacts = 0;
    for (const c of run.frames.contacts) maxContacts = Math.max(maxContacts, c);
    this.forceScale = forceScale(data.contacts, run.contact_floats, run.max_normal_force);
    this.contacts = new ContactView(maxContacts, this.forceScale, 0.05 * diagonal);
    this.scene.add(this.contacts.group);
    // crossings of the tunnelling guard: red markers where features passed through each other
    const crossingCount = (run.frames.crossings || []).reduce((a, b) => Math.max(a, b), 1);
    this.crossings = new THREE.Points(new THREE.BufferGeometry().setAttribute(
      'position', new THREE.BufferAttribute(new Float32Array(3 * crossingCount), 3).setUsage(THREE.DynamicDrawUsage)),
      new THREE.PointsMaterial({ color: 0xff2020, size: 12, sizeAttenuation: false, depthTest: false, map: disc(), alphaTest: 0.5 }));
    this.crossings.frustumCulled = false;
    this.crossings.renderOrder = 11;
    this.scene.add(this.crossings);

    this.buildTree();
    this.buildColorbar();
    this.buildTimeline();
    this.buildPlots();
    $('title').textContent = `penalty · ${run.title}`;
    document.title = `penalty viewer · ${run.title}`;
    new ResizeObserver(() => this.resize()).observe(view);
    this.resize();  // sizes the canvas, then frames the run (resetCamera)
    this.setFrame(frameFromUrl(this.frames));
    this.shareFrame = true;  // from now on the address names the frame shown (?frame=N), for sharing
    $('status').textContent = '';
    document.body.dataset.ready = 'true';
  }

  /// The shapes of layout l (a topological change between frames: other elements, other sizes).
  applyLayout(l) {
    if (l === this.layoutIndex) return;
    const { run, topology } = this.data;
    const layout = run.layouts[l];
    for (const v of this.shapes) { this.scene.remove(v.object); v.dispose(); }
    this.shapes = layout.shapes.map((shape) => {
      const state = layout.states[shape.state];
      const v = new ShapeView(shape, state, run, topology, this.nodeColor.get(state.node_path));
      if (this.wireframe) v.setWireframe(true);
      this.scene.add(v.object);
      return v;
    });
    this.layoutIndex = l;
    this.applyVisibility();
  }

  /// Box of every shape at every frame of the run: what Reset camera frames.
  computeRunBounds() { return this.computeBounds(0, this.data.run.frames.count - 1); }

  /// Box of every shape at frames first…last. Spheres reach their radius beyond the centre,
  /// cylinders √(r² + (h/2)²); other shapes are their DOFs.
  computeBounds(first, last) {
    const { run, positions } = this.data;
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    // Per layout, per shape: each drawn DOF once (a triangle mesh repeats its vertices), with its reach.
    const drawn = new Map();
    const drawnOf = (l) => {
      if (drawn.has(l)) return drawn.get(l);
      const layout = run.layouts[l];
      const list = layout.shapes.map((shape) => {
        const state = layout.states[shape.state];
        const indices = this.data.topology.subarray(shape.index_offset, shape.index_offset + shape.index_count);
        const perElement = shape.kind === 'spheres' || shape.kind === 'cylinders';
        const reachOf = new Map();
        indices.forEach((dof, e) => {
          const r = !perElement ? 0 : shape.kind === 'spheres' ? shape.radius[e] : Math.hypot(shape.radius[e], shape.height[e] / 2);
          reachOf.set(dof, Math.max(reachOf.get(dof) ?? 0, r));
        });
        const dofs = [...reachOf.keys()];
        return { state, stride: state.type === 'Rigid3d' ? 7 : 3, dofs, reach: dofs.map((d) => reachOf.get(d)) };
      });
      drawn.set(l, list);
      return list;
    };
    for (let f = first; f <= last; f++) {
      for (const { state, stride, dofs, reach } of drawnOf(run.frames.layout[f])) {
        const base = run.frames.position_offset[f] + state.offset;
        for (let k = 0; k < dofs.length; k++) {
          const i = base + dofs[k] * stride;
          for (let c = 0; c < 3; c++) {
            lo[c] = Math.min(lo[c], positions[i + c] - reach[k]);
            hi[c] = Math.max(hi[c], positions[i + c] + reach[k]);
          }
        }
      }
    }
    if (!(lo[0] <= hi[0])) return new THREE.Box3(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));
    return new THREE.Box3(new THREE.Vector3(...lo), new THREE.Vector3(...hi));
  }

  /// Frames the run: the camera looks at the centre c of the run's box along a fixed direction
  /// (unit b from c to the camera, with the camera's right and up axes X and Y), from the nearest
  /// distance d at which every corner p of the box (relative to c) projects inside both fields of
  /// view with a 5 % margin: at depth d − p·b, |p·X| ≤ (d − p·b)·tan(half-width angle) / 1.05, and
  /// the same with Y and the half-height angle. So d = max over corners of
  /// p·b + 1.05·max(|p·X| / tan h_w, |p·Y| / tan h_h).
  resetCamera(bounds = this.bounds) {
    const center = bounds.getCenter(new THREE.Vector3());
    const size = bounds.getSize(new THREE.Vector3());
    const radius = (size.length() / 2) || 1;
    const back = new THREE.Vector3(0.55, 0.4, 1).normalize();
    const right = new THREE.Vector3(0, 1, 0).cross(back).normalize();
    const up = new THREE.Vector3().crossVectors(back, right);
    const tanHeight = Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2));
    const tanWidth = tanHeight * this.camera.aspect;
    let distance = 0;
    for (let corner = 0; corner < 8; corner++) {
      const p = new THREE.Vector3((corner & 1 ? 0.5 : -0.5) * size.x, (corner & 2 ? 0.5 : -0.5) * size.y,
                                  (corner & 4 ? 0.5 : -0.5) * size.z);
      const spread = Math.max(Math.abs(p.dot(right)) / tanWidth, Math.abs(p.dot(up)) / tanHeight);
      distance = Math.max(distance, p.dot(back) + 1.05 * spread);
    }
    distance = Math.max(distance, 2 * radius * 1e-2, 1e-6);  // a box of no size: still a distance
    this.camera.position.copy(center).addScaledVector(back, distance);
    this.camera.up.set(0, 1, 0);
    this.camera.near = radius * 1e-3;  // the user may zoom in to a contact
    this.camera.far = (distance + radius) * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.camera.lookAt(center);
    this.controls.update();
    this.cameraMoved = bounds !== this.bounds;  // a resize re-frames the run, not a frame
    this.requestRender();
  }

  /// Frames the bodies as they are at the frame shown (a body that flies far away during the run
  /// makes the whole run's box large).
  fitFrame() { this.resetCamera(this.computeBounds(this.frame, this.frame)); }

  resize() {
    const view = $('view');
    const w = Math.max(1, view.clientWidth), h = Math.max(1, view.clientHeight);
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = `${w}px`;
    this.renderer.domElement.style.height = `${h}px`;
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    if (!this.cameraMoved) this.resetCamera();
    for (const p of this.plots) p.background = null;
    this.drawPlots();
    this.requestRender();
  }

  setFrame(f) {
    f = Math.min(Math.max(Math.round(f), 0), this.frames - 1);
    this.frame = f;
    const { run, positions, contacts, contactOffset } = this.data;
    this.applyLayout(run.frames.layout[f]);
    const frameOffset = run.frames.position_offset[f];
    for (const s of this.shapes) s.update(positions, frameOffset);
    this.contacts.update(contacts, contactOffset[f], contactOffset[f + 1]);
    const { crossings, crossingOffset } = this.data;
    const marks = this.crossings.geometry.attributes.position;
    marks.array.set(crossings.subarray(crossingOffset[f], crossingOffset[f + 1]));
    marks.needsUpdate = true;
    this.crossings.geometry.setDrawRange(0, (crossingOffset[f + 1] - crossingOffset[f]) / 3);
    $('frame-label').textContent = `${f} / ${this.frames - 1}`;
    $('time-label').textContent = run.frames.time[f].toPrecision(6);
    $('contacts-label').textContent = String(run.frames.contacts[f]);
    $('penetration-label').textContent = formatNumber(run.frames.max_penetration[f]);
    const slider = $('slider');
    if (Number(slider.value) !== f) slider.value = String(f);
    document.body.dataset.frame = String(f);
    if (this.shareFrame && !this.playing) writeFrameToUrl(f);
    this.drawPlots();
    this.requestRender();
  }

  // -- side panel: nodes → states → collision models, each with a visibility checkbox
  buildTree() {
    const { run } = this.data;
    const root = { name: run.title, path: '/', children: new Map(), states: [] };
    const nodeAt = (path) => {
      let node = root;
      let sofar = '';
      for (const part of path.split('/').filter(Boolean)) {
        sofar += `/${part}`;
        if (!node.children.has(part)) node.children.set(part, { name: part, path: sofar, children: new Map(), states: [] });
        node = node.children.get(part);
      }
      return node;
    };
    run.states.forEach((state, k) => nodeAt(state.node_path).states.push({ state, k }));
    const render = (node) => {
      const li = document.createElement('li');
      const color = this.nodeColor.get(node.path);
      li.innerHTML = `<label><input type="checkbox" checked data-node="${escapeHtml(node.path)}">` +
        (color !== undefined ? `<span class="swatch" style="background:#${color.toString(16).padStart(6, '0')}"></span>` : ' ') +
        `<b>${escapeHtml(node.name)}</b></label>`;
      const ul = document.createElement('ul');
      for (const { state, k } of node.states) {
        const sli = document.createElement('li');
        sli.innerHTML = `${escapeHtml(state.name)} <span class="kind">${state.type}, ${state.dofs} DOF${state.dofs === 1 ? '' : 's'}` +
          `${state.mapped ? ', mapped' : ''}</span>`;
        const sul = document.createElement('ul');
        this.shapes.forEach((v, s) => {
          if (v.shape.state !== k) return;
          const count = v.shape.kind === 'triangles' ? v.indices.length / 3 : v.shape.kind === 'lines' ? v.indices.length / 2
                                                                                                          : v.indices.length;
          const mli = document.createElement('li');
          mli.innerHTML = `<label><input type="checkbox" checked data-shape="${s}">${escapeHtml(v.shape.name)} ` +
            `<span class="kind">${escapeHtml(v.shape.type)}, ${count} ${v.shape.kind}</span></label>`;
          sul.append(mli);
        });
        sli.append(sul);
        ul.append(sli);
      }
      for (const child of node.children.values()) ul.append(render(child));
      li.append(ul);
      return li;
    };
    const top = document.createElement('ul');
    top.append(render(root));
    $('tree').append(top);
    $('tree').addEventListener('change', (event) => {
      const input = event.target;
      if (input.dataset.node !== undefined) {
        if (input.checked) this.hiddenNodes.delete(input.dataset.node); else this.hiddenNodes.add(input.dataset.node);
      } else if (input.dataset.shape !== undefined) {
        const s = Number(input.dataset.shape);
        if (input.checked) this.hiddenShapes.delete(s); else this.hiddenShapes.add(s);
      }
      this.applyVisibility();
    });
  }

  applyVisibility() {
    const hiddenBy = (path) => {
      if (this.hiddenNodes.has('/')) return true;
      let sofar = '';
      for (const part of path.split('/').filter(Boolean)) {
        sofar += `/${part}`;
        if (this.hiddenNodes.has(sofar)) return true;
      }
      return false;
    };
    this.shapes.forEach((v, s) => {
      v.object.visible = !this.hiddenShapes.has(s) && !hiddenBy(this.data.run.states[v.shape.state].node_path);
    });
    this.requestRender();
  }

  buildColorbar() {
    const canvas = $('colorbar-gradient');
    const g = canvas.getContext('2d');
    const rgb = [0, 0, 0];
    for (let x = 0; x < canvas.width; x++) {
      forceColor(x / (canvas.width - 1), rgb);
      g.fillStyle = `rgb(${rgb.map((c) => Math.round(255 * c)).join(',')})`;
      g.fillRect(x, 0, 1, 1);
    }
    const max = this.forceScale;
    const clipped = max < this.data.run.max_normal_force;
    $('colorbar-min').textContent = '0';
    $('colorbar-mid').textContent = formatNumber(max / 2);
    $('colorbar-max').textContent = `${clipped ? '≥ ' : ''}${formatNumber(max)} N`;
    $('colorbar').title = `colour scale: 99th percentile of |f·n| over the run (${formatNumber(max)} N); ` +
                          `largest ${formatNumber(this.data.run.max_normal_force)} N`;
    $('colorbar').hidden = false;
    $('show-contacts').addEventListener('change', (e) => { this.contacts.group.visible = e.target.checked; this.requestRender(); });
    $('show-normals').addEventListener('change', (e) => { this.contacts.normals.visible = e.target.checked; this.requestRender(); });
    $('show-wireframe').addEventListener('change', (e) => {
      this.wireframe = e.target.checked;
      for (const s of this.shapes) s.setWireframe(this.wireframe);
      this.requestRender();
    });
    $('reset-camera').addEventListener('click', () => this.resetCamera());
    $('fit-frame').addEventListener('click', () => this.fitFrame());
  }

  buildTimeline() {
    const slider = $('slider');
    slider.max = String(this.frames - 1);
    slider.addEventListener('input', () => { this.pause(); this.setFrame(Number(slider.value)); });
    $('play').addEventListener('click', () => (this.playing ? this.pause() : this.play()));
    $('step-back').addEventListener('click', () => { this.pause(); this.setFrame(this.frame - 1); });
    $('step-forward').addEventListener('click', () => { this.pause(); this.setFrame(this.frame + 1); });
    $('speed').addEventListener('change', (e) => { this.speed = Number(e.target.value); this.playStart = null; });
    window.addEventListener('keydown', (e) => {
      if (e.target instanceof HTMLInputElement && e.target.type !== 'range') return;
      if (e.key === ' ') { e.preventDefault(); this.playing ? this.pause() : this.play(); }
      else if (e.key === 'ArrowRight') { this.pause(); this.setFrame(this.frame + 1); }
      else if (e.key === 'ArrowLeft') { this.pause(); this.setFrame(this.frame - 1); }
    });
  }

  play() {
    if (this.frames < 2) return;
    if (this.frame >= this.frames - 1) this.setFrame(0);
    this.playing = true;
    this.playStart = null;
    $('play').textContent = '❚❚ pause';
    document.body.dataset.playing = 'true';
    this.requestRender();
  }

  pause() {
    this.playing = false;
    $('play').textContent = '▶ play';
    document.body.dataset.playing = 'false';
    writeFrameToUrl(this.frame);
  }

  /// Playback follows simulated time: after w seconds of wall time at speed s, the frame shown is
  /// the last one with time ≤ t_start + s·w (at least one frame further per animation frame).
  advance(now) {
    const times = this.data.run.frames.time;
    if (this.playStart === null) this.playStart = { wall: now, time: times[this.frame], frame: this.frame };
    const target = this.playStart.time + this.speed * (now - this.playStart.wall) / 1000;
    let f = this.frame;
    while (f + 1 < this.frames && times[f + 1] <= target) f++;
    if (f === this.frame && this.speed >= 1) f = this.frame + 1;
    if (f >= this.frames) { this.pause(); return; }
    if (f !== this.frame) this.setFrame(f);
    if (this.frame >= this.frames - 1) this.pause();
  }

  buildPlots() {
    const { run } = this.data;
    const fr = run.frames;
    this.plots = [
      new Plot($('plot-energy'), 'energy', 'J', fr.time, [
        { label: 'kinetic', color: '#4fa3ff', values: fr.kinetic_energy },
        { label: 'stored', color: '#f2a541', values: fr.contact_energy },
        { label: 'dissipated', color: '#e0607e', values: fr.dissipated_energy },
      ]),
      new Plot($('plot-contacts'), 'contacts', 'count', fr.time, [{ label: 'contacts', color: '#6cc551', values: fr.contacts }]),
      new Plot($('plot-penetration'), 'max penetration', 'm', fr.time,
               [{ label: 'max penetration', color: '#b38cf0', values: fr.max_penetration }]),
    ];
    for (const p of this.plots) {
      p.canvas.addEventListener('click', (e) => {
        const t = p.timeAt(e.clientX);
        let f = 0;
        while (f + 1 < this.frames && fr.time[f + 1] <= t) f++;
        this.pause();
        this.setFrame(f);
      });
    }
  }

  drawPlots() {
    if (this.plots) for (const p of this.plots) p.draw(this.frame);
  }

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame((now) => {
      this.renderPending = false;
      if (this.playing) this.advance(now);
      this.renderer.render(this.scene, this.camera);
      document.body.dataset.rendered = String((Number(document.body.dataset.rendered) || 0) + 1);
      if (this.playing) this.requestRender();
    });
  }
}

/// The top of the colour scale: the 99th percentile of |f·n| over every contact of the run (a few
/// impacts would otherwise squeeze everything else into one colour), at most `largest`.
function forceScale(contacts, stride, largest) {
  const n = Math.floor(contacts.length / stride);
  if (n === 0) return largest > 0 ? largest : 1;
  const step = Math.max(1, Math.floor(n / 200000));  // a sample of at most ~200k contacts
  const values = [];
  for (let c = 0; c < n; c += step) values.push(Math.abs(contacts[c * stride + 9]));
  values.sort((a, b) => a - b);
  const p99 = values[Math.min(values.length - 1, Math.floor(0.99 * values.length))];
  return p99 > 0 ? Math.min(p99, largest) : (largest > 0 ? largest : 1);
}

/// The frame the address asks for: `?frame=N` (clamped to the run's frames) or `?frame=last`;
/// frame 0 without the parameter or with another value.
function frameFromUrl(frames) {
  const value = new URLSearchParams(window.location.search).get('frame');
  if (value === 'last') return frames - 1;
  if (value === null || !/^\d+$/.test(value)) return 0;
  return Math.min(Number(value), frames - 1);
}

/// Puts `?frame=N` in the address without a new history entry: the address shares the frame.
function writeFrameToUrl(frame) {
  const url = new URL(window.location.href);
  if (url.searchParams.get('frame') === String(frame)) return;
  url.searchParams.set('frame', String(frame));
  window.history.replaceState(null, '', url);
}

function escapeHtml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]);
}

loadRun()
  .then((data) => { window.penaltyViewer = new Viewer(data); })
  .catch((error) => {
    $('status').textContent = `cannot load the run: ${error.message}`;
    document.body.dataset.error = error.message;
    console.error(error);
  });
