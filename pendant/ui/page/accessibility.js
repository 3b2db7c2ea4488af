// Accessibility of viser's page (served after client_page.js, in its own <script>; see client_page.py).
//
// viser draws each control as a row: a <label for=ID> on the left whose ID names the row's container, not
// the <input> (nor the slider thumb, nor the progress bar) inside. A screen reader, and Playwright's
// get_by_label, then find no name. This script names them from their row's label, and names the icon-only
// buttons (panel chrome, a notification's close), as the DOM changes (viser builds the panel from websocket
// messages, so a MutationObserver, batched to one pass per animation-free timeout).
//
// Keyboard (docs/screens.md): with nothing focused (a page just loaded, a click in the 3D view), Tab goes
// to Freeze first (viser's panel chrome and a notification come earlier in the page; Shift+Tab from Freeze
// still reaches them), then on down the panel in the order it is drawn.
//
// Contrast (WCAG AA, 4.5:1 for text): Mantine's red and blue (Freeze, Stop, Record, the button rows)
// and the dimmed label grey are darkened (orange and green keep their dark text); the rest is viser's.
(() => {
  "use strict";
  const PASS_DELAY_MS = 150;
  const AXES = ["x", "y", "z", "w"];
  const CSS = `
    :root, [data-mantine-color-scheme] {
      --mantine-color-red-filled: #c92a2a !important; --mantine-color-red-filled-hover: #a51f1f !important;
      --mantine-color-blue-filled: #1971c2 !important; --mantine-color-blue-filled-hover: #155ea3 !important;
      --mantine-color-blue-outline: #1971c2 !important; --mantine-color-blue-text: #1971c2 !important;
      --mantine-color-blue-light-color: #1971c2 !important;
      --mantine-color-dimmed: #5f6770 !important;
    }`;

  function named(element) {
    const label = element.getAttribute("aria-label");
    return (label !== null && label.trim() !== "") || element.hasAttribute("aria-labelledby");
  }

  function name(element, text) {
    if (!named(element)) element.setAttribute("aria-label", text);
  }

  // The row a label heads: viser's <p><label></p> sits in a fixed-width cell beside the control's cell.
  function rowOf(label) {
    const cell = label.closest("p") ? label.closest("p").parentElement : label.parentElement;
    return cell ? cell.parentElement : null;
  }

  function nameRow(label) {
    const text = label.textContent.trim();
    const row = rowOf(label);
    if (!text || !row) return;
    const inputs = [...row.querySelectorAll("input:not([type=hidden]), textarea")];
    const sliders = [...row.querySelectorAll("[role=slider]")];
    if (inputs.length === 1) {
      name(inputs[0], text);
      if (inputs[0].id && label.getAttribute("for") !== inputs[0].id) label.setAttribute("for", inputs[0].id);
    } else {
      inputs.forEach((input, k) => name(input, `${text} ${AXES[k] || k + 1}`));
    }
    sliders.forEach((slider, k) => name(slider, sliders.length === 1 ? `${text} slider` : `${text} slider ${k + 1}`));
    row.querySelectorAll("[role=progressbar]").forEach((bar) => name(bar, text));
  }

  function iconName(button) {
    const title = button.getAttribute("title");
    if (title) return title;
    if (button.classList.contains("mantine-Notification-closeButton")) return "Close notification";
    if (button.classList.contains("mantine-CloseButton-root")) return "Close";
    const icon = button.querySelector("svg[class*='tabler-icon-']");
    const kind = icon ? [...icon.classList].find((c) => c.startsWith("tabler-icon-") && c !== "tabler-icon") : null;
    return kind ? kind.slice("tabler-icon-".length).replace(/-/g, " ") : "Button";
  }

  function pass() {
    document.querySelectorAll("label[for]").forEach(nameRow);
    document.querySelectorAll("[role=progressbar]").forEach((bar) => name(bar, "Progress"));
    document.querySelectorAll("[role=slider]").forEach((slider) => name(slider, "Slider"));
    document.querySelectorAll("button").forEach((button) => {
      if (!named(button) && !button.textContent.trim()) button.setAttribute("aria-label", iconName(button));
    });
  }

  function freezeButton() {
    return [...document.querySelectorAll("button")].find((b) => b.textContent.trim() === "Freeze") || null;
  }

  function onTab(event) {
    if (event.key !== "Tab" || event.shiftKey || event.altKey || event.ctrlKey || event.metaKey) return;
    const active = document.activeElement;
    if (active !== null && active !== document.body && active !== document.documentElement) return;
    const freeze = freezeButton();
    if (freeze === null || freeze.disabled) return;
    event.preventDefault();
    freeze.focus();
  }

  // Focus kept where the operator put it: a control disabled under the focus (Run, while its run goes) or
  // drawn again (a redrawn row) drops the focus to the page's body, and a keyboard user would need a dozen
  // Tabs to come back. Then the focus goes to the same control drawn again, or else to the next one that
  // can take it. A click elsewhere (the 3D view) is the operator's own choice: left alone.
  let lastFocused = null;
  const FOCUSABLE = "button, input, select, textarea, a[href], [tabindex]:not([tabindex='-1'])";
  function controlName(element) {
    return (element.getAttribute("aria-label") || element.textContent || "").trim();
  }
  function canFocus(element) {
    return !element.disabled && element.tabIndex >= 0 && element.offsetParent !== null;
  }
  function keepFocus() {
    const lost = lastFocused;
    const active = document.activeElement;
    if (lost === null || (active !== null && active !== document.body && active !== document.documentElement)) return;
    if (lost.isConnected && !lost.disabled) return;
    const all = [...document.querySelectorAll(FOCUSABLE)].filter(canFocus);
    const name = controlName(lost);
    const next = lost.isConnected
      ? all.find((element) => lost.compareDocumentPosition(element) & Node.DOCUMENT_POSITION_FOLLOWING)
      : all.find((element) => name !== "" && controlName(element) === name);
    if (next !== undefined) next.focus();
  }
  function watchFocus() {
    document.addEventListener("focusin", (event) => {
      if (event.target instanceof HTMLElement && event.target !== document.body) lastFocused = event.target;
    }, true);
    document.addEventListener("pointerdown", (event) => {
      if (lastFocused !== null && !(event.target instanceof Node && lastFocused.contains(event.target))) {
        lastFocused = null;
      }
    }, true);
    document.addEventListener("focusout", () => setTimeout(keepFocus, 0), true);
    new MutationObserver(keepFocus).observe(document.body, {
      childList: true, subtree: true, attributes: true, attributeFilter: ["disabled"],
    });
  }

  let pending = null;
  function schedule() {
    if (pending === null) pending = setTimeout(() => ((pending = null), pass()), PASS_DELAY_MS);
  }

  function start() {
    const style = document.createElement("style");
    style.id = "pendant-accessibility";
    style.textContent = CSS;
    document.head.appendChild(style);
    new MutationObserver(schedule).observe(document.body, { childList: true, subtree: true });
    document.addEventListener("keydown", onTab, true);
    watchFocus();
    schedule();
  }

  if (document.body) start();
  else document.addEventListener("DOMContentLoaded", start);
})();
