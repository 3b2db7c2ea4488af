"""The Cell tab's "Cell file" folder: save the controller's cell to a file, load one and apply it."""

from __future__ import annotations

from concurrent.futures import Future
from pathlib import Path

import viser

from pendant.cell.file import CellFileError, apply_cell, list_cells, load_cell, read_cell, save_cell
from pendant.controller import Controller
from pendant.ui.kit.commands import CommandRunner, notify_refusal

NO_FILES = "(no cell files)"


class CellFilesSection:
    """Build inside the Cell tab; every save and load goes through `runner` (refused for a viewer)."""

    def __init__(self, gui: viser.GuiApi, runner: CommandRunner, folder: Path) -> None:
        self._runner = runner
        self._folder = folder
        with gui.add_folder("Cell file", expand_by_default=False):
            self.file_name = gui.add_text("File name", initial_value="cell")
            self.save = gui.add_button("Save cell", icon=viser.Icon.DEVICE_FLOPPY)
            self.files = gui.add_dropdown("Cell files", options=[NO_FILES], initial_value=NO_FILES)
            self.load = gui.add_button("Load and apply cell", icon=viser.Icon.FOLDER_OPEN)
        self.refresh_files()
        self.save.on_click(lambda e: self.save_file(e.client))
        self.load.on_click(lambda e: self.load_file(self.files.value, e.client))

    @property
    def folder(self) -> Path:
        """Where the cell files are saved and listed."""
        return self._folder

    def save_file(self, client: viser.ClientHandle | None = None) -> Future[object]:
        name = str(self.file_name.value)

        def save(c: Controller) -> object:
            try:
                path = save_cell(self._folder, name, read_cell(c))
            except (CellFileError, OSError) as error:
                notify_refusal(client, "Cell not saved", str(error))
                raise
            self.refresh_files(select=path.name.removesuffix(".cell.json"))
            return path

        return self._runner.submit(f"Save cell {name!r}", save, client)

    def load_file(self, name: str, client: viser.ClientHandle | None = None) -> Future[object] | None:
        try:
            cell = load_cell(self._folder, name)
        except CellFileError as error:
            notify_refusal(client, "Cell not loaded", str(error))
            return None
        return self._runner.submit(f"Apply cell {name!r}", lambda c: apply_cell(c, cell), client)

    def refresh_files(self, select: str | None = None) -> None:
        names = list_cells(self._folder) or [NO_FILES]
        if list(self.files.options) != names:
            self.files.options = names
        if select is not None and select in names:
            self.files.value = select
