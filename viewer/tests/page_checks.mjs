// Measurements of the viewer page for tests/browser_test.mjs, each run inside the page
// (page.evaluate) on window.penaltyViewer: what the camera frames, how contacts contrast with the
// bodies, where the plots are. They compute from the run's own data, independently of viewer.js.

/// A scene the viewer must frame whole (issue 49): a static obstacle far to the side of the moving
/// bodies (as CompositeCollisionPipeline's torus), a ball resting on a small floor (off the floor's
/// diagonal: a point exactly over the edge two triangles share makes no Triangle contact, as in
/// SOFA's MeshMinProximityIntersection), and a sphere
/// with nothing under it that falls freely to y ≈ −7 m in 120 steps (implicit Euler:
/// y_n = −g·dt²·n(n+1)/2 = −7.12 m at n = 120, dt = 0.01 s).
export const FRAMING_SCENE = `<?xml version="1.0"?>
<Node name="root" dt="0.01" gravity="0 -9.81 0">
    <DefaultAnimationLoop/>
    <CollisionPipeline/>
    <BruteForceBroadPhase/>
    <BVHNarrowPhase/>
    <MinProximityIntersection name="proximity" alarmDistance="0.2" contactDistance="0.05"/>
    <CollisionResponse name="response" response="PenalityContactForceField"/>
    <Node name="Obstacle">
        <MechanicalObject name="obstacle" position="3 0 -0.5  4 0 -0.5  4 1 -0.5  3 1 -0.5"/>
        <MeshTopology name="topology" triangles="0 1 2  0 2 3"/>
        <TriangleCollisionModel name="obstacle_triangles" simulated="0" moving="0"/>
    </Node>
    <Node name="Floor">
        <MechanicalObject name="floor" position="-1 0 -1  1 0 -1  1 0 1  -1 0 1"/>
        <MeshTopology name="topology" triangles="0 2 1  0 3 2"/>
        <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
    </Node>
    <Node name="Ball">
        <EulerImplicitSolver name="odesolver"/>
        <CGLinearSolver name="linear" iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject name="ball" position="0.3 0.12 -0.2"/>
        <UniformMass name="mass" totalMass="0.1"/>
        <SphereCollisionModel name="ball_sphere" radius="0.1" contactStiffness="100"/>
    </Node>
    <Node name="Falling">
        <EulerImplicitSolver name="odesolver"/>
        <CGLinearSolver name="linear" iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject name="falling" position="-1.5 0 0"/>
        <UniformMass name="mass" totalMass="0.1"/>
        <SphereCollisionModel name="falling_sphere" radius="0.2"/>
    </Node>
</Node>
`;

/// Every shape's bounding box at every frame (or at frames `only.first`…`only.last`; spheres:
/// centre ± radius; cylinders: centre ±
/// √(r² + (h/2)²); other shapes: their DOFs), its 8 corners projected through the camera: the
/// largest |x| or |y| in normalized device coordinates (≤ 1: inside the view) and where it is, the
/// largest |z| (≤ 1: between the near and far planes), the height in NDC of all the corners
/// together (2: the view's height), and the lowest y of all (the falling body's).
export function cameraFraming(only) {
  const v = window.penaltyViewer;
  const { run, positions, topology } = v.data;
  const first = only ? only.first : 0, last = only ? only.last : run.frames.count - 1;
  v.camera.updateMatrixWorld();
  const Vector = v.camera.position.constructor;
  let worst = 0, where = '', depth = 0, lowest = Infinity, top = -Infinity, bottom = Infinity;
  for (const shape of run.shapes) {
    const state = run.states[shape.state];
    const stride = state.type === 'Rigid3d' ? 7 : 3;
    const indices = topology.subarray(shape.index_offset, shape.index_offset + shape.index_count);
    for (let f = first; f <= last; f++) {
      const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
      indices.forEach((dof, e) => {
        const r = shape.kind === 'spheres' ? shape.radius[e]
          : shape.kind === 'cylinders' ? Math.hypot(shape.radius[e], shape.height[e] / 2) : 0;
        const i = f * run.frame_floats + state.offset + dof * stride;
        for (let c = 0; c < 3; c++) {
          lo[c] = Math.min(lo[c], positions[i + c] - r);
          hi[c] = Math.max(hi[c], positions[i + c] + r);
        }
      });
      lowest = Math.min(lowest, lo[1]);
      for (let corner = 0; corner < 8; corner++) {
        const p = new Vector(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]).project(v.camera);
        const m = Math.max(Math.abs(p.x), Math.abs(p.y));
        if (m > worst) { worst = m; where = `${shape.name} at frame ${f}`; }
        depth = Math.max(depth, Math.abs(p.z));
        top = Math.max(top, p.y);
        bottom = Math.min(bottom, p.y);
      }
    }
  }
  return { worst, where, depth, height: top - bottom, lowest, frames: run.frames.count, shapes: run.shapes.length };
}

/// CIE76 colour difference (ΔE*ab) of two sRGB colours given as [r, g, b] in 0…255.
export function deltaE(a, b) {
  const lab = (rgb) => {
    const [r, g, bl] = rgb.map((c) => { const x = c / 255; return x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4; });
    const f = (t) => (t > 0.008856 ? Math.cbrt(t) : 7.787 * t + 16 / 116);
    const X = f((0.4124 * r + 0.3576 * g + 0.1805 * bl) / 0.95047);
    const Y = f(0.2126 * r + 0.7152 * g + 0.0722 * bl);
    const Z = f((0.0193 * r + 0.1192 * g + 0.9505 * bl) / 1.08883);
    return [116 * Y - 16, 500 * (X - Y), 200 * (Y - Z)];
  };
  const [p, q] = [lab(a), lab(b)];
  return Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
}

/// The colour map against the body colours: the smallest ΔE between a colour of the contact map
/// (101 samples over 0…1) and a body colour of the palette lit at 0.35×, 0.6×, 1× or 1.4× its
/// brightness (in linear light), or the background.
export function colourMapSeparation(deltaESource) {
  const deltaE = new Function(`return ${deltaESource}`)();
  const v = window.penaltyViewer;
  const hex = (h) => [(h >> 16) & 255, (h >> 8) & 255, h & 255];
  const lit = (rgb, k) => rgb.map((c) => {
    const x = c / 255;
    const linear = Math.min(1, (x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4) * k);
    return 255 * (linear <= 0.0031308 ? 12.92 * linear : 1.055 * linear ** (1 / 2.4) - 0.055);
  });
  let worst = { deltaE: Infinity, what: '' };
  for (let s = 0; s <= 100; s++) {
    const contact = v.contactColor(s / 100).map((c) => 255 * c);
    const against = [...v.palette.map((p) => [p, hex(p)]), ['background', [0x1e, 0x22, 0x28]]];
    for (const [name, rgb] of against) {
      for (const k of name === 'background' ? [1] : [0.35, 0.6, 1, 1.4]) {
        const d = deltaE(contact, lit(rgb, k));
        if (d < worst.deltaE) worst = { deltaE: d, what: `map(${s / 100}) vs ${typeof name === 'number' ? `#${name.toString(16)}` : name} ×${k}` };
      }
    }
  }
  return worst;
}

/// The 3D view's pixels as [r, g, b, a, ...] (a plain array), kept in the page under `key`.
export function grabView(key) {
  const gl = document.querySelector('canvas.three');
  const c = document.createElement('canvas');
  c.width = gl.width;
  c.height = gl.height;
  const g = c.getContext('2d');
  g.drawImage(gl, 0, 0);
  window[key] = g.getImageData(0, 0, c.width, c.height).data;
  return c.width * c.height;
}

/// Contact pixels (those that change when the contacts are hidden: `shown` vs `hidden`, kept by
/// grabView) against what is under them: how many, and the share whose ΔE to the pixel beneath
/// is at least `threshold`, with the 10th percentile of ΔE.
export function contactContrast({ shown, hidden, threshold, deltaESource }) {
  const deltaE = new Function(`return ${deltaESource}`)();
  const a = window[shown], b = window[hidden];
  const differences = [];
  for (let i = 0; i < a.length; i += 4) {
    const change = Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]);
    if (change < 30) continue;
    const under = [b[i], b[i + 1], b[i + 2]];
    const background = Math.abs(under[0] - 0x1e) + Math.abs(under[1] - 0x22) + Math.abs(under[2] - 0x28) < 12;
    if (background) continue;  // contrast against bodies only
    differences.push(deltaE([a[i], a[i + 1], a[i + 2]], under));
  }
  differences.sort((x, y) => x - y);
  const strong = differences.filter((d) => d >= threshold).length;
  return { pixels: differences.length, share: differences.length ? strong / differences.length : 0,
           p10: differences.length ? differences[Math.floor(0.1 * differences.length)] : 0 };
}

/// Where the plots are: each canvas's rectangle, whether its backing store matches it (the axes
/// drawn at the size shown), and the document's height against the window's.
export function plotLayout() {
  const ratio = window.devicePixelRatio || 1;
  return {
    window: { width: window.innerWidth, height: window.innerHeight },
    scrollHeight: document.documentElement.scrollHeight,
    plots: [...document.querySelectorAll('#plots canvas')].map((c) => {
      const r = c.getBoundingClientRect();
      return { id: c.id, top: r.top, bottom: r.bottom, left: r.left, right: r.right, height: r.height,
               drawnHeight: c.height / ratio };
    }),
  };
}
