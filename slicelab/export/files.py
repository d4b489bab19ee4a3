"""Safe file output: every file is written under a temporary name and renamed when whole.

A reader never sees a half-written file, and a failure leaves no file.
"""
from __future__ import annotations

import contextlib
import itertools
import os
from pathlib import Path

__all__ = ["atomic_path", "atomic_open"]

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
