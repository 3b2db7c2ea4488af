// The 3D view's pixels off the page's main thread (issue 35; loaded after client_page.js, before viser).
//
// Without a GPU (Chromium's software compositing), the compositor copies a WebGL canvas of the page back to
// memory on every frame, on the main thread (GLES2::ReadPixels in the commit), and that copy waits for the
// software renderer to finish drawing: 40-500 ms a frame during which no press, release or keystroke is
// handled. (OffscreenCanvas.transferToImageBitmap waits the same way: measured 190-330 ms.)
// Here viser's three.js draws, with the same WebGL calls, into an OffscreenCanvas that is never composited;
// after each frame the renderer copies the picture into a pixel buffer when it gets there (WebGL2
// readPixels into a PIXEL_PACK_BUFFER, then a fence), and the page reads the buffer only once the fence
// has passed, so it never waits. The pixels go to a Web Worker that owns the canvas on screen (a 2D one:
// no readback to composite it). The next frame is drawn once the last one is read, so the page never asks
// for frames faster than the renderer draws them.
//
// While the arm moves (a jog held, a program, the API: client_page.js's armMoving) the view is drawn at
// MOVING_SCALE of its size (half the pixels) and shown stretched: the software renderer's frame is what
// bounds the frame rate (7-10 a second at 1400x900), and whoever watches a moving arm watches it move, not
// its edges. At rest it is drawn at full size again.
//
// ?view=inline: the old way (viser's canvas drawn in the page), for comparison (benchmarks/frames.py);
// ?view=none: three.js runs as usual but draws nothing (its draw calls skipped), the floor of that
// benchmark: the page without its 3D view's pixels;
// ?moving_scale=1: no smaller frames while the arm moves, for comparison.
(() => {
  "use strict";
  const pendant = window.__pendant || {};
  const query = new URLSearchParams(location.search);
  if (!pendant.software || !pendant.tuned || query.get("view") === "inline") return;
  if (typeof OffscreenCanvas !== "function" || !("transferControlToOffscreen" in HTMLCanvasElement.prototype)) return;

  // The worker: shows each frame it is given on the canvas the page handed it.
  const WORKER = `
    let context = null, behind = [255, 255, 255];
    self.onmessage = (event) => {
      const d = event.data;
      if (d.canvas) { context = d.canvas.getContext("2d", { alpha: false }); behind = d.behind; return; }
      if (context === null) return;
      // WebGL's pixels are premultiplied by their alpha, and the page showed them over what is behind.
      const p = d.pixels, [r, g, b] = behind;
      for (let i = 0; i < p.length; i += 4) {
        const rest = 255 - p[i + 3];
        if (rest === 0) continue;
        p[i] += (rest * r) / 255; p[i + 1] += (rest * g) / 255; p[i + 2] += (rest * b) / 255; p[i + 3] = 255;
      }
      const canvas = context.canvas;
      if (canvas.width !== d.width) canvas.width = d.width;
      if (canvas.height !== d.height) canvas.height = d.height;
      context.putImageData(new ImageData(d.pixels, d.width, d.height), 0, 0);
    };
  `;
  const FENCE_POLL_MS = 5;
  const MOVING_SCALE = parseFloat(query.get("moving_scale") || "") || 0.7;
  const DRAW_NOTHING = query.get("view") === "none";
  const DRAWS = ["clear", "drawArrays", "drawElements", "drawArraysInstanced", "drawElementsInstanced", "drawRangeElements"];

  let view = null; // { gl, offscreen, worker, drawn, fence }
  const getContext = HTMLCanvasElement.prototype.getContext;

  // The colour the page shows behind the view (the first box with a background of its own), as [r, g, b].
  function backgroundOf(element) {
    for (let box = element; box !== null; box = box.parentElement) {
      const rgba = getComputedStyle(box).backgroundColor.match(/[\d.]+/g);
      if (rgba !== null && (rgba.length < 4 || parseFloat(rgba[3]) > 0)) return rgba.slice(0, 3).map(Number);
    }
    return [255, 255, 255];
  }

  function redirect(canvas, type, options) {
    const offscreen = new OffscreenCanvas(Math.max(1, canvas.width), Math.max(1, canvas.height));
    // As client_page.js asks of every WebGL context in software: no multisampling.
    const gl = offscreen.getContext(type, Object.assign({}, options || {}, { antialias: false }));
    if (gl === null) return null;
    // three.js sizes the drawing buffer through the element's width and height: they size the offscreen one,
    // at `scale` of what was asked while a jog is held. Its viewport and scissor are scaled alike.
    const asked = { width: offscreen.width, height: offscreen.height };
    const sizeOffscreen = () => {
      const scale = view === null ? 1 : view.scale;
      offscreen.width = Math.max(1, Math.round(asked.width * scale));
      offscreen.height = Math.max(1, Math.round(asked.height * scale));
    };
    for (const side of ["width", "height"]) {
      Object.defineProperty(canvas, side, {
        get: () => asked[side],
        set: (value) => { asked[side] = Math.max(1, value | 0); sizeOffscreen(); },
        configurable: true,
      });
    }
    const screen = document.createElement("canvas");
    screen.dataset.pendantView = "";
    screen.setAttribute("aria-hidden", "true");
    Object.assign(screen.style, {
      position: "absolute", left: "0", top: "0", width: "100%", height: "100%", pointerEvents: "none",
      display: "block", transform: "scaleY(-1)", // WebGL's rows run bottom to top
    });
    const parent = canvas.parentElement;
    if (getComputedStyle(parent).position === "static") parent.style.position = "relative";
    parent.insertBefore(screen, canvas);
    canvas.style.position = "relative"; // above the picture, as before: its events reach viser's controls
    const worker = new Worker(URL.createObjectURL(new Blob([WORKER], { type: "text/javascript" })));
    const target = screen.transferControlToOffscreen();
    worker.postMessage({ canvas: target, behind: backgroundOf(parent) }, [target]);
    view = {
      gl, offscreen, worker, drawn: false, fence: null, pixels: null, size: 0, pending: null, frames: 0,
      scale: 1, boxes: [], sizeOffscreen,
    };
    for (const name of ["viewport", "scissor"]) { // three.js's boxes, kept as asked and set scaled
      const kept = { set: gl[name].bind(gl), box: null };
      view.boxes.push(kept);
      gl[name] = (...box) => { kept.box = box; kept.set(...box.map((v) => Math.round(v * view.scale))); };
    }
    for (const name of DRAWS) {
      const draw = gl[name];
      if (typeof draw !== "function") continue;
      gl[name] = DRAW_NOTHING
        ? () => undefined
        : function (...args) { view.drawn = true; return draw.apply(this, args); };
    }
    window.__pendant.view = "worker";
    window.__pendant.viewFrames = () => view.frames; // frames shown, for benchmarks/frames.py
    return gl;
  }

  HTMLCanvasElement.prototype.getContext = function (type, options) {
    if (view === null && type === "webgl2" && this.isConnected) {
      try {
        const gl = redirect(this, type, options);
        if (gl !== null) return gl;
      } catch (error) {
        console.warn("pendant: the 3D view is drawn in the page", error);
      }
    }
    return getContext.call(this, type, options);
  };

  // After a frame's callbacks: what was drawn is copied into a pixel buffer, by the renderer, when it is done
  // drawing (no wait here), and a fence marks the end of that copy.
  function present() {
    // Drawn outside a frame while the last copy is under way: it goes after the next frame's callbacks.
    if (view === null || !view.drawn || view.fence !== null) return;
    view.drawn = false;
    const gl = view.gl;
    const width = gl.drawingBufferWidth, height = gl.drawingBufferHeight, size = width * height * 4;
    if (view.pixels === null || view.size !== size) {
      if (view.pixels !== null) gl.deleteBuffer(view.pixels);
      view.pixels = gl.createBuffer();
      gl.bindBuffer(gl.PIXEL_PACK_BUFFER, view.pixels);
      gl.bufferData(gl.PIXEL_PACK_BUFFER, size, gl.STREAM_READ);
      view.size = size;
    }
    const read = gl.getParameter(gl.READ_FRAMEBUFFER_BINDING);
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, null);
    gl.bindBuffer(gl.PIXEL_PACK_BUFFER, view.pixels);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, 0);
    gl.bindBuffer(gl.PIXEL_PACK_BUFFER, null);
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, read);
    view.fence = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    view.pending = { width, height };
    gl.flush();
    // Chromium learns that a fence has passed only from polls a task apart: poll often (a cheap read), so
    // the frame is shown, and the next one drawn, soon after the renderer is done (the view's frames rate).
    const poll = () => { if (busy()) setTimeout(poll, FENCE_POLL_MS); };
    setTimeout(poll, FENCE_POLL_MS);
  }
  // The renderer still busy with the last frame: the next one waits (without blocking) for it. Done: its
  // pixels go to the worker.
  function busy() {
    if (view === null || view.fence === null) return false;
    const gl = view.gl;
    if (gl.getSyncParameter(view.fence, gl.SYNC_STATUS) !== gl.SIGNALED) return true;
    gl.deleteSync(view.fence);
    view.fence = null;
    const { width, height } = view.pending;
    const pixels = new Uint8ClampedArray(width * height * 4);
    gl.bindBuffer(gl.PIXEL_PACK_BUFFER, view.pixels);
    gl.getBufferSubData(gl.PIXEL_PACK_BUFFER, 0, pixels);
    gl.bindBuffer(gl.PIXEL_PACK_BUFFER, null);
    view.worker.postMessage({ pixels, width, height }, [pixels.buffer]);
    view.frames += 1;
    return false;
  }

  // Only the callbacks that draw the view wait for the renderer (three.js's loop passes the same function
  // each frame); the page's other frame callbacks (panel transitions, touch decisions) never wait for it.
  const drawers = new WeakSet();
  // Before a frame is drawn: smaller while the arm moves, full size at rest (never while a copy is pending).
  function rescale() {
    const wanted = pendant.armMoving() ? MOVING_SCALE : 1;
    if (view === null || view.scale === wanted || view.fence !== null) return;
    view.scale = wanted;
    view.sizeOffscreen();
    for (const { set, box } of view.boxes) {
      if (box !== null) set(...box.map((v) => Math.round(v * wanted)));
    }
  }
  const raf = window.requestAnimationFrame.bind(window);
  window.requestAnimationFrame = (callback) => {
    const run = (t) => {
      if (busy() && drawers.has(callback)) { raf(run); return; }
      if (drawers.has(callback)) rescale();
      const before = view !== null && view.drawn;
      callback(t);
      if (view !== null && view.drawn && !before) drawers.add(callback);
      present();
    };
    return raf(run);
  };
})();
