// What the operator types is what is used (served after client_page.js; see pendant/ui/kit/typed_field.py).
//
// The panel's text boxes (every numeric field is one) send their text to the server only when the operator
// commits it: Enter, or leaving the box (Tab, a click elsewhere, a button). Keystrokes stay in the box:
// viser would send each one, and the server's answer to "-6" could land in the box after "-69" was typed.
// While a box has focus or an uncommitted edit, an update from the server is kept aside (not written over
// what the operator typed); leaving the box unedited shows it, committing an edit drops it (the edit wins).
//
// How: React writes a server update through the element's `value` property (its value tracker wraps the
// prototype's); that property is wrapped here, per box. React never sees the keystrokes (their `input`
// events stop at the document); the commit replays one `input` event, which React's onChange turns into
// viser's one update message with the whole text.
(() => {
  "use strict";
  const boxes = new WeakMap(); // input -> { dirty, held, committing }

  function typedBox(target) {
    return target instanceof HTMLInputElement && target.classList.contains("mantine-TextInput-input")
      ? target
      : null;
  }

  function guard(input) {
    let box = boxes.get(input);
    if (box !== undefined) return box;
    box = { dirty: false, held: null, committing: false };
    boxes.set(input, box);
    const own = Object.getOwnPropertyDescriptor(input, "value")
      || Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value");
    const state = box;
    Object.defineProperty(input, "value", {
      configurable: true,
      enumerable: own.enumerable,
      get() { return own.get.call(this); },
      set(value) {
        const text = String(value);
        const editing = document.activeElement === this || state.dirty;
        if (!state.committing && editing && text !== own.get.call(this)) {
          state.held = text; // the server's value, shown when the operator leaves the box unedited
          this.dataset.pendantHeld = "";
          return;
        }
        own.set.call(this, value);
      },
    });
    box.show = (text) => own.set.call(input, text);
    return box;
  }

  function commit(input) {
    const box = boxes.get(input);
    if (box === undefined) return;
    if (!box.dirty) {
      if (box.held !== null && document.activeElement !== input) box.show(box.held);
      box.held = null;
      delete input.dataset.pendantHeld;
      return;
    }
    box.dirty = false;
    box.held = null;
    delete input.dataset.pendantHeld;
    delete input.dataset.pendantDraft;
    // React's onChange fires only when the text differs from the last value React knows the box has. A
    // server value held back above never reached the box, so React may still know the text being
    // committed (typed again after the server changed it: J2 -69.3, moved home, -69.3 typed again) and
    // would drop the commit, leaving the box saying what the server never got. Make the text new to it;
    // the server ignores a commit of the value it already has.
    const tracker = input._valueTracker;
    if (tracker && typeof tracker.setValue === "function") tracker.setValue("\u0000");
    box.committing = true;
    try {
      input.dispatchEvent(new Event("input", { bubbles: true }));
    } finally {
      box.committing = false;
    }
  }

  document.addEventListener("focusin", (event) => {
    const input = typedBox(event.target);
    if (input !== null) guard(input);
  }, true);
  for (const type of ["input", "change"]) {
    document.addEventListener(type, (event) => {
      const input = typedBox(event.target);
      if (input === null) return;
      const box = guard(input);
      if (box.committing) return; // the commit's own event: on to React
      event.stopImmediatePropagation();
      if (type === "input") {
        box.dirty = true;
        input.dataset.pendantDraft = "";
      }
    }, true);
  }
  document.addEventListener("keydown", (event) => {
    const input = typedBox(event.target);
    if (input === null || event.key !== "Enter" || event.isComposing) return;
    commit(input);
  }, true);
  document.addEventListener("focusout", (event) => {
    const input = typedBox(event.target);
    if (input === null) return;
    // After focus has gone: a held server value is then shown (the box no longer has focus).
    const box = boxes.get(input);
    if (box !== undefined && box.dirty) commit(input);
    else setTimeout(() => commit(input), 0);
  }, true);
})();
