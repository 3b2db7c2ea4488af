// The jog pad is one Tab stop (docs/screens.md, "The keyboard"): a roving tabindex, as WAI-ARIA's composite
// widgets do. Tab enters the pad on the button last used (J1- at first) and the next Tab leaves it for the
// teach row (Record, then Run 3 Tabs on); the arrow keys move between the pad's 12 buttons. Before, the pad
// was 12 Tab stops and Record 12 Tabs from J1-. Space or Enter held on the focused button jogs as before
// (client_page.js). Focus only: nothing here sends anything.
(() => {
  "use strict";
  const BUTTONS = "#jog-pad [data-jog-uuid]";
  const PER_AXIS = 2; // - then + on each row
  let current = 0; // the pad's button that takes the Tab stop, by its place (kept across a redrawn pad)

  const buttons = () => [...document.querySelectorAll(BUTTONS)];
  function rove(list) {
    if (list.length === 0) return;
    current = Math.min(current, list.length - 1);
    list.forEach((button, k) => {
      const wanted = k === current ? "0" : "-1";
      if (button.getAttribute("tabindex") !== wanted) button.setAttribute("tabindex", wanted);
    });
  }
  // Where an arrow goes from button `k`: left and right along the pad (J1-, J1+, J2-, ...), up and down to
  // the same sign of the axis above or below; Home and End to its first and last button. null: not ours.
  function next(key, k, count) {
    const moves = {
      ArrowLeft: k - 1, ArrowRight: k + 1, ArrowUp: k - PER_AXIS, ArrowDown: k + PER_AXIS,
      Home: 0, End: count - 1,
    };
    if (!(key in moves)) return null;
    return Math.max(0, Math.min(count - 1, moves[key]));
  }

  document.addEventListener("keydown", (event) => {
    if (event.altKey || event.ctrlKey || event.metaKey || event.shiftKey) return;
    const button = event.target instanceof Element ? event.target.closest(BUTTONS) : null;
    if (button === null) return;
    const list = buttons();
    const to = next(event.key, list.indexOf(button), list.length);
    if (to === null) return;
    event.preventDefault(); // no scrolling, and not the 3D view's keys
    event.stopPropagation();
    // While a jog is held (a key or a pointer) the focus stays on its button: the release belongs there.
    if (document.documentElement.dataset.jogging !== undefined) return;
    current = to;
    rove(list);
    list[to].focus();
  }, true);
  // A click or a programmatic focus on a pad button makes it the pad's Tab stop too.
  document.addEventListener("focusin", (event) => {
    const button = event.target instanceof Element ? event.target.closest(BUTTONS) : null;
    if (button === null) return;
    const list = buttons();
    current = Math.max(0, list.indexOf(button));
    rove(list);
  }, true);
  // The pad is redrawn when its frame or role changes: the new buttons get the same Tab stop.
  let pad = null;
  new MutationObserver(() => {
    const shown = document.getElementById("jog-pad");
    if (shown === pad) return;
    pad = shown;
    rove(buttons());
  }).observe(document.documentElement, { childList: true, subtree: true });
})();
