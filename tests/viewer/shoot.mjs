// Shows a glTF in a web viewer in headless Chromium and screenshots it, then draws the
// same view with every surface showing its texture coordinates, so that each pixel of
// the screenshot can be traced to the texel it shows.
//
//   node tests/viewer/shoot.mjs VIEW.json OUT
//
// VIEW.json: { viewer: "three" | "model-viewer", asset: path of the .gltf, size: pixels,
// orbit: { theta, phi, radius } (radians, radians, metres; as model-viewer's camera-orbit),
// target: [x, y, z] (metres), fov: vertical degrees, toneMapping, exposure, uvAttribute }.
// Writes OUT_look.png (the screenshot), OUT_uv.f32 (float32 RGBA, rows bottom to top: u,
// v, 0, covered) and OUT.json (what the page reported, and the camera of the uv pass).
// Chromium is $CHROMIUM or /usr/bin/chromium.
import fs from "node:fs";
import http from "node:http";
import path from "node:path";
import { createRequire } from "node:module";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const nodeModules = path.join(here, "..", "..", ".node", "node_modules");
const { chromium } = createRequire(path.join(nodeModules, "noop.js"))("playwright-core");

const TYPES = { ".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript",
  ".json": "application/json", ".gltf": "model/gltf+json", ".bin": "application/octet-stream",
  ".png": "image/png", ".glb": "model/gltf-binary", ".hdr": "application/octet-stream" };

// Serves the pages, the packages and the asset's folder on localhost, nothing else.
function serve(assetFolder) {
  const roots = { "/viewer/": here, "/node_modules/": nodeModules, "/asset/": assetFolder };
  const server = http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, "http://localhost").pathname);
    const prefix = Object.keys(roots).find((p) => url.startsWith(p));
    const file = prefix && path.resolve(roots[prefix], "." + url.slice(prefix.length - 1));
    if (!file || !file.startsWith(roots[prefix]) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
      response.writeHead(404).end();
      return;
    }
    response.writeHead(200, { "content-type": TYPES[path.extname(file)] ?? "application/octet-stream" });
    fs.createReadStream(file).pipe(response);
  });
  return new Promise((resolve) => server.listen(0, "127.0.0.1", () => resolve(server)));
}

async function open(browser, origin, page, view) {
  const tab = await browser.newPage({ viewport: { width: view.size, height: view.size } });
  const messages = [];
  tab.on("console", (message) => messages.push(message.text()));
  tab.on("pageerror", (error) => messages.push(String(error)));
  await tab.addInitScript((v) => { window.VIEW = v; }, view);
  await tab.goto(`${origin}/viewer/${page}`);
  await tab.waitForFunction(() => window.RESULT !== undefined, null, { timeout: 180000 });
  const result = await tab.evaluate(() => window.RESULT);
  if (result.error) throw new Error(`${page}: ${result.error}\n${messages.join("\n")}`);
  return { tab, result, messages };
}

async function main() {
  const [viewFile, out] = process.argv.slice(2);
  const view = JSON.parse(fs.readFileSync(viewFile, "utf8"));
  const server = await serve(path.dirname(path.resolve(view.asset)));
  const origin = `http://127.0.0.1:${server.address().port}`;
  const asset = `${origin}/asset/${encodeURIComponent(path.basename(view.asset))}`;
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    // WebGL in software (SwiftShader); no calls to the network.
    args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-quic"],
  });
  try {
    const page = view.viewer === "model-viewer" ? "model-viewer.html" : "three.html";
    const look = await open(browser, origin, page, { ...view, asset, pass: "look" });
    const selector = view.viewer === "model-viewer" ? "model-viewer" : "canvas";
    await look.tab.locator(selector).screenshot({ path: `${out}_look.png` });
    // The uv pass repeats the camera the viewer reports, not the one it was asked for.
    const camera = view.viewer === "model-viewer"
      ? { orbit: look.result.orbit, target: look.result.target, fov: look.result.fov }
      : { orbit: view.orbit, target: view.target, fov: view.fov };
    const uv = await open(browser, origin, "three.html", { ...view, ...camera, asset, pass: "uv" });
    fs.writeFileSync(`${out}_uv.f32`, Buffer.from(uv.result.uv, "base64"));
    const report = { ...look.result, uvCamera: camera, lights: uv.result.lights, console: look.messages };
    fs.writeFileSync(`${out}.json`, JSON.stringify(report, null, 2));
  } finally {
    await browser.close();
    server.close();
  }
}

main().catch((error) => {
  console.error(String(error && error.stack ? error.stack : error));
  process.exit(1);
});
