"""Run one function over many argument tuples: in this process, on local processes, or on Dask.

Both pools are driven through the same `concurrent.futures` interface (a
`ProcessPoolExecutor`, or a Dask client's executor) by one loop that keeps a
few jobs in flight and hands every result to ``on_done`` in the caller's
thread as it arrives. A job whose worker dies gets ``on_done(job, None,
why)``: a local process that dies breaks its pool, so the jobs it held are
rerun one at a time in fresh processes, and only the one that kills its
process again is lost; a job the cluster loses is reported as lost at once.
The function must be importable by name (a module-level function) and take
everything it needs as arguments.
"""
from __future__ import annotations

import contextlib
import os
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, wait

__all__ = ["run_jobs", "DIED", "LOST", "NoWorkersLeft", "die_with_parent"]

DIED = ("the worker process died while running this job (out of memory? or the pool was started by a "
        "script without an `if __name__ == '__main__':` guard)")
LOST = "the cluster lost this job"
_RAISED = "the job raised in its worker process"
_NO_WORKER_WAIT = 20.0  # seconds a Dask cluster may stay without any worker before the run gives up


class NoWorkersLeft(RuntimeError):
    """The cluster lost every worker: the jobs not yet done cannot run (their reports say so)."""


def die_with_parent(pid: int) -> None:  # pragma: no cover - runs in the worker processes
    """Watch the process `pid` that runs the batch and end this worker soon after it dies.

    The pool's workers are forked from a fork server, not from the batch, so
    the kernel's parent-death signal would watch the wrong process: a daemon
    thread checks twice a second. When the batch has died (killed with
    SIGKILL, say) the worker also ends the fork server that started it, which
    serves that batch alone, so that no process of the batch is left running.
    """
    import signal
    import threading
    import time

    def watch():
        while True:
            time.sleep(0.5)
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                server = os.getppid()
                if server not in (pid, 1):
                    with contextlib.suppress(OSError):
                        os.kill(server, signal.SIGKILL)
                os._exit(1)
            except PermissionError:  # pragma: no cover - a pid reused by another user
                os._exit(1)

    threading.Thread(target=watch, name="slicelab-watch-batch", daemon=True).start()


def run_jobs(fn, jobs, *, workers: int | None = None, scheduler: str | None = None, on_done,
             preload=()) -> None:
    """Call ``fn(*job)`` for every job and ``on_done(job, result, lost)`` as each one finishes.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled by name).
    jobs : sequence of tuple
        The arguments of each call.
    workers : int, optional
        Local processes (default: CPU count); 1, or a single job, runs in this process.
    scheduler : str, optional
        A Dask distributed scheduler's address (``tcp://host:8786``): the jobs run on
        its workers and `workers` is ignored.
    on_done : callable
        ``on_done(job, result, lost)``: `lost` is None, or why the job has no result
        (`DIED`, `LOST`: its worker went away).
    preload : sequence of str
        Modules the local worker processes import once, before they are forked.

    Examples
    --------
    >>> done = []
    >>> run_jobs(pow, [(2, 3), (3, 2)], workers=1, on_done=lambda job, r, lost: done.append(r))
    >>> done
    [8, 9]
    """
    jobs = list(jobs)
    if not jobs:
        return
    if scheduler:
        _run_dask(fn, jobs, scheduler, on_done)
    elif (workers or os.cpu_count() or 1) <= 1 or len(jobs) == 1:
        for job in jobs:  # in this process: simplest to debug, no start-up cost
            on_done(job, fn(*job), None)
    else:
        _run_local(fn, jobs, min(int(workers or os.cpu_count() or 1), len(jobs)), on_done, preload)


def _drain(executor, fn, queue: list, limit: int, on_done, lost: str, alive=None) -> list:
    """Submit from the end of `queue`, at most `limit` in flight, until all are done.

    A job that raises is reported lost. Returns the jobs in flight when the
    executor broke (a local worker died), for the caller to retry. `alive`,
    when given, is asked every few seconds while nothing finishes; when it
    answers False the run stops with `NoWorkersLeft`, after reporting every
    job not done as lost.
    """
    running = {}
    try:
        while queue or running:
            while queue and len(running) < limit:
                job = queue.pop()
                try:
                    running[executor.submit(fn, *job)] = job
                except BrokenExecutor:
                    queue.append(job)  # never submitted: it goes to the next executor, not astray
                    raise
            done, _ = wait(running, timeout=None if alive is None else 2.0, return_when=FIRST_COMPLETED)
            if not done and alive is not None and not alive():
                left = list(running.values()) + queue[::-1]
                for job in left:  # every job not done gets its report, then the run stops
                    on_done(job, None, f"{lost}: the cluster has no worker left")
                queue.clear()
                raise NoWorkersLeft(f"the Dask cluster has no worker left; {len(left)} jobs were not run "
                                    f"(their reports say so; rerun the batch to finish them)")
            for fut in done:
                try:
                    result = fut.result()
                except BrokenExecutor:
                    raise
                except Exception as exc:  # noqa: BLE001 - a lost job is reported, the others go on
                    on_done(running.pop(fut), None, f"{lost}: {type(exc).__name__}: {exc}")
                    continue
                on_done(running.pop(fut), result, None)
    except BrokenExecutor:
        return list(running.values())
    return []


def _pool_context(preload):
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
    return ctx


def _run_local(fn, jobs, workers: int, on_done, preload) -> None:
    """A process pool; a crash costs only the job that caused it."""
    from concurrent.futures import ProcessPoolExecutor
    ctx = _pool_context(preload)
    queue = list(reversed(jobs))
    suspects = []
    while queue:
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=die_with_parent,
                                 initargs=(os.getpid(),)) as pool:
            # A short queue (twice the workers): a crash sends few jobs to the retry.
            suspects += _drain(pool, fn, queue, 2 * workers, on_done, _RAISED)
    for job in suspects:  # one at a time, in a fresh process each
        with ProcessPoolExecutor(max_workers=1, mp_context=ctx, initializer=die_with_parent,
                                 initargs=(os.getpid(),)) as pool:
            if _drain(pool, fn, [job], 1, on_done, _RAISED):
                on_done(job, None, DIED)


def _run_dask(fn, jobs, scheduler: str, on_done) -> None:
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("a Dask scheduler needs Dask: pip install 'slicelab[cluster]'") from None
    import time
    client = Client(scheduler, timeout="30s", set_as_default=False)
    empty_since = [None]

    def alive() -> bool:
        # A cluster may lose its workers and get new ones: give up only after a while with none.
        if client.scheduler_info().get("workers"):
            empty_since[0] = None
            return True
        empty_since[0] = empty_since[0] or time.monotonic()
        return time.monotonic() - empty_since[0] < _NO_WORKER_WAIT

    try:
        executor = client.get_executor(pure=False)
        _drain(executor, fn, list(reversed(jobs)), len(jobs), on_done, LOST, alive=alive)
    finally:
        client.close()
