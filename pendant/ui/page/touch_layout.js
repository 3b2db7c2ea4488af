// Touch screens (docs/screens.md, "Touch targets"): every button, box, tab and tick box is at least 44x44 px
// (WCAG 2.5.5), where viser draws them 22-34 px tall for a mouse. On a phone (<= 480 px wide) the jog pad puts
// two axes on a row, so the whole pad and the teach row under it fit the bottom sheet without scrolling,
// and the status block folds to one line (mode, link, state: the joints are in the pad, the TCP in the 3D
// view; parts marked `phone-fold` are hidden). Only marks the page (`data-touch` on <html>) and adds rules: nothing here sends anything.
(() => {
  "use strict";
  const TOUCH = "(pointer: coarse), (any-pointer: coarse)";
  const PHONE = "(max-width: 480px)";
  const MIN_PX = 44;
  const CSS = `
    [data-touch] .mantine-Button-root, [data-touch] [role=tab], [data-touch] .mantine-Input-input,
    [data-touch] .mantine-ActionIcon-root {
      min-height: ${MIN_PX}px !important; min-width: ${MIN_PX}px !important;
    }
    [data-touch] .mantine-Button-root { height: auto !important; }
    [data-touch] .mantine-Input-input { height: ${MIN_PX}px !important; }
    [data-touch] .mantine-Checkbox-root { --checkbox-size: ${MIN_PX}px !important; }
    [data-touch] #jog-pad button { height: ${MIN_PX}px !important; }
    [data-touch] #jog-pad > div { grid-template-columns: 56px 1fr 56px !important; }
    @media ${PHONE} {
      [data-touch] #jog-pad { display: grid; grid-template-columns: 1fr 1fr; column-gap: 8px; }
      [data-touch] #jog-pad > div { grid-template-columns: ${MIN_PX}px 1fr ${MIN_PX}px !important; gap: 3px !important; }
      [data-touch] #jog-pad > div > div { white-space: normal !important; font-size: 0.85em; line-height: 1.1; }
      .phone-fold { display: none !important; }
      .status-line { display: flex; align-items: center; gap: 6px; }
      .status-line > div { margin: 0 !important; }
      .status-line > div + div { padding: 2px 8px !important; font-size: 1em !important; flex-shrink: 0; }
    }
  `;
  const touchScreen = () =>
    window.matchMedia(TOUCH).matches || navigator.maxTouchPoints > 0 || "ontouchstart" in window;
  function mark() {
    if (touchScreen()) document.documentElement.dataset.touch = "";
    else delete document.documentElement.dataset.touch;
  }
  function install() {
    const style = document.createElement("style");
    style.id = "pendant-touch-layout";
    style.textContent = CSS;
    document.head.appendChild(style);
    mark();
  }
  if (document.head !== null) install();
  else document.addEventListener("DOMContentLoaded", install);
  window.matchMedia(TOUCH).addEventListener("change", mark);
})();
