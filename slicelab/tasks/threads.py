"""The same numbers on any number of threads: native thread pools pinned to one thread while a job computes.

A BLAS library that runs a long reduction (a dot product, a matrix product
over a million facets) on several threads splits it into one partial sum
per thread and adds the partial sums at the end: another thread count adds
in another order and rounds otherwise. The vessel profile feeds such sums
through robust reweighting, medians and thresholds, so a change in the last
bit can move a measurement by far more: a batch on Dask (whose nanny sets
``OMP_NUM_THREADS=1`` and ``OPENBLAS_NUM_THREADS=1`` in its workers) and the
same batch on a laptop gave different capacities. `one_thread` runs the
block with every native pool threadpoolctl knows (OpenBLAS, MKL, BLIS,
OpenMP) at one thread, whatever the environment says, so a job gives the
bit-identical result in a terminal, in a local pool and on a cluster. Files
run in parallel as processes (`slicelab.tasks.executors`), not as threads
inside one job, so little is lost.

OpenBLAS built on pthreads (numpy's and SciPy's wheels) has one thread pool
for the whole process, and threadpoolctl lets only one Python thread at a
time set its size (the others are silently ignored). So the limit is held
with a count: when two jobs run on two threads of one process (a Dask worker
with several threads), the first to enter takes the pool over and pins it,
the last to leave restores what was there before, and neither ever computes
unpinned. Pools whose size is set per thread (OpenMP's) are pinned by each
thread for itself.
"""
from __future__ import annotations

import contextlib
import functools
import threading

__all__ = ["one_thread", "pinned", "native_threads"]

_LOCK = threading.Lock()
_held = 0          # blocks inside `one_thread`, over all threads of the process
_shared = None     # threadpoolctl's limiter of the process-wide pools while any block is inside
_pools = None      # threadpoolctl's controller of the pools, made when the first block enters


def _controller():
    """threadpoolctl's view of the native thread pools loaded now.

    SciPy's linear algebra brings its own OpenBLAS, loaded when it is first
    imported: it is imported here first, or a job that loads it later would
    run it unpinned.
    """
    import scipy.linalg  # noqa: F401 - loads SciPy's BLAS, to be pinned with numpy's
    from threadpoolctl import ThreadpoolController
    return ThreadpoolController()


def _let_go() -> None:
    """Let any thread set the process-wide OpenBLAS pool next (threadpoolctl gives it to the first that
    sets it, and ignores the others while that one lives)."""
    import threadpoolctl
    clear = getattr(getattr(threadpoolctl, "OpenBLASController", None), "clear_controlling_thread", None)
    if clear is not None:  # (older threadpoolctl lets every thread set it)
        clear(force=True)


@contextlib.contextmanager
def one_thread():
    """Run the block with every native thread pool (BLAS, OpenMP) at one thread.

    Re-entrant and safe across threads: the process-wide pools stay at one
    thread until the last block inside, in any thread, has left; then their
    sizes are restored.

    See Also
    --------
    pinned : the same for a function.
    native_threads : the thread counts in force.

    Examples
    --------
    >>> with one_thread():
    ...     inside = native_threads()
    >>> set(inside.values())
    {1}
    """
    global _held, _shared, _pools
    with _LOCK:
        if _held == 0:
            _pools = _controller()
            _let_go()
            _shared = _pools.limit(limits=1)
            _let_go()
        _held += 1
        own = _pools.limit(limits=1)  # the pools sized per thread: this thread's (the others are pinned)
    try:
        yield
    finally:
        with _LOCK:
            own.restore_original_limits()
            _held -= 1
            if _held == 0:
                shared, _shared = _shared, None
                _let_go()
                shared.restore_original_limits()
                _let_go()


def pinned(fn):
    """`fn` run inside `one_thread` (a decorator).

    Examples
    --------
    >>> @pinned
    ... def threads():
    ...     return set(native_threads().values())
    >>> threads()
    {1}
    """
    @functools.wraps(fn)
    def run(*args, **kwargs):
        with one_thread():
            return fn(*args, **kwargs)
    return run


def native_threads() -> dict:
    """Each native thread pool loaded in this process (its library file) and its thread count now.

    Examples
    --------
    >>> all(n >= 1 for n in native_threads().values())
    True
    """
    return {f"{x['internal_api']}:{x['filepath']}": x["num_threads"] for x in _controller().info()}
