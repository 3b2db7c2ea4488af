// The 3D view is drawn again only when what it shows has changed (loaded after client_page.js, before viser).
//
// viser's client draws on demand, but with a heartbeat frame a second and a 250 ms burst of frames after every
// request (a GUI update asks for one too). Without a GPU every such frame is drawn in software for the same
// picture: an open page with the arm at rest cost Chromium 0.8-1.0 of a core (benchmarks/idle_page.py), which
// a tablet's battery, a room of viewers' laptops and the suite's two cores all pay.
// three.js's devtools hook (__THREE_DEVTOOLS__, which it tells of every renderer it makes) hands us viser's
// renderer. Its render() of a scene to the screen first writes down what the frame would show: the camera, the
// drawing buffer, and every visible object's world matrix, material (version, colour, opacity, every shader
// uniform, its textures) and geometry (its buffers' versions, draw range, instances). When that is
// what the last drawn frame showed, nothing is drawn: the buffer keeps its picture (viser asks for
// preserveDrawingBuffer) and view_frames.js has nothing new to show. A frame is drawn at least every
// SAFETY_NET_MS all the same, so whatever this list might miss is on screen within that. While the arm moves
// (client_page.js's armMoving) every frame is drawn, unsigned.
//
// ?still=off: every frame drawn, as before (benchmarks/idle_page.py compares the two).
(() => {
  "use strict";
  const pendant = (window.__pendant = window.__pendant || {});
  pendant.stillSkipped = 0; // frames not drawn: their picture was on screen already
  if (new URLSearchParams(location.search).get("still") === "off") return;
  const SAFETY_NET_MS = 5000;

  let last = [];
  let next = [];
  let drawnAt = -Infinity;

  function putValue(out, value) {
    if (typeof value === "number") out.push(value);
    else if (typeof value === "boolean") out.push(value ? 1 : 0);
    else if (value === null || value === undefined) out.push(-1);
    else if (value.isTexture) putTexture(out, value);
    else if (value.isColor) out.push(value.r, value.g, value.b);
    else if (value.isMatrix3 || value.isMatrix4) for (const e of value.elements) out.push(e);
    else if (value.isVector2 || value.isVector3 || value.isVector4 || value.isQuaternion) value.toArray(out, out.length);
    else if (Array.isArray(value) || ArrayBuffer.isView(value)) for (const item of value) putValue(out, item);
    else out.push(-2); // something else (a string, an object): its changes are left to the safety net
  }

  // A small data texture is signed by what it holds: viser's labels write their positions into one and
  // raise its version every frame, changed or not.
  const DATA_SIGNED_MAX = 16384;
  function putTexture(out, texture) {
    const data = texture.isDataTexture && texture.image ? texture.image.data : null;
    if (data && data.length <= DATA_SIGNED_MAX) {
      out.push(texture.id, data.length);
      for (let i = 0; i < data.length; i++) out.push(data[i]);
    } else {
      out.push(texture.id, texture.version);
    }
  }

  // A material by what it draws with, not by its version: some of viser's raise it (needsUpdate) every frame.
  const MATERIAL_KEYS = [
    "opacity", "visible", "transparent", "side", "blending", "depthTest", "depthWrite", "alphaTest", "wireframe",
    "vertexColors", "color", "emissive", "map", "envMap", "alphaMap", "normalMap", "linewidth", "size",
    "roughness", "metalness", "envMapIntensity", "flatShading",
  ];
  function putMaterial(out, material) {
    out.push(material.id);
    for (const key of MATERIAL_KEYS) if (key in material) putValue(out, material[key]);
    if (material.defines) out.push(Object.keys(material.defines).length);
    const uniforms = material.uniforms;
    if (uniforms) for (const name in uniforms) putValue(out, uniforms[name].value);
  }

  function putGeometry(out, geometry) {
    out.push(geometry.id, geometry.drawRange.start, geometry.drawRange.count);
    if (geometry.index) out.push(geometry.index.version);
    for (const name in geometry.attributes) {
      const attribute = geometry.attributes[name];
      out.push(attribute.isInterleavedBufferAttribute ? attribute.data.version : attribute.version);
    }
    if (geometry.instanceCount !== undefined) out.push(geometry.instanceCount);
  }

  function putObject(out, object) {
    out.push(object.id, object.renderOrder);
    for (const e of object.matrixWorld.elements) out.push(e);
    if (object.isInstancedMesh) {
      out.push(object.count, object.instanceMatrix.version, object.instanceColor ? object.instanceColor.version : -1);
    }
    if (object.isBatchedMesh) {
      for (const key in object) if (object[key] && object[key].isTexture) putValue(out, object[key]);
    }
    const material = object.material;
    if (Array.isArray(material)) for (const m of material) putMaterial(out, m);
    else if (material) putMaterial(out, material);
    if (object.geometry) putGeometry(out, object.geometry);
  }

  // What a render of `scene` by `camera` to the screen would show, written into `out`.
  function sign(out, renderer, scene, camera) {
    out.length = 0;
    const gl = renderer.getContext();
    out.push(gl.drawingBufferWidth, gl.drawingBufferHeight, renderer.getPixelRatio(), renderer.toneMappingExposure);
    const clear = renderer.getClearColor(copied);
    const viewport = renderer.getViewport(copied2);
    out.push(renderer.getClearAlpha(), clear.r, clear.g, clear.b, viewport.x, viewport.y, viewport.z, viewport.w);
    putValue(out, scene.background);
    putValue(out, scene.environment);
    out.push(camera.id);
    putValue(out, camera.matrixWorld);
    putValue(out, camera.projectionMatrix);
    scene.traverseVisible((object) => putObject(out, object));
  }

  function same(a, b) {
    if (a.length !== b.length) return false;
    for (let i = 0; i < a.length; i++) if (a[i] !== b[i] && !(a[i] !== a[i] && b[i] !== b[i])) return false;
    return true;
  }

  // getClearColor and getViewport copy into what they are given (a THREE.Color, a THREE.Vector4): these two
  // take the copy without three.js's classes at hand.
  const copier = () => ({
    copy(from) {
      Object.assign(this, { r: from.r, g: from.g, b: from.b, x: from.x, y: from.y, z: from.z, w: from.w });
      return this;
    },
  });
  const copied = copier();
  const copied2 = copier();

  function quieten(renderer) {
    const render = renderer.render;
    renderer.render = function (scene, camera) {
      if (!scene || !scene.isScene || !camera || this.getRenderTarget() !== null) {
        return render.call(this, scene, camera); // a render to a texture (an environment map): always
      }
      const now = performance.now();
      if (pendant.armMoving && pendant.armMoving()) {
        // Every frame is new while the arm moves: drawn without signing it (no work added to those frames).
        last.length = 0;
        drawnAt = now;
        return render.call(this, scene, camera);
      }
      // render() brings the matrices up to date itself; done first here so that they are what is signed.
      if (scene.matrixWorldAutoUpdate === true) scene.updateMatrixWorld();
      if (camera.parent === null && camera.matrixWorldAutoUpdate === true) camera.updateMatrixWorld();
      sign(next, this, scene, camera);
      if (same(next, last) && now - drawnAt < SAFETY_NET_MS) {
        pendant.stillSkipped += 1;
        return undefined;
      }
      [last, next] = [next, last];
      drawnAt = now;
      return render.call(this, scene, camera);
    };
  }

  const hook = window.__THREE_DEVTOOLS__ || (window.__THREE_DEVTOOLS__ = new EventTarget());
  hook.addEventListener("observe", (event) => {
    const renderer = event.detail;
    if (renderer && renderer.isWebGLRenderer && !renderer.__pendantStill) {
      renderer.__pendantStill = true;
      quieten(renderer);
    }
  });
})();
