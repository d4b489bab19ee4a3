"""The process pool that plans layers and formats G-code: forked, one thread each, the collector frozen.

Both the print planner and the G-code writer hand runs of layers to a pool
of forked processes, each run's inputs given as arguments. Forking is what
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

__all__ = ["forked_pool", "end_with_parent"]

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
def forked_pool(workers: int):
    """A `ProcessPoolExecutor` of `workers` forked processes, OpenCV single-threaded and the
    collector's objects frozen while it runs; the workers end if this process dies.

    The workers are forked at once, by the thread that enters the ``with``
    block, which waits for them when it leaves it: the parent-death signal of
    `end_with_parent` follows that thread, so it must outlive them.

    Examples
    --------
    >>> with forked_pool(2) as pool:
    ...     sorted(pool.map(abs, [-2, 1]))
    [1, 2]
    """
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

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
