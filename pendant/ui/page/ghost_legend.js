// The ghost legend (pendant/ui/scene/ghost_stage.py): which translucent arms the 3D view shows (target, plan,
// waypoint, check playback, replay: one, or each with "Every ghost" on, the newest first), in a small box at
// the view's bottom left corner (the top left has viser's notifications). The panel carries a hidden element
// per ghost (`data-ghost-legend`); this copies their text over the view and hides the box when no ghost is
// shown. Layout only: nothing here sends anything.
(() => {
  "use strict";
  const MARGIN_PX = 8;
  const STYLE = "position:fixed;z-index:5;pointer-events:none;display:none;flex-direction:column;" +
    "gap:2px;padding:3px 8px;border-radius:6px;font:600 13px system-ui,sans-serif;" +
    "background:rgba(255,255,255,0.9);color:#212529;box-shadow:0 1px 3px rgba(0,0,0,0.25)";
  const ROW = '<span style="display:flex;align-items:center;gap:6px"><span data-swatch ' +
    'style="width:12px;height:12px;border-radius:3px;display:inline-block"></span><span data-words></span></span>';
  let box = null;
  let shown = null;
  function legendBox() {
    if (box !== null && box.isConnected) return box;
    box = document.createElement("div");
    box.id = "ghost-legend";
    box.setAttribute("role", "status");
    box.style.cssText = STYLE;
    document.body.appendChild(box);
    return box;
  }
  function apply() {
    if (document.body === null) return;
    const ghosts = [...document.querySelectorAll("[data-ghost-legend]")]
      .map((source) => [source.dataset.ghostLegend, source.dataset.ghostColour || ""])
      .filter(([words]) => words !== "");
    const key = JSON.stringify(ghosts);
    if (key === shown && box !== null && box.isConnected) return;
    shown = key;
    const legend = legendBox();
    legend.innerHTML = ROW.repeat(ghosts.length);
    ghosts.forEach(([words, colour], k) => {
      const row = legend.children[k];
      row.querySelector("[data-words]").textContent = words;
      row.querySelector("[data-swatch]").style.background = colour;
    });
    legend.style.display = ghosts.length === 0 ? "none" : "flex";
    place();
  }
  // At the 3D view's bottom left corner, wherever the view is (beside the panel, or above a phone's sheet).
  function place() {
    if (box === null || box.style.display === "none") return;
    const canvas = document.querySelector("canvas");
    const view = canvas === null ? null : canvas.getBoundingClientRect();
    const left = view === null ? 0 : Math.max(0, view.left);
    const bottom = view === null ? innerHeight : Math.min(innerHeight, view.bottom);
    box.style.left = `${left + MARGIN_PX}px`;
    box.style.top = `${bottom - MARGIN_PX - box.offsetHeight}px`;
  }
  window.addEventListener("resize", place);
  new MutationObserver(apply).observe(document.documentElement, {
    childList: true, subtree: true, attributes: true, attributeFilter: ["data-ghost-legend"],
  });
})();
