// Draws window.VIEW.asset with three.js from the camera window.VIEW gives, either as
// the viewer shows it ("look") or with every surface replaced by its texture
// coordinates ("uv", into a float target), so a test can tell which texel each pixel
// shows. The result goes to window.RESULT.
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

const TONE_MAPPINGS = {
  none: THREE.NoToneMapping,
  linear: THREE.LinearToneMapping,
  neutral: THREE.NeutralToneMapping,
};

function cameraFor(view) {
  const { theta, phi, radius } = view.orbit;
  const target = new THREE.Vector3(...view.target);
  // The span of the scene along the view sets the clip planes; nothing is cut off.
  const camera = new THREE.PerspectiveCamera(view.fov, 1, radius / 100, radius * 100);
  camera.position.setFromSphericalCoords(radius, phi, theta).add(target);
  camera.lookAt(target);
  return camera;
}

// Each surface shows its texture coordinates (the set its emissive texture reads).
function uvMaterial(attribute) {
  return new THREE.ShaderMaterial({
    vertexShader: `
      ${attribute === "uv" ? "" : `attribute vec2 ${attribute};`}
      varying vec2 vCoordinates;
      void main() {
        vCoordinates = ${attribute};
        gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
      }`,
    fragmentShader: `
      varying vec2 vCoordinates;
      void main() { gl_FragColor = vec4(vCoordinates, 0.0, 1.0); }`,
    side: THREE.DoubleSide,
  });
}

function toBase64(array) {
  const bytes = new Uint8Array(array.buffer);
  let text = "";
  for (let i = 0; i < bytes.length; i += 0x8000) {
    text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  }
  return btoa(text);
}

async function main() {
  const view = window.VIEW;
  const canvas = document.getElementById("view");
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(view.size, view.size, false);
  const gltf = await new GLTFLoader().loadAsync(view.asset);
  const scene = gltf.scene;
  const camera = cameraFor(view);
  let lights = 0;
  scene.traverse((node) => {
    if (node.isLight) lights += 1;
  });

  if (view.pass === "uv") {
    const coordinates = uvMaterial(view.uvAttribute);
    scene.traverse((node) => {
      if (node.isMesh) node.material = coordinates;
    });
    const target = new THREE.WebGLRenderTarget(view.size, view.size, { type: THREE.FloatType });
    renderer.setRenderTarget(target);
    renderer.setClearColor(0x000000, 0);
    renderer.render(scene, camera);
    const pixels = new Float32Array(view.size * view.size * 4);
    renderer.readRenderTargetPixels(target, 0, 0, view.size, view.size, pixels);
    window.RESULT = { lights, uv: toBase64(pixels) };
    return;
  }
  renderer.toneMapping = TONE_MAPPINGS[view.toneMapping];
  renderer.toneMappingExposure = view.exposure;
  renderer.setClearColor(0x000000, 0);
  renderer.render(scene, camera);
  window.RESULT = { lights, renderer: "three.js " + THREE.REVISION };
}

main().catch((error) => {
  window.RESULT = { error: String(error && error.stack ? error.stack : error) };
});
