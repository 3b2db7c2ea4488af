// viser's heartbeat frame every 5 s, not every second, where WebGL is drawn in software (issue 36; loaded
// after client_page.js, before viser).
//
// viser's client draws on demand: a scene message, a camera move, a texture or mesh that has loaded ask for
// a frame and 250 ms more (its requestRender). Besides, a heartbeat asks for a frame every second, a safety
// net for a change that asks for none. Without a GPU each frame is drawn in software (0.5-0.7 s of the GPU
// process at 1400x900 on the suite's machine), and at rest the heartbeat's are the same picture again: they
// were about a quarter of what an open page at rest cost Chromium (benchmarks/idle_page.py, 0.7-0.8 of a
// core with them, 0.5-0.6 without). The net stays, at REST_HEARTBEAT_MS.
// The heartbeat is the only setInterval of viser 1.1.1's client (pinned in pyproject.toml):
// `setInterval(() => invalidate(), 1000)` in App.tsx. window.__pendant.heartbeat says whether it was
// found ("slowed"), so that a viser whose heartbeat changed shape fails tests/browser/test_rest_frames.py.
// ?heartbeat_ms=1000: viser's own rate, for comparison.
(() => {
  "use strict";
  const pendant = window.__pendant || {};
  if (!pendant.software || !pendant.tuned) return;
  const VISER_HEARTBEAT_MS = 1000;
  const asked = parseFloat(new URLSearchParams(location.search).get("heartbeat_ms") || "");
  const REST_HEARTBEAT_MS = asked > 0 ? asked : 5000;
  const VISER_HEARTBEAT = /^\(\)\s*=>\s*[\w$]+\(\)$/; // its minified `() => invalidate()`
  pendant.heartbeat = "not found";
  const setInterval = window.setInterval.bind(window);
  window.setInterval = (handler, delay, ...rest) => {
    if (delay === VISER_HEARTBEAT_MS && typeof handler === "function" && VISER_HEARTBEAT.test(String(handler))) {
      pendant.heartbeat = "slowed";
      return setInterval(handler, REST_HEARTBEAT_MS, ...rest);
    }
    return setInterval(handler, delay, ...rest);
  };
})();
