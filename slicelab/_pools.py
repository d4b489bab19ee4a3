"""slicelab's process pools, made in one place: forked where the platform allows it, else from a fork server.

The print planner, the G-code writer and the layer drawings hand runs of
layers to a pool of forked processes (`process_pool` with no context), each
run's inputs given as arguments; a batch, whose process runs threads (a
progress bar, BLAS), takes its workers from a fork server that imported its
modules once (`forkserver_context`, then `process_pool` with that context). Forking is what
makes a pool cheap here: the workers inherit the modules and the compiled
kernels loaded before the fork instead of loading them again. Three things
keep the forked workers from fighting each other, copying their parent or
outliving it:

- OpenCV's own threads are turned off (the processes already fill the
  cores; its thread pool would only add context switches). It is set before
  the fork, in the parent: calling it in a forked child can deadlock on the
  thread pool the child inherited.
- The garbage collector's tracked objects are frozen before the fork (the
  pattern `gc.freeze` is documented for): the compiled kernels leave
  hundreds of thousands of long-lived objects, which a worker's full
  collection would otherwise walk, touching (and so copying) the pages
  they sit on. The parent unfreezes them when the pool is done.
- Each worker ends when its parent dies (`end_with_parent`). A forked
  worker waits for work on a pipe whose writing end it inherited itself,
  so it never sees the pipe close: without this, killing the parent
  (``kill -9``) would leave the workers blocked for good.

See Also
--------
slicelab.printing.planner.plan, slicelab.gcode.writer.write_gcode : the pool's users.
"""
from __future__ import annotations

import contextlib
import gc
import os
import sys
import threading

__all__ = ["process_pool", "forkserver_context", "start_forkserver", "end_with_parent"]

_PR_SET_PDEATHSIG = 1  # from <linux/prctl.h>


def end_with_parent(parent: int) -> None:
    """End this process when its parent, the process `parent`, dies: a pool worker's initializer.

    On Linux the kernel sends SIGKILL when the parent dies (``prctl(PR_SET_PDEATHSIG)``),
    which also ends a worker stuck in compiled code that never returns to Python.
    Elsewhere, or when that call fails, a daemon thread checks twice a second
    whether the process has been handed to another parent. Either way, a
    parent that died before this call (the process already belongs to another
    parent, init or a subreaper) ends it at once. Only this process is ever
    ended: never its parent, nor whatever adopted it.

    The kernel's signal fires when the *thread* that forked this process
    ends, not the whole parent: the pool's processes must be forked by a
    thread that outlives them (`forked_pool` sees to it).

    Examples
    --------
    >>> import multiprocessing, os
    >>> from concurrent.futures import ProcessPoolExecutor
    >>> with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork"),
    ...                          initializer=end_with_parent, initargs=(os.getpid(),)) as pool:
    ...     pool.submit(os.getppid).result() == os.getpid()
    True
    """
    import signal
    armed = False
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            libc = ctypes.CDLL(None, use_errno=True)
            armed = libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
        except (OSError, AttributeError):  # no prctl in this libc: the thread below watches
            armed = False
    # After arming: a parent that died before it has no death left to signal.
    if os.getppid() != parent:
        os._exit(1)
    if armed:
        return

    def watch():
        import time
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    import threading
    threading.Thread(target=watch, name="slicelab-watch-parent", daemon=True).start()


@contextlib.contextmanager
def process_pool(workers: int, *, context=None, initializer=None, initargs=()):
    """A `ProcessPoolExecutor` of `workers` processes.

    Without a `context`, forked (where the platform has fork): OpenCV single-threaded and the
    collector's objects frozen while it runs, the workers ending if this process dies
    (`end_with_parent`). The workers are forked at once, by the thread that enters the ``with``
    block, which waits for them when it leaves it: the parent-death signal of `end_with_parent`
    follows that thread, so it must outlive them. With a `context` (`forkserver_context`), its
    workers, made ready by `initializer`.

    Examples
    --------
    >>> with process_pool(2) as pool:
    ...     sorted(pool.map(abs, [-2, 1]))
    [1, 2]
    """
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    if context is not None:
        with ProcessPoolExecutor(int(workers), mp_context=context, initializer=initializer,
                                 initargs=tuple(initargs)) as pool:
            yield pool
        return
    import cv2
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    gc.freeze()
    try:
        with ProcessPoolExecutor(int(workers), mp_context=mp.get_context("fork"), initializer=end_with_parent,
                                 initargs=(os.getpid(),)) as pool:
            # With the fork start method the first submit forks every worker, in the calling thread:
            # make that this thread, whatever thread submits the real work.
            pool.submit(int)
            yield pool
    finally:
        gc.unfreeze()
        cv2.setNumThreads(threads)


_ENVIRON = threading.Lock()


def start_forkserver() -> None:
    """Start the fork server, unless it runs, with no current folder on its ``sys.path``.

    It is started as ``python -c``, which puts the current folder first on
    ``sys.path``: run from a folder that holds a ``slicelab/`` (a checkout,
    say), the server would import that one, and every job would fail in its
    workers. PYTHONSAFEPATH (Python 3.11) leaves the folder out; it is set
    only while the server starts, and the workers restore the user's value.
    """
    from multiprocessing import forkserver
    with _ENVIRON:
        before = os.environ.get("PYTHONSAFEPATH")
        os.environ["PYTHONSAFEPATH"] = "1"
        try:
            forkserver.ensure_running()
        finally:
            if before is None:
                del os.environ["PYTHONSAFEPATH"]
            else:
                os.environ["PYTHONSAFEPATH"] = before


def forkserver_context(preload):
    """Worker processes forked from a server that has imported `preload` once (forkserver).

    Not a fork of this process, which may run threads (tqdm, BLAS); not a
    spawn, which would import numpy, scipy and matplotlib again in every
    worker of every run and re-run an unguarded __main__.
    """
    import multiprocessing
    try:
        ctx = multiprocessing.get_context("forkserver")
    except ValueError:  # no forkserver on this platform (Windows)
        return multiprocessing.get_context("spawn")
    ctx.set_forkserver_preload(list(preload))
    start_forkserver()
    return ctx
