"""The process pool that plans layers and formats G-code: forked, one thread each, the collector frozen.

Both the print planner and the G-code writer hand runs of layers to a pool
of forked processes, each run's inputs given as arguments. Forking is what
makes a pool cheap here: the workers inherit the modules and the compiled
kernels loaded before the fork instead of loading them again. Two things
keep the forked workers from fighting each other or copying their parent:

- OpenCV's own threads are turned off (the processes already fill the
  cores; its thread pool would only add context switches). It is set before
  the fork, in the parent: calling it in a forked child can deadlock on the
  thread pool the child inherited.
- The garbage collector's tracked objects are frozen before the fork (the
  pattern `gc.freeze` is documented for): the compiled kernels leave
  hundreds of thousands of long-lived objects, which a worker's full
  collection would otherwise walk, touching (and so copying) the pages
  they sit on. The parent unfreezes them when the pool is done.

See Also
--------
slicelab.toolpath.planner.plan, slicelab.export.gcode.write_gcode : the pool's users.
"""
from __future__ import annotations

import contextlib
import gc

__all__ = ["forked_pool"]


@contextlib.contextmanager
def forked_pool(workers: int):
    """A `ProcessPoolExecutor` of `workers` forked processes, OpenCV single-threaded and the
    collector's objects frozen while it runs.

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
        with ProcessPoolExecutor(int(workers), mp_context=mp.get_context("fork")) as pool:
            yield pool
    finally:
        gc.unfreeze()
        cv2.setNumThreads(threads)
