// Renders the first material of a .gltf file with three.js (npm package three) in headless
// Chromium, on the sphere `brdffit render` draws, and writes the linear pixels as JSON:
//   {"width": N, "height": N, "rgb": [r, g, b, ...]}   rows top first, f·cosθi per channel.
//
//   node render_gltf_three.js CHROMIUM MATERIAL.gltf SIZE LIGHT_X,LIGHT_Y,LIGHT_Z OUT.json
//
// The scene is brdffit's (src/render.cc, sphere.h): an orthographic camera looking along -z at
// a unit sphere whose outline has radius SIZE/2 - 1 pixels, centred in the picture, and one
// directional light of intensity 1 from LIGHT (camera frame: x right, y up, z toward the
// camera). three.js lights a surface with BRDF · cosθi · intensity (no π factor: physically
// based light units are its only mode since r165), so intensity 1 gives brdffit's f·cosθi. No
// environment, no ambient light, no tone mapping; a float render target keeps the output linear
// (three.js applies outputColorSpace and toneMapping only when drawing to the screen).
//
// The material comes from three's own GLTFLoader (MeshStandardMaterial for core glTF,
// MeshPhysicalMaterial with KHR_materials_ior / _specular / _clearcoat / _sheen / _anisotropy); the sphere is three's
// SphereGeometry with its tangents computed,
// tessellated finely so that interpolated vertex normals stay within a fraction of a pixel's
// normal change of the analytic sphere's.
//
// A local HTTP server serves the page, three's modules and the glTF file, and receives the
// pixels. Exit status: 0 with the file written, 1 when rendering failed, 2 on bad arguments.
// NODE_PATH must hold the package (scripts/install-deps.sh installs it under .deps/npm/node_modules).
const fs = require('fs');
const http = require('http');
const path = require('path');
const {spawn} = require('child_process');

const [chromium, gltfFile, sizeText, lightText, outFile] = process.argv.slice(2);
const size = Number(sizeText), light = (lightText || '').split(',').map(Number);
if (!outFile || !(size >= 8 && size <= 2048) || light.length !== 3 || light.some((x) => !Number.isFinite(x))) {
  console.error('usage: render_gltf_three.js CHROMIUM MATERIAL.gltf SIZE X,Y,Z OUT.json');
  process.exit(2);
}
const threeDir = path.dirname(path.dirname(require.resolve('three')));  // .../node_modules/three

const page = `<!doctype html><html><body>
<script>
// Errors outside render() (a module that fails to load) reach the harness too.
addEventListener('error', (e) => fetch('/result', {method: 'POST', body: JSON.stringify({error: String(e.message)})}));
</script>
<script type="importmap">{"imports": {"three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from 'three';
import {GLTFLoader} from 'three/addons/loaders/GLTFLoader.js';
const size = ${size}, light = ${JSON.stringify(light)};
async function render() {
  const gltf = await new GLTFLoader().loadAsync('/material.gltf');
  const material = await gltf.parser.getDependency('material', 0);
  const scene = new THREE.Scene();
  // Tangents along u, the longitude: brdffit's shading frame on its sphere (sphere.h's LocalFrame), which
  // KHR_materials_anisotropy's rotation is relative to. three.js uses them only for anisotropy.
  const sphere = new THREE.SphereGeometry(1, 720, 360);
  sphere.computeTangents();
  scene.add(new THREE.Mesh(sphere, material));
  const sun = new THREE.DirectionalLight(0xffffff, 1.0);
  sun.position.set(light[0], light[1], light[2]);  // toward the light; its target stays at the origin
  scene.add(sun);
  // Pixel centres at (i + 1/2)·2w/size - w must sit at (i - (size-1)/2) / (size/2 - 1) sphere radii.
  const w = size / (size - 2);
  const camera = new THREE.OrthographicCamera(-w, w, w, -w, 0.5, 10);
  camera.position.set(0, 0, 5);
  const renderer = new THREE.WebGLRenderer({antialias: false});
  renderer.toneMapping = THREE.NoToneMapping;
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
  const target = new THREE.WebGLRenderTarget(size, size, {type: THREE.FloatType});
  renderer.setRenderTarget(target);
  renderer.render(scene, camera);
  const rgba = new Float32Array(size * size * 4);
  renderer.readRenderTargetPixels(target, 0, 0, size, size, rgba);
  const rgb = [];
  for (let row = size - 1; row >= 0; --row)  // WebGL's rows start at the bottom
    for (let x = 0; x < size; ++x) rgb.push(...rgba.subarray(4 * (row * size + x), 4 * (row * size + x) + 3));
  return {width: size, height: size, material: material.type, rgb};
}
render().then((result) => fetch('/result', {method: 'POST', body: JSON.stringify(result)}),
              (error) => fetch('/result', {method: 'POST', body: JSON.stringify({error: String(error && error.stack || error)})}));
</script></body></html>`;

const types = {'.js': 'text/javascript', '.html': 'text/html', '.gltf': 'model/gltf+json'};
let browser = null;
const finish = (status, message) => {
  if (message) console.error(message);
  if (browser) browser.kill('SIGKILL');
  server.close();
  process.exitCode = status;
};
const server = http.createServer((request, response) => {
  const url = decodeURIComponent(request.url.split('?')[0]);
  if (request.method === 'POST' && url === '/result') {
    const chunks = [];
    request.on('data', (chunk) => chunks.push(chunk));
    request.on('end', () => {
      response.end();
      const text = Buffer.concat(chunks).toString();
      const result = JSON.parse(text);
      if (result.error) return finish(1, 'three.js: ' + result.error);
      fs.writeFileSync(outFile, text);
      finish(0);
    });
    return;
  }
  let file = null;  // the page itself
  if (url === '/material.gltf') file = gltfFile;
  else if (url.startsWith('/three/') && !url.includes('..')) file = path.join(threeDir, url.slice('/three/'.length));
  else if (url !== '/') return response.writeHead(404).end();
  response.setHeader('Content-Type', file ? types[path.extname(file)] || 'application/octet-stream' : 'text/html');
  response.end(file ? fs.readFileSync(file) : page);
});
server.listen(0, '127.0.0.1', () => {
  // Beside the output, left there: Chromium's helper processes may still write to it after it exits.
  const profile = fs.mkdtempSync(path.join(path.dirname(path.resolve(outFile)), 'chromium-profile-'));
  browser = spawn(chromium, ['--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
                             '--no-first-run', '--disable-background-networking', '--disable-component-update',
                             '--disable-sync', '--enable-logging=stderr',  // the page's console, shown on failure
                             '--user-data-dir=' + profile, '--remote-debugging-port=0',
                             `http://127.0.0.1:${server.address().port}/`],
                  {stdio: ['ignore', 'ignore', 'pipe']});
  let log = '';
  browser.stderr.on('data', (chunk) => (log += chunk));
  browser.on('exit', (code) => {
    if (process.exitCode === undefined) finish(1, `chromium exited (${code}) before the page answered:\n${log}`);
  });
  setTimeout(() => finish(1, 'no answer from the page in 60 s:\n' + log), 60000).unref();
});
