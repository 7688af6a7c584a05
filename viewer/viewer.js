// surfkit's HTML viewer: the mesh (plain, UV checkerboard, conformal distortion), the smooth
// surface (shaded with its exact normals, zebra stripes = reflection lines, deviation colours)
// and its patch boundaries; orbit / pan / zoom with the mouse.

function decode(b64, Type) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}

// blue - green - yellow - red, as the PNG pictures (render/raster.c)
const RAMP = [[0.23, 0.30, 0.75], [0.35, 0.70, 0.90], [0.55, 0.80, 0.40], [0.98, 0.80, 0.20], [0.80, 0.10, 0.10]];
function ramp(t) {
  t = Math.min(Math.max(t, 0), 1) * 4;
  const i = Math.min(Math.floor(t), 3), s = t - i;
  return RAMP[i].map((c, k) => (1 - s) * c + s * RAMP[i + 1][k]);
}

// sigma1 / sigma2 of the map from each 3D triangle to its uv triangle
function conformalDistortion(pos, idx, uv) {
  const out = new Float32Array(idx.length / 3);
  for (let t = 0; t < out.length; ++t) {
    const a = idx[3 * t], b = idx[3 * t + 1], c = idx[3 * t + 2];
    const e1 = [0, 1, 2].map((k) => pos[3 * b + k] - pos[3 * a + k]);
    const e2 = [0, 1, 2].map((k) => pos[3 * c + k] - pos[3 * a + k]);
    const l1 = Math.hypot(...e1);
    const x2 = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / l1;
    const y2 = Math.sqrt(Math.max(0, e2[0] ** 2 + e2[1] ** 2 + e2[2] ** 2 - x2 * x2));
    const u1 = uv[2 * b] - uv[2 * a], v1 = uv[2 * b + 1] - uv[2 * a + 1];
    const u2 = uv[2 * c] - uv[2 * a], v2 = uv[2 * c + 1] - uv[2 * a + 1];
    // Jacobian J = [u1 u2; v1 v2] * inverse([l1 x2; 0 y2])
    const det = l1 * y2;
    if (!(det > 0)) { out[t] = 1e9; continue; }
    const j00 = u1 / l1, j10 = v1 / l1;
    const j01 = (u2 - j00 * x2) / y2, j11 = (v2 - j10 * x2) / y2;
    const f = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11, d = j00 * j11 - j01 * j10;
    const r = Math.sqrt(Math.max(0, f * f - 4 * d * d));
    const s1 = Math.sqrt((f + r) / 2), s2 = Math.sqrt(Math.max(0, (f - r) / 2));
    out[t] = d <= 0 ? 1e9 : s1 / s2;
  }
  return out;
}

function checkerTexture(THREE) {
  const n = 256, cv = document.createElement('canvas');
  cv.width = cv.height = n;
  const g = cv.getContext('2d');
  for (let j = 0; j < 16; ++j)
    for (let i = 0; i < 16; ++i) {
      g.fillStyle = (i + j) % 2 ? '#263f8c' : '#f2f2e6';
      g.fillRect(i * n / 16, j * n / 16, n / 16, n / 16);
    }
  const tex = new THREE.CanvasTexture(cv);
  tex.wrapS = tex.wrapT = THREE.RepeatWrapping;
  tex.magFilter = THREE.NearestFilter;
  tex.colorSpace = THREE.SRGBColorSpace;
  return tex;
}

// reflection lines: stripes of the view vector reflected at the surface normal (view space),
// against a fixed striped environment; a kink in the stripes is a kink in the surface
const ZEBRA_VS = `
varying vec3 vN; varying vec3 vP;
void main() {
  vec4 p = modelViewMatrix * vec4(position, 1.0);
  vP = p.xyz; vN = normalize(normalMatrix * normal);
  gl_Position = projectionMatrix * p;
}`;
const ZEBRA_FS = `
uniform float stripes;
varying vec3 vN; varying vec3 vP;
void main() {
  vec3 n = normalize(vN);
  if (!gl_FrontFacing) n = -n;
  vec3 r = reflect(normalize(vP), n);
  float s = step(0.5, fract(stripes * (0.5 + 0.5 * r.y)));
  float light = 0.35 + 0.65 * abs(n.z);
  gl_FragColor = vec4(vec3(mix(0.08, 0.97, s)) * light, 1.0);
}`;

function buildGeometry(THREE, m) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(m.pos, 3));
  g.setIndex(new THREE.BufferAttribute(m.idx, 1));
  if (m.nrm) g.setAttribute('normal', new THREE.BufferAttribute(m.nrm, 3));
  else g.computeVertexNormals();
  return g;
}

// per-face colours need unshared vertices: a non-indexed copy with a colour per corner
function faceColoured(THREE, m, values, top) {
  const g = new THREE.BufferGeometry();
  const nt = m.idx.length / 3, pos = new Float32Array(9 * nt), col = new Float32Array(9 * nt);
  for (let t = 0; t < nt; ++t) {
    const c = values[t] >= 1e9 ? [1, 0, 1] : ramp(Math.log(values[t]) / Math.log(top));
    for (let k = 0; k < 3; ++k) {
      const v = m.idx[3 * t + k];
      for (let q = 0; q < 3; ++q) { pos[9 * t + 3 * k + q] = m.pos[3 * v + q]; col[9 * t + 3 * k + q] = c[q]; }
    }
  }
  g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  g.setAttribute('color', new THREE.BufferAttribute(col, 3));
  g.computeVertexNormals();
  return g;
}

function vertexColoured(THREE, geom, values, top) {
  const col = new Float32Array(3 * values.length);
  for (let v = 0; v < values.length; ++v) {
    const c = values[v] > top * (1 + 1e-9) ? [1, 0, 1] : ramp(values[v] / top);
    col.set(c, 3 * v);
  }
  const g = geom.clone();
  g.setAttribute('color', new THREE.BufferAttribute(col, 3));
  return g;
}

function legend(text, left, right, magenta) {
  const el = document.getElementById('legend');
  el.innerHTML = '';
  if (!text) return;
  const cv = document.createElement('canvas');
  cv.width = 200; cv.height = 12;
  const g = cv.getContext('2d');
  for (let i = 0; i < 200; ++i) {
    const c = ramp(i / 199);
    g.fillStyle = `rgb(${c.map((x) => Math.round(255 * x)).join(',')})`;
    g.fillRect(i, 0, 1, 12);
  }
  el.appendChild(cv);
  const d = document.createElement('div');
  d.textContent = `${text}: ${left} ... ${right}` + (magenta ? ` (magenta: ${magenta})` : '');
  el.appendChild(d);
}

export function start(THREE, data) {
  const canvas = document.getElementById('c');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f4);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x555566, 1.6));
  const camera = new THREE.PerspectiveCamera(35, 1, 1e-3, 1e3);
  const head = new THREE.DirectionalLight(0xffffff, 1.4);
  camera.add(head);
  scene.add(camera);
  document.getElementById('title').textContent = data.title || 'surfkit view';

  const mesh = { pos: decode(data.mesh.positions, Float32Array), idx: decode(data.mesh.triangles, Uint32Array) };
  const uv = data.mesh.uv ? decode(data.mesh.uv, Float32Array) : null;
  const meshGeom = buildGeometry(THREE, mesh);
  if (uv) meshGeom.setAttribute('uv', new THREE.BufferAttribute(uv, 2));
  const layers = {}; // name -> { object, legend }
  const std = (o) => new THREE.MeshStandardMaterial(Object.assign({ roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide }, o));
  layers['mesh'] = { object: new THREE.Mesh(meshGeom, std({ color: 0xb8bcc8, flatShading: true })) };
  layers['mesh edges'] = { object: new THREE.LineSegments(new THREE.WireframeGeometry(meshGeom), new THREE.LineBasicMaterial({ color: 0x333333, transparent: true, opacity: 0.35 })) };
  if (uv) {
    const tex = checkerTexture(THREE);
    let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    for (let i = 0; i < uv.length; i += 2) for (let k = 0; k < 2; ++k) { lo[k] = Math.min(lo[k], uv[i + k]); hi[k] = Math.max(hi[k], uv[i + k]); }
    const span = Math.max(hi[0] - lo[0], hi[1] - lo[1]) || 1;
    tex.repeat.set(1 / span, 1 / span);
    tex.offset.set(-lo[0] / span, -lo[1] / span);
    layers['uv checkerboard'] = { object: new THREE.Mesh(meshGeom, std({ map: tex })) };
    const dist = conformalDistortion(mesh.pos, mesh.idx, uv);
    layers['uv distortion'] = { object: new THREE.Mesh(faceColoured(THREE, mesh, dist, 4), std({ vertexColors: true })),
                                legend: ['sigma1 / sigma2 (log)', '1', '>= 4', 'flipped'] };
  }
  let surfGeom = null;
  if (data.surface) {
    const s = { pos: decode(data.surface.positions, Float32Array), idx: decode(data.surface.triangles, Uint32Array),
                nrm: decode(data.surface.normals, Float32Array) };
    surfGeom = buildGeometry(THREE, s);
    layers['surface'] = { object: new THREE.Mesh(surfGeom, std({ color: 0xc9cfe6, roughness: 0.35 })) };
    layers['zebra'] = { object: new THREE.Mesh(surfGeom, new THREE.ShaderMaterial({ uniforms: { stripes: { value: 14.0 } },
      vertexShader: ZEBRA_VS, fragmentShader: ZEBRA_FS, side: THREE.DoubleSide })) };
    if (data.surface.distance) {
      const d = decode(data.surface.distance, Float32Array);
      const top = data.surface.distance_scale;
      layers['deviation'] = { object: new THREE.Mesh(vertexColoured(THREE, surfGeom, d, top), std({ vertexColors: true })),
                              legend: ['distance to the mesh', '0', top.toPrecision(3), 'beyond'] };
    }
    if (data.surface.boundaries) {
      const b = new THREE.BufferGeometry();
      b.setAttribute('position', new THREE.BufferAttribute(decode(data.surface.boundaries, Float32Array), 3));
      layers['patch boundaries'] = { object: new THREE.LineSegments(b, new THREE.LineBasicMaterial({ color: 0x8a1010 })) };
    }
  }
  // at most one "skin" at a time (they cover each other); edges and boundaries go on top
  const skins = Object.keys(layers).filter((k) => k !== 'mesh edges' && k !== 'patch boundaries');
  const initial = data.surface ? 'zebra' : uv ? 'uv checkerboard' : 'mesh';
  const toggles = document.getElementById('toggles');
  const state = {};
  function apply() {
    for (const [k, l] of Object.entries(layers)) l.object.visible = !!state[k];
    const shown = skins.find((k) => state[k]);
    const lg = shown && layers[shown].legend;
    legend(lg && lg[0], lg && lg[1], lg && lg[2], lg && lg[3]);
    draw();
  }
  for (const k of Object.keys(layers)) {
    scene.add(layers[k].object);
    const isSkin = skins.includes(k);
    const lab = document.createElement('label');
    const inp = document.createElement('input');
    inp.type = isSkin ? 'radio' : 'checkbox';
    inp.name = isSkin ? 'skin' : k;
    inp.dataset.layer = k;
    state[k] = isSkin ? k === initial : (k === 'patch boundaries');
    inp.checked = state[k];
    inp.addEventListener('change', () => {
      if (isSkin) for (const s of skins) state[s] = s === k;
      else state[k] = inp.checked;
      apply();
    });
    lab.appendChild(inp);
    lab.appendChild(document.createTextNode(' ' + k));
    toggles.appendChild(lab);
  }
  document.getElementById('info').textContent = data.info || '';

  // orbit camera around the bounding sphere's centre
  meshGeom.computeBoundingSphere();
  const bs = (surfGeom || meshGeom).boundingSphere || meshGeom.boundingSphere;
  const centre = bs.center.clone(), radius = bs.radius || 1;
  const home = { theta: 0.0, phi: 0.0, dist: 4.2 * radius, target: centre.clone() };
  let view = { ...home, target: home.target.clone() };
  camera.near = radius * 1e-3; camera.far = radius * 100; camera.updateProjectionMatrix();
  function place() {
    const c = Math.cos(view.phi);
    camera.position.set(view.target.x + view.dist * c * Math.sin(view.theta),
                        view.target.y + view.dist * Math.sin(view.phi),
                        view.target.z + view.dist * c * Math.cos(view.theta));
    camera.lookAt(view.target);
  }
  function draw() {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== Math.floor(w * renderer.getPixelRatio()) || canvas.height !== Math.floor(h * renderer.getPixelRatio())) {
      renderer.setSize(w, h, false);
      camera.aspect = w / h; camera.updateProjectionMatrix();
    }
    place();
    renderer.render(scene, camera);
  }
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey }; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointerup', () => { drag = null; });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      const s = view.dist / canvas.clientHeight;
      const right = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 0);
      const up = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 1);
      view.target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
    } else {
      view.theta -= dx * 0.008;
      view.phi = Math.max(-1.55, Math.min(1.55, view.phi + dy * 0.008));
    }
    draw();
  });
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); view.dist *= Math.exp(e.deltaY * 0.001); draw(); }, { passive: false });
  window.addEventListener('keydown', (e) => { if (e.key === 'r') { view = { ...home, target: home.target.clone() }; draw(); } });
  window.addEventListener('resize', draw);
  apply();

  // what was drawn, for tests: pixels that differ from the background
  const gl = renderer.getContext();
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight, px = new Uint8Array(4 * w * h);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let covered = 0;
  for (let i = 0; i < px.length; i += 4)
    if (Math.abs(px[i] - 244) > 6 || Math.abs(px[i + 1] - 244) > 6 || Math.abs(px[i + 2] - 244) > 6) ++covered;
  window.skReport({ rendered: true, layers: Object.keys(layers), shown: skins.find((k) => state[k]),
                    covered: covered / (w * h), triangles: mesh.idx.length / 3 });
}
