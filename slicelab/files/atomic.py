"""Safe file output: every file is written under a temporary name and renamed when whole.

A reader never sees a half-written file, and a failure leaves no file. The
files a command writes into a folder are one set (`StagedFolder`): staged,
moved in together, and the earlier run's leftovers removed; an output that
is the input is refused (`same_file`).
"""
from __future__ import annotations

import contextlib
import itertools
import os
from pathlib import Path

__all__ = ["atomic_path", "atomic_open", "same_file", "StagedFolder"]

#: Serial numbers of the temporary files this process makes (with its pid, a name no other
#: writer takes; `next` on a count is atomic, so threads may share it).
_SERIAL = itertools.count()


def _temporary(target: Path) -> tuple[Path, int]:
    """A new file beside `target`, made exclusively (never one another writer made), and its
    descriptor: created with the mode an ordinary ``open`` gives (0666 less the umask).

    A name of this process's own and one ``os.open``, not `tempfile.mkstemp` (a random name, a
    0600 file to chmod, the umask read by setting it twice): a plan's preview writes a file
    per layer, and this costs a third of mkstemp's way.
    """
    while True:  # (a name left over by an earlier process of the same pid is stepped over)
        tmp = target.with_name(f".{target.name}.{os.getpid()}.{next(_SERIAL)}.part")
        try:
            return tmp, os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
        except FileExistsError:
            continue


@contextlib.contextmanager
def _replacing(target, mode: str | None = None, **kwargs):
    """A temporary file beside `target` (its path, or with `mode` the open file), renamed over
    `target` when the block ends cleanly and removed when it fails."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp, fd = _temporary(target)
    try:
        if mode is None:
            os.close(fd)
            yield tmp
        else:
            with open(fd, mode, **kwargs) as fh:
                yield fh
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside `path`; rename it over `path` on success.

    A reader never sees a half-written file, and a failure leaves no file.

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> with atomic_path(os.path.join(d, "x.txt")) as tmp:
    ...     _ = open(tmp, "w").write("whole")
    >>> open(os.path.join(d, "x.txt")).read()
    'whole'
    """
    with _replacing(path) as tmp:
        yield tmp


@contextlib.contextmanager
def atomic_open(path, mode: str = "w", **kwargs):
    """Open a temporary file beside `path` and rename it over `path` when closed cleanly.

    Examples
    --------
    >>> import tempfile, os
    >>> target = os.path.join(tempfile.mkdtemp(), "y.txt")
    >>> with atomic_open(target) as fh:
    ...     _ = fh.write("ok")
    >>> open(target).read()
    'ok'
    """
    if not any(c in mode for c in "wx"):
        raise ValueError(f"atomic_open writes a new file: mode {mode!r} is not a writing mode ('w', 'wb')")
    with _replacing(path, mode.replace("x", "w"), **kwargs) as fh:
        yield fh


def same_file(a, b) -> bool:
    """Whether paths `a` and `b` name one file (through links too; a path that does not exist yet
    is compared by its resolved name).

    Examples
    --------
    >>> import tempfile, os
    >>> d = tempfile.mkdtemp(); f = os.path.join(d, "part.stl"); _ = open(f, "w").write("x")
    >>> os.symlink(f, os.path.join(d, "link.stl"))
    >>> same_file(f, os.path.join(d, "link.stl")), same_file(f, os.path.join(d, "other.stl"))
    (True, False)
    """
    a, b = Path(a), Path(b)
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet)
        return a.resolve() == b.resolve()


class StagedFolder:
    """The files one command writes into a folder, as one set.

    Every file goes first into a hidden staging folder inside `folder`
    (``staging``); `commit` moves each into place (a rename, so a reader sees
    a file whole or not at all), removes the files that an earlier run of the
    same command listed in its manifest (``.slicelab-COMMAND.json``) and this
    run did not write, and writes the new manifest; other files in the folder
    are never touched. `discard` removes the staging folder and leaves
    `folder` as it was. A file in `keep` (the input) is never overwritten or
    removed: `commit` refuses instead.

    Parameters
    ----------
    folder : path
    command : str
        Names the manifest, so that two commands writing into one folder keep their own sets.
    keep : sequence of path
        Files that must survive (the input).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> for names in (["a.txt", "b.txt"], ["a.txt"]):   # a rerun that writes fewer files
    ...     run = StagedFolder(out, "demo")
    ...     for n in names:
    ...         _ = (run.staging / n).write_text(n)
    ...     _ = run.commit()
    >>> sorted(p.name for p in out.iterdir())
    ['.slicelab-demo.json', 'a.txt']
    """

    def __init__(self, folder, command: str, keep=()):
        self.folder = Path(folder)
        self.command = command
        self.keep = [Path(k) for k in keep]
        self.folder.mkdir(parents=True, exist_ok=True)
        while True:
            self.staging = self.folder / f".slicelab-{command}.{os.getpid()}.{next(_SERIAL)}.staging"
            try:
                self.staging.mkdir()
                break
            except FileExistsError:
                continue

    @property
    def manifest(self) -> Path:
        """The file listing what the last run of this command wrote here."""
        return self.folder / f".slicelab-{self.command}.json"

    def _listed(self) -> list[str]:
        import json
        try:
            names = json.loads(self.manifest.read_text(encoding="utf-8")).get("files", [])
        except (OSError, ValueError, AttributeError):
            return []
        # Only plain relative names below the folder: a manifest is data, never a licence to
        # remove anything elsewhere.
        return [n for n in names if isinstance(n, str) and n and not Path(n).is_absolute()
                and ".." not in Path(n).parts]

    def commit(self) -> dict:
        """Move the staged files into the folder; return {staged path: final path}."""
        import json
        import shutil
        staged = sorted(p for p in self.staging.rglob("*") if p.is_file())
        names = [p.relative_to(self.staging).as_posix() for p in staged]
        finals = [self.folder / n for n in names]
        for f in finals:
            if any(same_file(f, k) for k in self.keep):
                self.discard()
                raise ValueError(f"{f}: is the input file; write the outputs to another folder")
            if f.is_dir():
                self.discard()
                raise ValueError(f"{f}: a folder is in the way of an output file")
        old = [n for n in self._listed() if n not in set(names)]
        # The manifest first lists both sets: an interruption leaves no file unaccounted for.
        with atomic_open(self.manifest, "w", encoding="utf-8") as fh:
            json.dump({"command": self.command, "files": sorted(set(names) | set(old))}, fh)
        moved = {}
        for src, dst in zip(staged, finals):  # over files
            dst.parent.mkdir(parents=True, exist_ok=True)
            os.replace(src, dst)
            moved[src] = dst
        for n in old:  # files of the earlier run that this one did not write
            stale = self.folder / n
            if stale.is_file() and not any(same_file(stale, k) for k in self.keep):
                with contextlib.suppress(OSError):
                    stale.unlink()
        with atomic_open(self.manifest, "w", encoding="utf-8") as fh:
            json.dump({"command": self.command, "files": names}, fh)
        shutil.rmtree(self.staging, ignore_errors=True)
        return moved

    def discard(self) -> None:
        """Remove the staging folder and everything in it; the folder is left as it was."""
        import shutil
        shutil.rmtree(self.staging, ignore_errors=True)
