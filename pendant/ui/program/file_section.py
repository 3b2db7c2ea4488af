"""The Program tab's "Files" folder: New, Save, Save as, Load, Delete file, Download, Export, Upload.

Nothing is lost without a question: New, Load and Upload over unsaved changes, and Delete file always, wait
for the operator to confirm (a row of buttons in the folder, so every browser and the tests see it).
"""

from __future__ import annotations

from collections.abc import Callable

import viser

from pendant.program.files import MAX_FILE_BYTES
from pendant.ui.kit.confirm import Confirmation
from pendant.ui.kit.upload_limit import limit_uploads
from pendant.ui.program.host import ProgramHost

NO_FILE = "(no saved programs)"
FILE_OPTIONS = ("New", "Save", "Save as", "Load", "Delete file")


class FileSection:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        gui = host.target.gui
        with gui.add_folder("Files"):
            self.status = gui.add_markdown("")
            self.file_name = gui.add_text("Save as name", initial_value="")
            self.saved = gui.add_dropdown("Saved programs", options=[NO_FILE], initial_value=NO_FILE)
            self.files = gui.add_button_group("File", options=FILE_OPTIONS)
            self.confirmation = Confirmation(host.target)
            self.question, self.confirm = self.confirmation.question, self.confirmation.buttons
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
            case "Save" | "Save as":
                name = str(self.file_name.value)
                action = shared.save if option == "Save" else (lambda: shared.save_as(name))

                def save() -> None:
                    action()
                    if client is not None:
                        body = f"{shared.file_name}.json"
                        client.add_notification(
                            title="Saved", body=body, color="green", auto_close_seconds=3.0
                        )

                host.edit(option, client, save)

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
