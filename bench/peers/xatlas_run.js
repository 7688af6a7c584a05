#!/usr/bin/env node
// xatlas peer for bench/atlas.sh. xatlas-web (npm, bench/package.json) is an emscripten build for
// browsers only, so this script serves bench/peers/xatlas_page.html, the package's js + wasm and
// the mesh from a local HTTP server on 127.0.0.1 and opens the page in headless Chromium, which
// runs xatlas's generateAtlas and posts the atlas back. Writes OUT.obj with the original vertex
// positions (the input's own text), one vt per xatlas vertex, faces v/vt; prints
//   XATLAS_SECONDS s   (generateAtlas + getMeshData inside the page, not load / transfer)
//   XATLAS_HEAP_MB m   (the wasm heap at the end: xatlas's own memory)
//   XATLAS_PIECES n    (1 unless the mesh has more than 65,536 vertices, see below)
// xatlas-web 0.1.0's generateAtlas takes no options: xatlas's defaults (chart growing, LSCM /
// piecewise parametrization, padding 0, one atlas sized from the texel density).
// With --padding P [--resolution R] it runs xatlasjs instead (npm `xatlasjs` 0.2.0, the same
// xatlas with its options bound, built for node: no browser): xatlas's defaults but for
// PackOptions padding = P texels and resolution = R (default 1024), the gutter of surfkit's
// --padding P --resolution R; the atlas xatlas makes may be smaller than R (it trims the unused
// part), so the gutter in the unit square is P / max(W, H) (bench/atlas_metrics.py measures it).
// Usage: node bench/peers/xatlas_run.js IN.obj OUT.obj [--padding P [--resolution R]]
"use strict";
const fs = require("fs");
const http = require("http");
const path = require("path");
const { spawn } = require("child_process");

const [src, dst] = process.argv.slice(2);
const optArg = (name) => {
  const i = process.argv.indexOf(name);
  return i > 0 && i + 1 < process.argv.length ? parseFloat(process.argv[i + 1]) : NaN;
};
const padding = optArg("--padding"), resolution = optArg("--resolution");
if (!src || !dst || (process.argv.length > 4 && !(padding >= 0))) {
  console.error("usage: xatlas_run.js IN.obj OUT.obj [--padding P [--resolution R]]");
  process.exit(2);
}
const dist = path.join(__dirname, "..", "node_modules", "xatlas-web", "dist");
if (!fs.existsSync(path.join(dist, "xatlas-web.wasm"))) {
  console.error("xatlas_run: xatlas-web missing (cd bench && npm ci)");
  process.exit(1);
}
const chromium = process.env.CHROMIUM || "/usr/bin/chromium";
const timeoutS = parseFloat(process.env.XATLAS_TIMEOUT || "1800");

// The input OBJ: keep the "v" lines as text (positions bit for bit), triangles (fanned).
const vlines = [];
const tris = [];
for (const line of fs.readFileSync(src, "utf8").split("\n")) {
  if (line.startsWith("v ")) {
    vlines.push(line.trim());
  } else if (line.startsWith("f ")) {
    const c = line.trim().split(/\s+/).slice(1).map((t) => {
      const i = parseInt(t.split("/")[0], 10);
      return i < 0 ? vlines.length + i : i - 1;
    });
    for (let k = 1; k + 1 < c.length; ++k) tris.push(c[0], c[k], c[k + 1]);
  }
}
const nv = vlines.length, nf = tris.length / 3;
const P = new Float32Array(3 * nv);
vlines.forEach((l, i) => {
  const p = l.split(/\s+/);
  for (let k = 0; k < 3; ++k) P[3 * i + k] = parseFloat(p[k + 1]);
});

// xatlas-web 0.1.0 takes 16-bit indices: a mesh of more than 65,536 vertices goes in as pieces of
// at most 65,536 vertices each, grown face by face across edges (breadth first), all added to one
// atlas. Charts cannot cross a piece border, so the pieces add seams (reported by XATLAS_PIECES).
const MAXV = Math.min(65536, parseInt(process.env.XATLAS_MAX_VERTICES || "65536", 10)); // env: for tests
function pieces() {
  if (nv <= MAXV) return [Array.from({ length: nf }, (_, f) => f)];
  const vf = new Map(); // vertex -> faces
  for (let f = 0; f < nf; ++f)
    for (let k = 0; k < 3; ++k) {
      const v = tris[3 * f + k];
      if (!vf.has(v)) vf.set(v, []);
      vf.get(v).push(f);
    }
  const taken = new Uint8Array(nf);
  const out = [];
  let seed = 0;
  while (true) {
    while (seed < nf && taken[seed]) ++seed;
    if (seed === nf) break;
    const faces = [], verts = new Set(), queue = [seed];
    taken[seed] = 1;
    while (queue.length) {
      const f = queue.shift();
      const add = [0, 1, 2].map((k) => tris[3 * f + k]).filter((v) => !verts.has(v));
      if (verts.size + add.length > MAXV) { taken[f] = 0; continue; }
      add.forEach((v) => verts.add(v));
      faces.push(f);
      for (let k = 0; k < 3; ++k)
        for (const g of vf.get(tris[3 * f + k]))
          if (!taken[g]) { taken[g] = 1; queue.push(g); }
    }
    out.push(faces);
  }
  return out;
}
const parts = pieces().map((faces) => {
  const local = new Map(), verts = [];
  const idx = new Uint32Array(3 * faces.length);
  faces.forEach((f, i) => {
    for (let k = 0; k < 3; ++k) {
      const v = tris[3 * f + k];
      if (!local.has(v)) { local.set(v, verts.length); verts.push(v); }
      idx[3 * i + k] = local.get(v);
    }
  });
  return { faces: faces, verts: verts, idx: idx };
});
let size = 4;
for (const p of parts) size += 8 + 12 * p.verts.length + 12 * p.faces.length;
const mesh = Buffer.alloc(size);
mesh.writeUInt32LE(parts.length, 0);
let at = 4;
for (const p of parts) {
  mesh.writeUInt32LE(p.verts.length, at);
  mesh.writeUInt32LE(p.faces.length, at + 4);
  at += 8;
  for (const v of p.verts) {
    for (let k = 0; k < 3; ++k) mesh.writeFloatLE(P[3 * v + k], at + 4 * k);
    at += 12;
  }
  for (const i of p.idx) { mesh.writeUInt32LE(i, at); at += 4; }
}

// xatlasjs in node: the same atlas as the page makes, options set; the result goes through
// writeObj in the page's layout (per piece: counts, xref, uv, indices).
function runNode() {
  const create = require(path.join(__dirname, "..", "node_modules", "xatlasjs", "dist", "node", "xatlas.js"));
  create({ print: () => {}, printErr: () => {} }).then((M) => {
    const t0 = performance.now();
    M.createAtlas();
    const infos = parts.map((p) => {
      const info = M.createMesh(p.verts.length, 3 * p.faces.length, false, false);
      for (let i = 0; i < p.verts.length; ++i)
        for (let k = 0; k < 3; ++k) M.HEAPF32[info.positionOffset / 4 + 3 * i + k] = P[3 * p.verts[i] + k];
      M.HEAPU16.set(p.idx, info.indexOffset / 2);
      M.addMesh();
      return info;
    });
    const pack = Object.assign(M.defaultPackOptions(), { padding: padding,
      resolution: resolution > 0 ? resolution : 1024 });
    M.generateAtlas(M.defaultChartOptions(), pack);
    const outs = infos.map((info) => M.getMeshData(info.meshId));
    const t1 = performance.now();
    const atlas = M.getAtlas();
    const chunks = [];
    for (const o of outs) {
      const n = o.newVertexCount, ni = o.newIndexCount, head = Buffer.alloc(8);
      head.writeUInt32LE(n, 0);
      head.writeUInt32LE(ni, 4);
      chunks.push(head, Buffer.from(M.HEAPU32.slice(o.originalIndexOffset / 4, o.originalIndexOffset / 4 + n).buffer),
        Buffer.from(M.HEAPF32.slice(o.uvOffset / 4, o.uvOffset / 4 + 2 * n).buffer),
        Buffer.from(M.HEAPU32.slice(o.indexOffset / 4, o.indexOffset / 4 + ni).buffer));
    }
    if (atlas.atlasCount !== 1) throw new Error("xatlas made " + atlas.atlasCount + " atlases");
    writeObj(Buffer.concat(chunks), new URLSearchParams({ width: atlas.width, height: atlas.height,
      seconds: (t1 - t0) / 1000, heap_mb: M.HEAPU8.length / 1048576 }));
  }).catch((e) => { console.error("xatlas_run: " + e); process.exit(1); });
}

const files = {
  "/index.html": [path.join(__dirname, "xatlas_page.html"), "text/html"],
  "/xatlas-web.js": [path.join(dist, "xatlas-web.js"), "text/javascript"],
  "/xatlas-web.wasm": [path.join(dist, "xatlas-web.wasm"), "application/wasm"],
};
let browser = null;
let done = false;
function stopBrowser() { // chromium and its helpers run in their own process group
  if (!browser || browser.exitCode !== null || browser.signalCode !== null) return;
  try { process.kill(-browser.pid, "SIGTERM"); } catch (e) { /* already gone */ }
  setTimeout(() => { try { process.kill(-browser.pid, "SIGKILL"); } catch (e) { /* gone */ } }, 3000).unref();
}
function finish(code, msg) {
  if (done) return;
  done = true;
  if (msg) console.error("xatlas_run: " + msg);
  process.exitCode = code;
  server.close();
  if (!browser || browser.exitCode !== null) process.exit(code);
  browser.on("exit", () => setTimeout(() => process.exit(code), 100));
  stopBrowser();
}
function writeObj(body, query) {
  const u32 = (off, n) => new Uint32Array(body.buffer.slice(body.byteOffset + off, body.byteOffset + off + 4 * n));
  const out = ["# xatlas-web atlas of " + path.basename(src)];
  for (const l of vlines) out.push(l);
  const fl = [];
  // undo getMeshData's u / width, v / height (see atlasSize in the page): one scale for both axes
  const W = parseFloat(query.get("width")), H = parseFloat(query.get("height"));
  if (!(W > 0 && H > 0)) throw new Error("atlas width / height not found: the uvs would be squeezed");
  const su = W / Math.max(W, H), sv = H / Math.max(W, H);
  let at = 0, base = 0;
  for (const p of parts) {
    const nn = body.readUInt32LE(at), ni = body.readUInt32LE(at + 4);
    const xref = u32(at + 8, nn);
    const uv = new Float32Array(body.buffer.slice(body.byteOffset + at + 8 + 4 * nn, body.byteOffset + at + 8 + 12 * nn));
    const idx = u32(at + 8 + 12 * nn, ni);
    if (ni !== 3 * p.faces.length) throw new Error("xatlas returned " + ni + " indices for " + p.faces.length + " triangles");
    for (let i = 0; i < nn; ++i) out.push("vt " + su * uv[2 * i] + " " + sv * uv[2 * i + 1]);
    for (let f = 0; f < ni / 3; ++f) {
      const c = [0, 1, 2].map((k) => idx[3 * f + k]);
      if (c.some((j) => j >= nn || xref[j] >= p.verts.length)) throw new Error("xatlas index out of range");
      fl.push("f " + c.map((j) => (p.verts[xref[j]] + 1) + "/" + (base + j + 1)).join(" "));
    }
    base += nn;
    at += 8 + 12 * nn + 4 * ni;
  }
  fs.writeFileSync(dst, out.concat(fl).join("\n") + "\n");
  console.log("XATLAS_SECONDS " + parseFloat(query.get("seconds")).toFixed(6));
  console.log("XATLAS_HEAP_MB " + parseFloat(query.get("heap_mb")).toFixed(1));
  console.log("XATLAS_PIECES " + parts.length);
  console.log("XATLAS_ATLAS " + W + "x" + H);
}
const server = padding >= 0 ? null : http.createServer((req, res) => {
  const url = new URL(req.url, "http://127.0.0.1");
  if (req.method === "GET") {
    if (url.pathname === "/mesh.bin") {
      res.writeHead(200, { "Content-Type": "application/octet-stream" });
      res.end(mesh);
      return;
    }
    const f = files[url.pathname];
    if (!f) {
      res.writeHead(404);
      res.end();
      return;
    }
    res.writeHead(200, { "Content-Type": f[1] });
    res.end(fs.readFileSync(f[0]));
    return;
  }
  const chunks = [];
  req.on("data", (c) => chunks.push(c));
  req.on("end", () => {
    res.writeHead(200);
    res.end();
    const body = Buffer.concat(chunks);
    if (url.pathname === "/result.bin") {
      try {
        writeObj(body, url.searchParams);
      } catch (e) {
        finish(1, String(e));
      }
    } else if (url.pathname === "/log") {
      if (process.env.XATLAS_LOG) fs.writeFileSync(process.env.XATLAS_LOG, body.toString("utf8"));
      finish(0);
    } else if (url.pathname === "/error") {
      finish(1, "page failed: " + body.toString("utf8"));
    }
  });
});
if (padding >= 0) runNode();
else server.listen(0, "127.0.0.1", () => {
  const port = server.address().port;
  const profile = fs.mkdtempSync(path.join(require("os").tmpdir(), "sk-xatlas-"));
  browser = spawn(chromium, ["--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run",
    "--disable-extensions", "--disable-background-networking", "--user-data-dir=" + profile,
    "http://127.0.0.1:" + port + "/index.html"],
  { stdio: ["ignore", "ignore", "pipe"], detached: true });
  let err = "";
  browser.stderr.on("data", (d) => { err = (err + d).slice(-4000); });
  browser.on("exit", (code) => {
    try { process.kill(-browser.pid, "SIGKILL"); } catch (e) { /* the group is gone */ }
    fs.rmSync(profile, { recursive: true, force: true });
    if (!done) finish(1, "chromium exited (" + code + ") before the atlas came back: " + err.trim().split("\n").pop());
  });
  setTimeout(() => finish(1, "timed out after " + timeoutS + " s"), timeoutS * 1000).unref();
});
