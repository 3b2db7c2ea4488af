// The pendant's additions to viser's page (served by client_page.py, before viser's own script runs).
//
// 1. Hold-to-run that does not depend on the render loop: while a jog button is held, the "still held"
//    confirmations come from a timer in viser's websocket Web Worker, which keeps its pace however long
//    a (software WebGL) frame blocks the page's main thread. Release, cancel, blur and a hidden tab stop
//    them at once; a main thread that stops answering for MAIN_STALL_MS stops them too, and the server's
//    deadman stops the arm when they stop arriving (tab closed, network cut).
// 2. Touch: a finger jogs only after TOUCH_DELAY_MS without moving more than TOUCH_SLOP_PX, so a swipe
//    that starts on a jog button scrolls the panel and never moves the arm.
// 3. Software WebGL (no GPU): no multisampling, a capped pixel ratio and frame rate, which leave the main
//    thread time for input.
// 4. Freeze pinned to the top of the panel, which stays as wide as its dock (docs/screens.md).
// 5. `?token=T` in the page's URL (as Jupyter's): handed to viser's websocket URL (`?websocket=`), whose
//    handshake is where the pendant reads it, before viser's own script reads the page's URL.
// 6. Focus on request: a question in the panel (pendant/ui/kit/focus_request.py) puts the cursor in the text box
//    it names (Save of an unnamed program asks for the name there).
// 7. The jog pad's live values written into its labels in place (the pad itself is not rebuilt on a value).
// 8. An upload's outcome: viser's "File uploaded successfully." says "File received.", hidden by a refusal.
// 9. The jog's confirmations and release over the hold line, a socket of their own (see section 1).
// 10. The page's own buttons for hidden viser buttons (`data-click-uuid`: the teach row) send their click.
// 11. Which tabs are on screen: a tab's marker (`data-tab-shown`, pendant/ui/kit/tab_watch.py) says when it
//     comes into view and when it leaves, so the pendant sends its live drawings only while they are seen.
(() => {
  "use strict";
  (function tokenIntoWebsocketUrl() {
    const params = new URLSearchParams(location.search);
    const token = params.get("token");
    if (token === null || params.has("websocket")) return;
    const ws = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}${location.pathname}`;
    params.delete("token");
    params.set("websocket", `${ws}?token=${encodeURIComponent(token)}`);
    history.replaceState(null, "", `${location.pathname}?${params.toString()}${location.hash}`);
  })();
  const HOLD_HZ = 20;
  const TOUCH_DELAY_MS = 60;
  const TOUCH_SLOP_PX = 10;
  const ALIVE_MS = 100;
  // A main thread silent this long stops the hold: a release it has not seen yet then stops the arm within
  // MAIN_STALL_MS + the server's 200 ms deadman, however long the page stays stuck.
  const MAIN_STALL_MS = 400;
  const SOFTWARE_MAX_DPR = 0.75;
  const SOFTWARE_FRAME_MS = 50;
  // While the arm moves, frames further apart: each software-rendered frame blocks the main thread (and
  // takes a core), and a release or a Stop waits for the frame it lands in. The pad's values still change
  // at 10 Hz.
  const SOFTWARE_JOG_FRAME_MS = 100;
  // With the view drawn off the main thread (view_frames.js), smaller while the arm moves, a frame no
  // longer blocks it: frames 60 ms apart then give 12 a second at 1400x900 instead of 9
  // (benchmarks/frames.py).
  const WORKER_JOG_FRAME_MS = 60;
  // The browser's own, before the spacing below wraps it: a touch's decision waits for the next frame,
  // not for the next frame the spacing lets through.
  const nextFrame = window.requestAnimationFrame.bind(window);
  // While a touch is being decided, the 3D view's frames wait (at most this long after the touch): a
  // software frame blocks the main thread for 50-300 ms, and the decision (a frame) would wait behind it.
  const TOUCH_FRAME_HOLD_MS = 150;
  let framesHeldUntil = 0;

  // --- 3. rendering cost in software WebGL ------------------------------------------------------------
  function softwareWebGL() {
    try {
      const gl = document.createElement("canvas").getContext("webgl");
      if (!gl) return true;
      const info = gl.getExtension("WEBGL_debug_renderer_info");
      const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
      const lose = gl.getExtension("WEBGL_lose_context");
      if (lose) lose.loseContext();
      return /swiftshader|llvmpipe|softpipe|software/i.test(name);
    } catch (e) {
      return false;
    }
  }
  // ?render=viser: viser's own rendering, for comparison (benchmarks/jog.py).
  const tuned = new URLSearchParams(location.search).get("render") !== "viser";
  const software = softwareWebGL();
  // The arm moves: a jog held on this page, or any motion the status block shows (a program, the API,
  // another browser). Frames are then spaced and sized for motion (here and in view_frames.js).
  const armMoving = () => {
    if (document.documentElement.dataset.jogging !== undefined) return true;
    const state = document.getElementById("motion-state");
    return state !== null && state.textContent === "RUNNING";
  };
  window.__pendant = { software, tuned, armMoving };
  if (software && tuned) {
    const getContext = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (type, options) {
      if (type === "webgl2" || type === "webgl") {
        options = Object.assign({}, options || {}, { antialias: false });
      }
      return getContext.call(this, type, options);
    };
    const asked = parseFloat(new URLSearchParams(location.search).get("dpr") || "");  // ?dpr=1: sharper
    const dpr = Math.min(window.devicePixelRatio || 1, asked > 0 ? asked : SOFTWARE_MAX_DPR);
    Object.defineProperty(window, "devicePixelRatio", { get: () => dpr, configurable: true });
    // Frames back to back leave the main thread no time for input: a release would wait for the next
    // frame too. At most one frame per SOFTWARE_FRAME_MS leaves it gaps.
    const raf = window.requestAnimationFrame.bind(window);
    const query = new URLSearchParams(location.search);  // ?frame_ms= / ?jog_frame_ms=: for benchmarks
    const idleMs = parseFloat(query.get("frame_ms") || "") || SOFTWARE_FRAME_MS;
    const askedJogMs = parseFloat(query.get("jog_frame_ms") || "");
    const jogMs = () =>
      askedJogMs || (window.__pendant.view === "worker" ? WORKER_JOG_FRAME_MS : SOFTWARE_JOG_FRAME_MS);
    let lastFrame = 0;
    window.requestAnimationFrame = (callback) => raf((now) => {
      const spacing = armMoving() ? jogMs() : idleMs;
      const wait = Math.max(lastFrame + spacing, framesHeldUntil) - now;
      const run = (t) => { lastFrame = t; callback(t); };
      if (wait <= 0) run(now);
      else setTimeout(() => raf(run), wait);
    });
  }

  // --- 1. the hold signal from viser's websocket worker ----------------------------------------------
  // Runs inside the worker, before viser's code: it sends through viser's own handler (same socket,
  // same encoding), so the server sees exactly the messages viser's button would send.
  const WORKER_PREAMBLE = `{
    let holdTimer = null, lastAlive = 0;
    // The hold line (pendant/ui/kit/hold_line.py): a socket of its own for a press's confirmations and
    // release, read on a thread of its own, not behind every viewer's traffic on viser's. A press uses
    // it only when it is open as the press starts, and then for its release too (never both for one press).
    // pressUuid: the press under way (until its release): a hold asked again after a stall keeps its channel.
    let line = null, lineUrl = null, pressLine = null, pressUuid = null;
    const openLine = () => {
      if (lineUrl === null || (line !== null && line.readyState <= 1)) return;
      try {
        const socket = new WebSocket(lineUrl);
        socket.onclose = () => { if (line === socket) line = null; };
        line = socket;
      } catch (error) { line = null; }
    };
    const send = (message) => {
      if (typeof self.onmessage === "function") self.onmessage({ data: { type: "send", message } });
    };
    const stop = () => { if (holdTimer !== null) { clearInterval(holdTimer); holdTimer = null; } };
    self.addEventListener("message", (event) => {
      const d = event.data;
      if (!d || typeof d.type !== "string" || !d.type.startsWith("pendant_")) return;
      event.stopImmediatePropagation();
      if (d.type === "pendant_line") {
        if (d.url !== lineUrl) { if (line !== null) line.close(); line = null; lineUrl = d.url; }
        openLine();
      } else if (d.type === "pendant_hold") {
        stop();
        lastAlive = performance.now();
        if (d.uuid !== pressUuid) pressLine = line !== null && line.readyState === 1 ? line : null;
        pressUuid = d.uuid;
        const via = pressLine;
        const hold = { type: "GuiButtonHoldMessage", uuid: d.uuid, frequency: d.hz };
        const confirm = via !== null ? () => via.send("hold " + d.uuid) : () => send(hold);
        if (via === null) openLine(); // for the next press
        confirm();
        holdTimer = setInterval(() => {
          // The page hung: stop until it asks again (it does once it runs and the button is still held).
          if (performance.now() - lastAlive > ${MAIN_STALL_MS}) { stop(); return; }
          confirm();
        }, 1000 / d.hz);
      } else if (d.type === "pendant_alive") {
        lastAlive = performance.now();
      } else if (d.type === "pendant_click") {  // a hidden button's click, nothing else (section 11)
        send({ type: "GuiUpdateMessage", uuid: d.uuid, updates: { value: true } });
      } else if (d.type === "pendant_release") {
        stop();
        if (pressLine !== null && pressLine.readyState === 1) pressLine.send("release " + d.uuid);
        else send({ type: "GuiUpdateMessage", uuid: d.uuid, updates: { value: true } });
        pressLine = null;
        pressUuid = null;
      }
    });
  }
`;
  const NativeWorker = window.Worker;
  let socketWorker = null;
  function PendantWorker(url, options) {
    if (socketWorker === null && String(url).startsWith("blob:")) {
      try {
        // Vite revokes the blob URL right after construction: read it now, synchronously.
        const xhr = new XMLHttpRequest();
        xhr.open("GET", url, false);
        xhr.send();
        const source = xhr.responseText;
        if (source.includes("set_server") && source.includes("zstd_wasm")) {
          const blob = new Blob([WORKER_PREAMBLE, source], { type: "text/javascript" });
          socketWorker = new NativeWorker(URL.createObjectURL(blob), options);
          return socketWorker;
        }
      } catch (error) {
        console.warn("pendant: hold signal from the page instead of the worker", error);
      }
    }
    return new NativeWorker(url, options);
  }
  PendantWorker.prototype = NativeWorker.prototype;
  window.Worker = PendantWorker;

  const post = (message) => { if (socketWorker !== null) socketWorker.postMessage(message); };
  const holds = new Map(); // pointer id (or "key") -> { uuid, stop, started, x, y }
  let aliveTimer = null;
  let lastTick = 0;

  // Tells the worker this thread runs. After a stall long enough for the worker to have stopped, the
  // holds still held (no release was handled in the meantime: input runs before timers) ask again.
  function tick() {
    const now = performance.now();
    const stalled = now - lastTick > MAIN_STALL_MS * 0.75;
    lastTick = now;
    post({ type: "pendant_alive" });
    if (!stalled) return;
    for (const hold of holds.values()) {
      if (hold.started) post({ type: "pendant_hold", uuid: hold.uuid, hz: HOLD_HZ });
    }
  }

  function start(hold) {
    hold.started = true;
    post({ type: "pendant_hold", uuid: hold.uuid, hz: HOLD_HZ });
    if (aliveTimer === null) {
      lastTick = performance.now();
      aliveTimer = setInterval(tick, ALIVE_MS);
    }
    document.documentElement.dataset.jogging = hold.uuid;
  }

  // `click`: the release of a press (the server stops a continuous jog, or makes one step); otherwise a
  // cancel (swipe, focus lost) that must only stop, never step.
  function finish(id, click) {
    const hold = holds.get(id);
    if (hold === undefined) return;
    holds.delete(id);
    if (!hold.started) framesHeldUntil = 0;
    if (click) post({ type: "pendant_release", uuid: hold.uuid });
    else if (hold.started) post({ type: "pendant_release", uuid: hold.stop });
    if (holds.size === 0) {
      if (aliveTimer !== null) clearInterval(aliveTimer);
      aliveTimer = null;
      delete document.documentElement.dataset.jogging;
    }
  }
  const finishAll = () => { for (const id of [...holds.keys()]) finish(id, false); };
  // The page is going: its worker's release may die with it, so the stop also goes by a fetch that outlives
  // the page (a GET, the one method viser's server takes besides the websocket).
  const pageGoing = () => {
    const jogging = [...holds.values()].some((hold) => hold.started);
    finishAll();
    if (!jogging) return;
    fetch(new URL("pendant-stop-jog", location.href), { keepalive: true, cache: "no-store" }).catch(() => {});
  };

  function jogButton(target) {
    const button = target instanceof Element ? target.closest("[data-jog-uuid]") : null;
    return button !== null && !button.disabled ? button : null;
  }

  document.addEventListener("pointerdown", (event) => {
    const button = jogButton(event.target);
    if (button === null || (event.pointerType === "mouse" && event.button !== 0)) return;
    if (holds.size > 0) finishAll(); // one jog at a time: a second finger stops the first
    const hold = {
      uuid: button.dataset.jogUuid, stop: button.closest("[data-jog-stop]").dataset.jogStop,
      started: false, x: event.clientX, y: event.clientY,
    };
    holds.set(event.pointerId, hold);
    // A touch captures its pointer to the button it began on; the pad is redrawn with new values while
    // the arm moves, and events of a captured pointer would go to the detached old button and never reach
    // this document. Released, they go to whatever is under the finger.
    if (button.hasPointerCapture(event.pointerId)) button.releasePointerCapture(event.pointerId);
    if (event.pointerType !== "touch") {
      start(hold);
      return;
    }
    // Decide in the first frame that begins TOUCH_DELAY_MS after the finger touched: Chrome hands the page
    // the moves and cancels that reached it before a frame at that frame's start, so a swipe is seen before
    // this decides. The window counts from the touch's own time (event.timeStamp), not from this handler,
    // which runs late when a frame was being drawn; the view's frames wait meanwhile (TOUCH_FRAME_HOLD_MS).
    const now = performance.now();
    const decideAt = Math.min(event.timeStamp > 0 ? event.timeStamp : now, now) + TOUCH_DELAY_MS;
    framesHeldUntil = decideAt - TOUCH_DELAY_MS + TOUCH_FRAME_HOLD_MS;
    const decide = (frameTime) => {
      if (holds.get(event.pointerId) !== hold || hold.started) return;
      if (frameTime < decideAt) { nextFrame(decide); return; }
      framesHeldUntil = 0;
      start(hold);
    };
    nextFrame(decide);
  }, true);
  document.addEventListener("pointermove", (event) => {
    const hold = holds.get(event.pointerId);
    if (hold === undefined || event.pointerType !== "touch") return;
    if (Math.hypot(event.clientX - hold.x, event.clientY - hold.y) > TOUCH_SLOP_PX) {
      finish(event.pointerId, false); // a swipe, not a press
    }
  }, true);
  document.addEventListener("pointerup", (event) => finish(event.pointerId, true), true);
  document.addEventListener("pointercancel", (event) => finish(event.pointerId, false), true);
  document.addEventListener("contextmenu", (event) => { if (jogButton(event.target)) event.preventDefault(); }, true);
  window.addEventListener("blur", finishAll);
  document.addEventListener("visibilitychange", () => { if (document.hidden) finishAll(); });
  window.addEventListener("pagehide", pageGoing);
  window.addEventListener("beforeunload", pageGoing); // the tab is closing: stop now, not when it is gone

  // --- Freeze stays in reach: pinned to the top of the panel at every scroll position of every tab ------
  let pinned = null;
  function pinFreeze() {
    if (pinned !== null && pinned.isConnected) return;
    const freeze = [...document.querySelectorAll("button")].find((b) => b.textContent.trim() === "Freeze");
    if (freeze === undefined || freeze.parentElement === null) return;
    pinned = freeze.parentElement; // viser's box around the button, a child of the panel's content
    // Between it and the panel's scrolling viewport, a box that hides its overflow would be the one the
    // pin sticks to (and never scrolls): clipping instead keeps the look and lets the pin work.
    for (let box = pinned.parentElement; box !== null; box = box.parentElement) {
      if (box.classList.contains("mantine-ScrollArea-viewport")) break;
      const style = getComputedStyle(box);
      if (style.overflowY === "hidden" || style.overflowX === "hidden") {
        box.style.overflow = "clip";
        // A hidden overflow also let the box shrink below its content's width (a grid or flex item's
        // automatic minimum is 0 only for a scroll container); clip does not: say it, or the widest thing
        // in a tab widens the whole panel and pushes Freeze off its right edge.
        box.style.minWidth = "0";
      }
    }
    Object.assign(pinned.style, {
      position: "sticky", top: "0", zIndex: "20", paddingTop: "6px",
      background: "var(--mantine-color-body, white)", boxShadow: "0 4px 6px -4px rgba(0,0,0,0.25)",
    });
  }
  new MutationObserver(pinFreeze).observe(document.documentElement, { childList: true, subtree: true });

  // The jog pad names this browser's hold line ("PORT KEY"): the worker opens it before the first press.
  let lineShown = null;
  function lineFromPad() {
    const pad = document.querySelector("[data-jog-line]");
    const line = pad === null ? null : pad.dataset.jogLine;
    if (line === null || line === lineShown || socketWorker === null) return;
    lineShown = line;
    const [port, key] = line.split(" ");
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    post({ type: "pendant_line", url: `${scheme}://${location.hostname}:${port}/?key=${encodeURIComponent(key)}` });
  }
  new MutationObserver(lineFromPad).observe(document.documentElement, { childList: true, subtree: true });

  // The page's own buttons that stand for a hidden viser button (the Jog tab's teach row): a click (mouse,
  // finger, Enter or Space) sends that button's click, as viser's own button would.
  document.addEventListener("click", (event) => {
    const button = event.target instanceof Element ? event.target.closest("[data-click-uuid]") : null;
    if (button === null || button.disabled) return;
    post({ type: "pendant_release", uuid: button.dataset.clickUuid });
  }, true);

  // Keyboard: Space or Enter held on a focused jog button.
  document.addEventListener("keydown", (event) => {
    if ((event.key !== " " && event.key !== "Enter") || event.repeat) return;
    const button = jogButton(event.target);
    if (button === null) return;
    event.preventDefault();
    finishAll();
    const hold = { uuid: button.dataset.jogUuid, stop: button.closest("[data-jog-stop]").dataset.jogStop,
                   started: false, x: 0, y: 0 };
    holds.set("key", hold);
    start(hold);
  }, true);
  document.addEventListener("keyup", (event) => {
    if (event.key === " " || event.key === "Enter") finish("key", true);
  }, true);

  // --- 7. The jog pad's live values, in place ----------------------------------------------------------
  // The pad's markup is rebuilt only when its frame or role changes (pendant/ui/jog/pad.py): its values come
  // in a hidden element of their own, copied here into the pad's labels, so its buttons (and the keyboard
  // focus on one) stay while the arm moves.
  (function jogValuesInPlace() {
    let applied = null;
    let pad = null;
    function apply() {
      const source = document.querySelector("[data-jog-values]");
      const current = document.getElementById("jog-pad");
      if (source === null || current === null) return;
      const text = source.dataset.jogValues;
      if (text === applied && current === pad) return;
      applied = text;
      pad = current;
      text.split("|").forEach((value, axis) => {
        const label = current.querySelector(`[data-jog-value="${axis}"]`);
        if (label !== null && label.textContent !== value) label.textContent = value;
      });
    }
    new MutationObserver(apply).observe(document.documentElement, { childList: true, subtree: true });
  })();

  // --- 11. Which tabs are on screen ---------------------------------------------------------------------
  // An IntersectionObserver with a margin far larger than any screen says when a marker has a box at all
  // (its tab shown) or none (display: none, unmounted), without forcing a layout (offsetParent, read at each
  // change of the page's styles, forced one up to 10 times a second in every page while the arm moved). New
  // markers are looked for at most every TAB_LOOK_MS after elements are added or removed. A click is told
  // only once the websocket's worker is there to send it.
  (function tabsOnScreen() {
    const TAB_LOOK_MS = 100;
    const told = new Map(); // marker element -> shown, as last told to the pendant
    const seen = new Map(); // marker element -> shown, as last seen here
    function tell(marker) {
      const shown = seen.get(marker);
      if (shown === undefined || told.get(marker) === shown) return;
      if (socketWorker === null) { setTimeout(() => tell(marker), TAB_LOOK_MS); return; } // not yet: again soon
      post({ type: "pendant_click", uuid: shown ? marker.dataset.tabShown : marker.dataset.tabHidden });
      told.set(marker, shown);
    }
    const boxes = new IntersectionObserver((entries) => {
      for (const entry of entries) {
        const marker = entry.target;
        const shown = entry.isIntersecting && marker.isConnected;
        if (!told.has(marker) && !shown) told.set(marker, false); // hidden from the start: the pendant's default
        seen.set(marker, shown);
        tell(marker);
      }
    }, { rootMargin: "100000px" });
    const watched = new Set();
    let due = null;
    function look() {
      due = null;
      for (const marker of document.querySelectorAll("[data-tab-shown]")) {
        if (watched.has(marker)) continue;
        watched.add(marker);
        boxes.observe(marker);
      }
      for (const marker of watched) {
        if (marker.isConnected) continue;
        boxes.unobserve(marker);
        watched.delete(marker);
        seen.set(marker, false); // unmounted: out of view
        tell(marker);
        told.delete(marker);
        seen.delete(marker);
      }
    }
    new MutationObserver(() => { if (due === null) due = setTimeout(look, TAB_LOOK_MS); })
      .observe(document.documentElement, { childList: true, subtree: true });
  })();

  // --- 8. An upload's outcome is the pendant's to say -------------------------------------------------
  // viser says "File uploaded successfully." as soon as the bytes are in, before the pendant has read them:
  // a refused file showed it beside "Upload refused". Here it says "File received.", and a refusal that
  // comes after it hides it, so only the refusal is said.
  (function uploadOutcome() {
    const seen = new WeakMap(); // notification -> when it first appeared
    const REFUSAL = /refused|not loaded|not uploaded/i;
    let order = 0;
    function pass() {
      const notes = [...document.querySelectorAll(".mantine-Notification-root")];
      for (const note of notes) if (!seen.has(note)) seen.set(note, ++order);
      const title = (note) => (note.querySelector(".mantine-Notification-title") || {}).textContent || "";
      const lastRefusal = Math.max(0, ...notes.filter((n) => REFUSAL.test(title(n))).map((n) => seen.get(n)));
      for (const note of notes) {
        if (!title(note).startsWith("Uploading ")) continue;
        const text = note.querySelector(".mantine-Notification-description");
        if (text !== null && text.textContent.trim() === "File uploaded successfully.") text.textContent = "File received.";
        if (lastRefusal > seen.get(note) && note.style.display !== "none") note.style.display = "none";
      }
    }
    new MutationObserver(pass).observe(document.documentElement, { childList: true, subtree: true });
  })();

  // --- 6. Focus on request ----------------------------------------------------------------------------
  // Layout and focus only (nothing here sends anything). The panel's labels are not tied to their inputs:
  // the box asked for is the first input in the smallest box holding both the label's text and an input.
  (function focusOnRequest() {
    const asked = new WeakSet();
    function inputLabelled(label) {
      const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
      for (let text = walker.nextNode(); text !== null; text = walker.nextNode()) {
        if (text.data.trim() !== label) continue;
        for (let box = text.parentElement; box !== null; box = box.parentElement) {
          const input = box.querySelector("input:not([type=hidden]), textarea");
          if (input !== null) return input;
        }
      }
      return null;
    }
    function focusAsked() {
      for (const ask of document.querySelectorAll("[data-pendant-focus]")) {
        if (asked.has(ask) || ask.offsetParent === null) continue; // done, or not shown yet
        const input = inputLabelled(ask.dataset.pendantFocus);
        if (input === null) continue;
        asked.add(ask);
        input.focus();
        input.select();
      }
    }
    new MutationObserver(focusAsked).observe(document.documentElement, {
      childList: true, subtree: true, attributes: true, attributeFilter: ["style", "class"],
    });
  })();
})();
