// Puts one <model-viewer> on the page from window.VIEW, waits until it has drawn the
// model at full scale from its final camera, and reports that camera (as the element's
// own API states it) in window.RESULT, for the texture-coordinate pass to repeat.
async function main() {
  const view = window.VIEW;
  await customElements.whenDefined("model-viewer");
  const ModelViewer = customElements.get("model-viewer");
  // A slow (software) GPU would otherwise draw at a quarter of the resolution.
  ModelViewer.minimumRenderScale = 1;
  const element = document.createElement("model-viewer");
  element.style.width = element.style.height = `${view.size}px`;
  element.setAttribute("interaction-prompt", "none");
  const { theta, phi, radius } = view.orbit;
  element.setAttribute("camera-orbit", `${theta}rad ${phi}rad ${radius}m`);
  element.setAttribute("min-camera-orbit", `auto auto ${radius / 10}m`);
  element.setAttribute("camera-target", view.target.map((x) => `${x}m`).join(" "));
  element.setAttribute("field-of-view", `${view.fov}deg`);
  element.setAttribute("min-field-of-view", `${view.fov / 2}deg`);
  element.setAttribute("exposure", String(view.exposure));
  const loaded = new Promise((resolve, reject) => {
    element.addEventListener("load", resolve, { once: true });
    element.addEventListener("error", (event) => reject(new Error(JSON.stringify(event.detail))), { once: true });
  });
  element.src = view.asset;
  document.body.appendChild(element);
  await loaded;
  element.jumpCameraToGoal();
  // Let it settle: the frames after the camera stops are drawn at full scale.
  for (let i = 0; i < 30; i++) await new Promise((resolve) => requestAnimationFrame(resolve));
  await new Promise((resolve) => setTimeout(resolve, 500));
  const orbit = element.getCameraOrbit();
  const target = element.getCameraTarget();
  window.RESULT = {
    orbit: { theta: orbit.theta, phi: orbit.phi, radius: orbit.radius },
    target: [target.x, target.y, target.z],
    fov: element.getFieldOfView(),
    toneMapping: element.toneMapping,
    environment: element.environmentImage ?? null,
    renderer: "model-viewer",
  };
}

main().catch((error) => {
  window.RESULT = { error: String(error && error.stack ? error.stack : error) };
});
