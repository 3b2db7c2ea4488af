"""The programs folder as a git repository (dulwich: pure Python, no git binary): every save a commit.

The folder is the repository's root: one the user made is used as it is (its hooks are not run), any other
folder becomes one on its first save, with a .gitignore for the autosave and the programs already there as
its first commit. A commit holds only the file it is about (the user's other staged work stays staged),
and nothing is ever rewritten: a restore is a new commit, so every version stays reachable.
"""

from __future__ import annotations

import contextlib
import socket
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

from dulwich.errors import NotGitRepository
from dulwich.objects import Blob, Commit, Tree
from dulwich.objectspec import AmbiguousShortId, parse_commit
from dulwich.refs import Ref
from dulwich.repo import Repo

MAX_VERSIONS = 1000  # listed per program: the newest ones (older commits stay in the repository)
MAX_MESSAGE_LINES = 200  # of a commit message's body
WHO_MAX = 120  # characters of an author's name
GITIGNORE = ".gitignore"
# The autosave, its refused copies and atomic_write's temporary files are never versions.
IGNORED = (".autosave*.json", ".*.tmp")
COMMITTER = "PULSE pendant"
OUTSIDE = "outside the pendant"  # who changed a file the pendant did not write
# Files git leaves while a merge, rebase, cherry-pick or another git command is under way.
_UNFINISHED = {
    "MERGE_HEAD": "a merge",
    "rebase-merge": "a rebase",
    "rebase-apply": "a rebase",
    "CHERRY_PICK_HEAD": "a cherry-pick",
    "REVERT_HEAD": "a revert",
    "index.lock": "another git command (or one that crashed: remove .git/index.lock)",
}


class HistoryError(Exception):
    """The history could not be read or written; `str()` says why and what to do."""


@dataclass(frozen=True)
class Version:
    """One commit that changed a program file."""

    commit: str  # the full hex id
    time: datetime  # UTC
    who: str  # the author's name: "browser #2 (10.0.0.7)", "alice (pendant CLI)", "outside the pendant"
    summary: str  # the message's first line
    deleted: bool = False  # this commit deleted the file

    @property
    def short(self) -> str:
        return self.commit[:7]


def _identity(name: str) -> bytes:
    """`name <pendant@host>` with what git forbids in a name (<, >, newlines) taken out."""
    clean = " ".join(name.replace("<", "(").replace(">", ")").split())[:WHO_MAX] or "unknown"
    host = "".join(c for c in socket.gethostname() if c.isalnum() or c in ".-") or "localhost"
    return f"{clean} <pendant@{host}>".encode()


class ProgramHistory:
    """The git history of one programs folder. Opened lazily: a folder with no repository has no versions
    until its first recorded change."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder

    @property
    def exists(self) -> bool:
        return (self.folder / ".git").exists()

    # --- reading --------------------------------------------------------------------------------------
    def _open(self) -> Repo:
        try:
            return Repo(str(self.folder))
        except NotGitRepository as error:
            raise HistoryError(
                f"{self.folder}/.git is not a usable git repository ({error}): "
                "repair it, or move it away to start a new history"
            ) from error
        except Exception as error:  # a damaged .git: dulwich's own errors, OSError, ValueError
            raise HistoryError(f"The history in {self.folder}/.git cannot be read: {error}") from error

    def _head(self, repo: Repo) -> Commit | None:
        try:
            head = repo.refs[Ref(b"HEAD")]
        except KeyError:
            return None  # a new repository: no commit yet
        try:
            commit = repo[head]
        except KeyError as error:
            raise HistoryError(
                f"The history in {self.folder}/.git is damaged: HEAD names commit {head.decode()}, "
                "which is missing (try `git fsck`)"
            ) from error
        assert isinstance(commit, Commit)
        return commit

    @contextlib.contextmanager
    def _reading(self) -> Iterator[Repo]:
        """The repository, open for the block; whatever a damaged one raises (a commit cut short, an object
        that does not parse) comes out as a HistoryError that says so."""
        repo = self._open()
        try:
            yield repo
        except HistoryError:
            raise
        except Exception as error:
            raise HistoryError(
                f"The history in {self.folder}/.git is damaged ({type(error).__name__}: {_one_line(error)}; "
                "try `git fsck`)"
            ) from error
        finally:
            repo.close()

    def committed_bytes(self, file_name: str) -> bytes | None:
        """The file as the newest commit holds it; None when it is not in the history (or there is none)."""
        if not self.exists:
            return None
        with self._reading() as repo:
            head = self._head(repo)
            return None if head is None else _blob_in(repo, head, file_name)

    def versions(self, file_name: str, limit: int = MAX_VERSIONS) -> list[Version]:
        """The commits that changed `file_name`, newest first, at most `limit` of them."""
        if not self.exists:
            return []
        with self._reading() as repo:
            if self._head(repo) is None:
                return []
            found: list[Version] = []
            try:
                for entry in repo.get_walker(paths=[file_name.encode()], max_entries=limit):
                    commit = entry.commit
                    found.append(_version(commit, _blob_in(repo, commit, file_name) is None))
            except KeyError as error:
                raise HistoryError(
                    f"The history in {self.folder}/.git is damaged (object {error} is missing; "
                    "try `git fsck`): it lists the versions it can read"
                ) from error
            return found

    def read(self, file_name: str, revision: str) -> tuple[Version, bytes]:
        """The version `revision` (a commit id or its first 4+ hex digits) of `file_name` and its bytes."""
        if not self.exists:
            raise HistoryError(f"{self.folder} has no history yet")
        with self._reading() as repo:
            commit = _resolve(repo, revision)
            data = _blob_in(repo, commit, file_name)
            if data is None:
                raise HistoryError(f"{file_name} is not in version {revision}")
            return _version(commit, False), data

    # --- writing --------------------------------------------------------------------------------------
    def record(self, file_name: str, message: str, who: str) -> str | None:
        """Commit the file as it is now in the folder (deleted if it is gone); returns the commit id, or
        None when it is already in the history as it is. HistoryError if the repository refuses."""
        repo = self._open_or_create(file_name)
        try:
            return self._commit(repo, file_name, message, who)
        except HistoryError:
            raise
        except Exception as error:  # whatever dulwich meets (locks, damaged objects): the save stands, said
            raise HistoryError(
                f"The history in {self.folder}/.git could not be written ({type(error).__name__}: "
                f"{_one_line(error)}; try `git fsck`)"
            ) from error
        finally:
            repo.close()

    def _open_or_create(self, recording: str) -> Repo:
        if self.exists:
            repo = self._open()
            unfinished = [
                what for name, what in _UNFINISHED.items() if (Path(repo.controldir()) / name).exists()
            ]
            if unfinished:
                repo.close()
                raise HistoryError(
                    f"The git repository in {self.folder} is in the middle of {unfinished[0]}: "
                    "finish or abort it with git, then save again"
                )
            return repo
        try:
            repo = Repo.init(str(self.folder))
            self._first_commit(repo, recording)
        except Exception as error:
            raise HistoryError(f"A history could not be started in {self.folder}: {error}") from error
        return repo

    def _first_commit(self, repo: Repo, recording: str) -> None:
        """The .gitignore and every program already in the folder but `recording` (its own commit follows),
        so the history starts with them."""
        ignore = self.folder / GITIGNORE
        if not ignore.exists():
            ignore.write_text(
                "# Not versions: the pendant's autosave and its temporary files\n" + "\n".join(IGNORED) + "\n"
            )
        programs = (p.name for p in self.folder.iterdir() if p.is_file() and p.suffix == ".json")
        names = [GITIGNORE, *sorted(n for n in programs if not n.startswith(".") and n != recording)]
        tree = Tree()
        for name in names:
            blob = Blob.from_string((self.folder / name).read_bytes())
            repo.object_store.add_object(blob)
            tree.add(name.encode(), 0o100644, blob.id)
        repo.object_store.add_object(tree)
        count = len(names) - 1
        message = (
            f"Start the history of this programs folder ({count} program{'s' if count != 1 else ''} in it)"
        )
        self._write_commit(repo, tree, message, COMMITTER, None)
        repo.get_worktree().stage(names)

    def _commit(self, repo: Repo, file_name: str, message: str, who: str) -> str | None:
        head = self._head(repo)
        tree = Tree()
        if head is not None:
            head_tree = repo[head.tree]
            assert isinstance(head_tree, Tree)
            for entry in head_tree.items():
                tree.add(entry.path, entry.mode, entry.sha)
        path = self.folder / file_name
        key = file_name.encode()
        if path.exists():
            blob = Blob.from_string(path.read_bytes())
            repo.object_store.add_object(blob)
            tree.add(key, 0o100644, blob.id)
        elif key in tree:
            del tree[key]
        if head is not None and tree.id == head.tree:
            return None  # nothing changed
        repo.object_store.add_object(tree)
        commit = self._write_commit(repo, tree, message, who, head)
        repo.get_worktree().stage([file_name])  # the index agrees: `git status` shows nothing to commit
        return commit

    def _write_commit(self, repo: Repo, tree: Tree, message: str, who: str, parent: Commit | None) -> str:
        lines = message.strip().splitlines()
        text = "\n".join(lines[: MAX_MESSAGE_LINES + 1]) + "\n"
        commit_id = repo.get_worktree().commit(
            message=text.encode(),
            author=_identity(who),
            committer=_identity(COMMITTER),
            tree=tree.id,
            merge_heads=[],
            no_verify=True,  # a user's hooks are theirs to run, not the pendant's at every save
        )
        return commit_id.decode()


def _one_line(error: BaseException, limit: int = 200) -> str:
    """An error's text on one line, cut to `limit` characters (dulwich may quote whole objects)."""
    text = " ".join(str(error).split()) or type(error).__name__
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _blob_in(repo: Repo, commit: Commit, file_name: str) -> bytes | None:
    tree = repo[commit.tree]
    assert isinstance(tree, Tree)
    key = file_name.encode()
    if key not in tree:
        return None
    _, sha = tree[key]
    blob = repo[sha]
    assert isinstance(blob, Blob)
    return blob.as_raw_string()


def _version(commit: Commit, deleted: bool) -> Version:
    name = commit.author.decode(errors="replace").rsplit(" <", 1)[0]
    summary = commit.message.decode(errors="replace").strip().split("\n", 1)[0]
    return Version(
        commit=commit.id.decode(),
        time=datetime.fromtimestamp(commit.author_time, UTC),
        who=name,
        summary=summary,
        deleted=deleted,
    )


def _resolve(repo: Repo, revision: str) -> Commit:
    """A commit id (4+ hex digits), a branch or tag name, or git's HEAD~N forms."""
    try:
        return parse_commit(repo, revision.strip())
    except AmbiguousShortId as error:
        raise HistoryError(f"{revision!r} names more than one version: give more of its digits") from error
    except (KeyError, ValueError) as error:
        raise HistoryError(f"No version {revision!r} in the history") from error
