"""The Program tab's "Files" folder: New, Save, Save as, Load, Delete file, Download, Export, Upload.

Save never refuses a program without a file: it saves under the name typed in "Save as name" if that is a
new one, and otherwise asks for a name there (the box focused) until it gets one.

Nothing is lost without a question: New, Load and Upload over unsaved changes, and Delete file always, wait
for the operator to confirm in a dialog that takes the focus (kit/confirm.py).
"""

from __future__ import annotations

from collections.abc import Callable

import viser

from pendant.program.files import MAX_FILE_BYTES, ProgramFileError, sanitize_name
from pendant.ui.kit.confirm import Confirmation
from pendant.ui.kit.focus_request import focus_request
from pendant.ui.kit.upload_limit import limit_uploads
from pendant.ui.program.host import ProgramHost

NO_FILE = "(no saved programs)"
FILE_OPTIONS = ("New", "Save", "Save as", "Load", "Delete file")
FILE_NAME_LABEL = "Save as name"


class FileSection:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        self._name_asks = 0  # how many times Save asked for a name: each ask focuses the box again
        gui = host.target.gui
        with gui.add_folder("Files"):
            self.status = gui.add_markdown("")
            self.name_prompt = gui.add_html("", visible=False)  # Save's question for an unnamed program
            self.file_name = gui.add_text(FILE_NAME_LABEL, initial_value="")
            self.saved = gui.add_dropdown("Saved programs", options=[NO_FILE], initial_value=NO_FILE)
            self.files = gui.add_button_group("File", options=FILE_OPTIONS)
            self.confirmation = Confirmation(host.target)
            self.download = gui.add_button("Download .json", icon=viser.Icon.DOWNLOAD)
            self.export = gui.add_button("Export Python script", icon=viser.Icon.CODE)
            self.upload = gui.add_upload_button(
                "Upload .json", icon=viser.Icon.UPLOAD, mime_type="application/json"
            )
            limit_uploads(gui, MAX_FILE_BYTES)  # no larger file is a program: refuse it before it is kept
        shared = host.shared
        self.files.on_click(lambda e: self._file_action(str(self.files.value), e.client))
        self.download.on_click(lambda e: self._send(e.client, *shared.download()))
        self.export.on_click(
            lambda e: host.edit("Export", e.client, lambda: self._send(e.client, *shared.export()))
        )
        self.upload.on_upload(self._on_upload)

    @property
    def question(self) -> viser.GuiMarkdownHandle:
        """The last question's text (in its dialog)."""
        return self.confirmation.question

    @property
    def confirm(self) -> viser.GuiButtonGroupHandle:
        """The open question's Cancel / Yes."""
        return self.confirmation.buttons

    # --- asking first -------------------------------------------------------------------------------
    def _ask(
        self, label: str, question: str, action: Callable[[], object], client: viser.ClientHandle | None
    ) -> None:
        """Do `action` (as edit `label`) once the operator answers Yes to `question`."""
        if not self._host.allowed(client, label):
            return
        self.confirmation.ask(question, lambda answered_by: self._host.edit(label, answered_by, action))

    def _unsaved(self) -> str | None:
        shared = self._host.shared
        if not shared.dirty or (not shared.program.steps and not shared.program.waypoints):
            return None
        where = f"{shared.file_name}.json" if shared.file_name else "the unsaved program"
        return f"Discard the unsaved changes to {where}? (Undo brings them back.)"

    def _maybe_ask(self, label: str, action: Callable[[], object], client: viser.ClientHandle | None) -> None:
        question = self._unsaved()
        if question is None:
            self._host.edit(label, client, action)
        else:
            self._ask(label, question, action, client)

    # --- actions ------------------------------------------------------------------------------------
    def _file_action(self, option: str, client: viser.ClientHandle | None) -> None:
        host, shared = self._host, self._host.shared
        saved = str(self.saved.value)

        def then_select_first(action: Callable[[], object]) -> Callable[[], None]:
            def run() -> None:
                action()
                host.select_line(0 if shared.program.steps else None)

            return run

        match option:
            case "New":
                self._maybe_ask("New", then_select_first(shared.new), client)
            case "Load" if saved != NO_FILE:
                self._maybe_ask("Load", then_select_first(lambda: shared.load(saved)), client)
            case "Delete file" if saved != NO_FILE:
                question = f"Delete the file {saved}.json? This cannot be undone."
                self._ask("Delete file", question, lambda: shared.delete_file(saved), client)
            case "Save" if shared.file_name is None:
                self._save_unnamed(str(self.file_name.value), client)
            case "Save" | "Save as":
                name = str(self.file_name.value)
                self._save(
                    option, client, shared.save if option == "Save" else (lambda: shared.save_as(name))
                )

    def _save(self, label: str, client: viser.ClientHandle | None, action: Callable[[], object]) -> None:
        shared = self._host.shared

        def save() -> None:
            action()
            self.name_prompt.visible = False
            if client is None:
                return
            # The save stands; what the history says about it (not recorded, and why) is shown with it.
            note = getattr(shared.store, "history_note", None)
            if note:
                client.add_notification(title="Saved", body=note, color="yellow")
            else:
                body = f"{shared.file_name}.json"
                client.add_notification(title="Saved", body=body, color="green", auto_close_seconds=3.0)

        self._host.edit(label, client, save)

    def _save_unnamed(self, typed: str, client: viser.ClientHandle | None) -> None:
        """Save of a program with no file yet: under `typed` if that names a new file, otherwise ask for a
        name in the box (focused), which the next Save uses."""
        if not self._host.allowed(client, "Save"):
            return
        shared = self._host.shared
        try:
            name = sanitize_name(typed) if typed.strip() else None
        except ProgramFileError as error:
            question = f"{error}. Type a name for this program, then press Save."
        else:
            if name is not None and not shared.store.exists(name):
                self._save("Save", client, lambda: shared.save_as(name))
                return
            question = (
                "Name this program: type a name, then press Save."
                if name is None
                else f"A program named {name!r} already exists: type a new name, then press Save."
            )
        self._name_asks += 1
        self.name_prompt.content = focus_request(FILE_NAME_LABEL, self._name_asks, question)
        self.name_prompt.visible = True

    def _on_upload(self, event: viser.GuiEvent) -> None:
        uploaded = self.upload.value
        shared = self._host.shared

        def read_then_open() -> None:  # a refused file is said at once, before any question
            program = shared.read_upload(uploaded.name, uploaded.content)
            self._maybe_ask("Upload", lambda: shared.open_uploaded(program), event.client)

        self._host.edit("Upload", event.client, read_then_open)

    def _send(self, client: viser.ClientHandle | None, filename: str, content: bytes) -> None:
        if client is not None:
            client.send_file_download(filename, content)

    # --- display ------------------------------------------------------------------------------------
    def redraw(self) -> None:
        shared = self._host.shared
        names = shared.saved_programs() or [NO_FILE]
        self._host.syncing = True
        try:
            if list(self.saved.options) != names:
                self.saved.options = names
            current = shared.file_name
            if current in names and self.saved.value != current:
                self.saved.value = current
            if not self.file_name.value and current:
                self.file_name.value = current
        finally:
            self._host.syncing = False
        status = f"Programs folder: `{shared.store.folder}` ({len(shared.saved_programs())} saved)"
        problem = shared.store.restore_problem
        if problem is not None:  # said until the pendant restarts: the refused file waits in the folder
            status += f"  \n**{problem}**"
        self.status.content = status
