// The phone layout (screens <= 480 px wide; docs/screens.md). viser 1.1.1 shows its control panel there as
// a bottom sheet 20em wide floating over the lower right of the 3D view; here it becomes a full-width sheet
// over the lower part of the screen, the 3D view shrinks to the part above it (so the camera frames the whole
// arm there, as on a desktop), and the tabs stay on one row that scrolls sideways inside itself.
//
// A grab bar on the sheet's top edge resizes it: drag it, or tap it (or the panel's title row) to switch
// between the usual and a small sheet. The sheet never collapses below Freeze: viser's own tap on the title
// row (which folded the whole panel, Freeze with it) is taken over here. Desktop and tablet are untouched:
// every rule sits in the media query, and the script only marks the boxes the rules apply to.
(() => {
  "use strict";
  const PHONE = "(max-width: 480px)";
  const USUAL = 0.64; // of the screen's height: the sheet (the jog pad and the teach row in full); the view keeps the rest
  const SMALL = 0.34; // Freeze, the status and the start of a tab
  const MIN = 0.25;
  const MAX = 0.75; // the view keeps a quarter of the screen
  const BAR_PX = 22;
  const DRAG_SLOP_PX = 6;
  const CSS = `
    #pendant-sheet-bar {
      display: none; position: fixed; left: 0; right: 0; bottom: var(--pendant-sheet-h); height: ${BAR_PX}px;
      z-index: 11; align-items: center; justify-content: center; border: 0; padding: 0; margin: 0;
      background: var(--mantine-color-body, white); border-top: 1px solid #ced4da; touch-action: none;
      cursor: ns-resize;
    }
    #pendant-sheet-bar::after { content: ""; width: 44px; height: 5px; border-radius: 3px; background: #868e96; }
    @media ${PHONE} {
      [data-phone-sheet] {
        left: 0 !important; right: 0 !important; width: 100% !important;
        height: var(--pendant-sheet-h) !important; max-height: none !important; transition: none !important;
      }
      [data-phone-sheet] [data-phone-sheet-inner] { width: 100% !important; }
      [data-phone-sheet] .mantine-ScrollArea-root { height: 100%; }
      [data-phone-sheet] .mantine-ScrollArea-viewport { max-height: 100% !important; }
      [data-phone-view] { height: calc(100% - var(--pendant-sheet-h) - ${BAR_PX}px) !important; }
      [data-phone-sheet] [role=tablist] {
        flex-wrap: nowrap !important; overflow-x: auto !important; overflow-y: hidden; scrollbar-width: none;
      }
      [data-phone-sheet] [role=tablist] > [role=tab] { flex-shrink: 0; }
      /* viser underlines wrapped rows with a 200vw stripe right of each tab: on one scrolling row the stripes
         would be scrolled to. Each tab's own bottom border underlines the row. */
      [data-phone-sheet] [role=tablist] > [role=tab]::after { display: none !important; }
      #pendant-sheet-bar { display: flex; }
    }
`;

  const phone = window.matchMedia(PHONE);
  let fraction = USUAL;
  let bar = null;
  let queued = false;

  function apply() {
    const px = Math.round(window.innerHeight * fraction);
    document.documentElement.style.setProperty("--pendant-sheet-h", `${px}px`);
    if (bar !== null) {
      bar.setAttribute("aria-label", fraction > (USUAL + SMALL) / 2 ? "Make the panel smaller" : "Make the panel larger");
    }
  }
  const toggle = () => { fraction = fraction > (USUAL + SMALL) / 2 ? SMALL : USUAL; apply(); };

  // viser's bottom sheet: the fixed Paper around Freeze; the 3D view: the canvas's box beside it.
  function mark() {
    queued = false;
    const old = document.querySelector("[data-phone-sheet]");
    if (old !== null && old.isConnected && document.querySelector("[data-phone-view]") !== null) return;
    const freeze = [...document.querySelectorAll("button")].find((b) => b.textContent.trim() === "Freeze");
    const sheet = freeze === undefined ? null : freeze.closest(".mantine-Paper-root");
    const canvas = document.querySelector("canvas");
    if (sheet === null || sheet.style.position !== "fixed" || canvas === null) return;
    const content = sheet.querySelector(".mantine-ScrollArea-content");
    let view = canvas;
    while (view.parentElement !== null && !view.parentElement.contains(sheet)) view = view.parentElement;
    if (content === null || content.firstElementChild === null || view.parentElement === null) return;
    sheet.dataset.phoneSheet = "";
    content.firstElementChild.dataset.phoneSheetInner = "";
    view.dataset.phoneView = "";
  }
  const later = () => { if (!queued) { queued = true; setTimeout(mark, 0); } };

  // The bar: a drag resizes the sheet, a tap toggles it. Pointer capture keeps the drag with the bar.
  function makeBar() {
    bar = document.createElement("button");
    bar.id = "pendant-sheet-bar";
    bar.type = "button";
    let drag = null;
    let dragged = false; // the click that ends a drag is not a tap
    bar.addEventListener("pointerdown", (event) => {
      drag = { y: event.clientY, start: fraction };
      dragged = false;
      bar.setPointerCapture(event.pointerId);
    });
    bar.addEventListener("pointermove", (event) => {
      if (drag === null) return;
      const dy = event.clientY - drag.y;
      if (!dragged && Math.abs(dy) < DRAG_SLOP_PX) return;
      dragged = true;
      fraction = Math.min(MAX, Math.max(MIN, drag.start - dy / window.innerHeight));
      apply();
    });
    bar.addEventListener("pointerup", () => { drag = null; });
    bar.addEventListener("pointercancel", () => { drag = null; });
    bar.addEventListener("click", () => {
      if (!dragged) toggle();
      dragged = false;
    });
    document.body.appendChild(bar);
    apply();
  }

  // viser's title row (connection status, the panel's name, its icons) folds the whole panel on a tap; on
  // a phone that tap resizes the sheet instead, so Freeze never folds away. Its icon buttons still work.
  document.addEventListener("click", (event) => {
    if (!phone.matches || !(event.target instanceof Element)) return;
    const inner = event.target.closest("[data-phone-sheet-inner]");
    if (inner === null || event.target.closest("button, a, input") !== null) return;
    const row = inner.firstElementChild;
    if (row === null || !row.contains(event.target)) return;
    event.stopPropagation();
    toggle();
  }, true);
  // A tab chosen on the one-row bar slides wholly into sight (only the bar scrolls, never the panel).
  document.addEventListener("click", (event) => {
    const tab = event.target instanceof Element ? event.target.closest("[data-phone-sheet] [role=tab]") : null;
    if (tab === null || !phone.matches) return;
    const list = tab.parentElement;
    const left = tab.offsetLeft - list.offsetLeft;
    if (left < list.scrollLeft) list.scrollLeft = left;
    else if (left + tab.offsetWidth > list.scrollLeft + list.clientWidth) list.scrollLeft = left + tab.offsetWidth - list.clientWidth;
  });

  function start() {
    const style = document.createElement("style");
    style.id = "pendant-phone-layout";
    style.textContent = CSS;
    document.head.appendChild(style);
    makeBar();
    new MutationObserver(later).observe(document.body, { childList: true, subtree: true });
    window.addEventListener("resize", apply);
    later();
  }
  if (document.body) start();
  else document.addEventListener("DOMContentLoaded", start);
})();
