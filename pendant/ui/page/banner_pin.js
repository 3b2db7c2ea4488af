// The banner (page/banner.py) stays in sight under Freeze at every scroll position of every tab: its box and
// its buttons' boxes are pinned below Freeze's (client_page.js pins that one), each just under the last.
// Styles are written only when they change: the status redraws 30 times a second.
(() => {
  const MAX_BUTTONS = 3; // banner.py's MAX_BUTTONS
  let queued = false;
  function bannerBoxes(banner) {
    const freezeButton = [...document.querySelectorAll("button")].find((b) => b.textContent.trim() === "Freeze");
    const freeze = freezeButton === undefined ? null : freezeButton.parentElement;
    if (freeze === null) return [null, []];
    let box = banner;
    while (box !== null && box.parentElement !== freeze.parentElement) box = box.parentElement;
    if (box === null) return [null, []];
    const boxes = [box];
    for (let next = box.nextElementSibling; next !== null && boxes.length <= MAX_BUTTONS; next = next.nextElementSibling) {
      if (next.querySelectorAll("button").length !== 1 || next.querySelector("#motion-state") !== null) break;
      boxes.push(next);
    }
    return [freeze, boxes];
  }
  function pin() {
    queued = false;
    const banner = document.getElementById("recovery-banner");
    const old = [...document.querySelectorAll("[data-banner-pinned]")];
    if (banner === null && old.length === 0) return;
    const [freeze, boxes] = banner === null ? [null, []] : bannerBoxes(banner);
    let top = freeze === null ? 0 : freeze.offsetHeight;
    for (const box of boxes) {
      if (box.style.top !== `${top}px` || box.style.position !== "sticky") {
        Object.assign(box.style, {
          position: "sticky", top: `${top}px`, zIndex: "19", background: "var(--mantine-color-body, white)",
        });
      }
      box.dataset.bannerPinned = "1";
      top += box.offsetHeight;
    }
    for (const box of old) {
      if (boxes.includes(box)) continue;
      Object.assign(box.style, { position: "", top: "", zIndex: "", background: "" });
      delete box.dataset.bannerPinned;
    }
  }
  const later = () => { if (!queued) { queued = true; requestAnimationFrame(pin); } };
  new MutationObserver(later).observe(document.documentElement, { childList: true, subtree: true, characterData: true });
  window.addEventListener("resize", later);
})();
