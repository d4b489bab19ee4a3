"""Run one function over many argument tuples: in this process, on local processes, or on Dask.

Both pools are driven through the same `concurrent.futures` interface (a
`ProcessPoolExecutor`, or futures of a Dask client) by one loop that keeps a
few jobs in flight and hands every result to ``on_done`` in the caller's
thread as it arrives. A job whose worker dies gets ``on_done(job, None,
why)``: a local process that dies breaks its pool, so the jobs it held are
rerun one at a time in fresh processes, and only the one that kills its
process again is lost; a job the cluster loses is reported as lost at once.
A job that runs past the time limit is stopped and gets a `TimedOut` reason.
The function must be importable by name (a module-level function) and take
everything it needs as arguments.
"""
from __future__ import annotations

import contextlib
import itertools
import os
import struct
import threading
import time
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, Future, wait

__all__ = ["run_jobs", "DIED", "LOST", "TimedOut", "NoWorkersLeft", "die_with_parent"]

DIED = ("the worker process died while running this job (out of memory? or the pool was started by a "
        "script without an `if __name__ == '__main__':` guard)")
LOST = "the cluster lost this job"
_RAISED = "the job raised in its worker process"
_NO_WORKER_WAIT = 20.0  # seconds a Dask cluster may stay without any worker before the run gives up
_TICK = 0.2  # seconds between looks at the running jobs' clocks, when there is a time limit
_START = struct.Struct("=qqd")  # a worker's word that it starts a job: job key, its pid, time.monotonic()


class NoWorkersLeft(RuntimeError):
    """The cluster lost every worker: the jobs not yet done cannot run (their reports say so)."""


class TimedOut(str):
    """Why a job has no result when it ran past the time limit: a `str`, as every `lost` reason."""


def die_with_parent(pid: int) -> None:  # pragma: no cover - runs in the worker processes
    """End this worker soon after the process `pid` that runs the batch dies.

    The pool's workers are forked from a fork server, not from the batch. The
    fork server exits when the batch dies (the worker lets go of what would
    keep it running, `_let_go_of_forkserver`), and the kernel's parent-death
    signal (`slicelab._pools.end_with_parent`) then ends the worker,
    even one stuck in compiled code. A daemon thread also checks the batch
    twice a second, for systems without that signal: once the batch has
    died, the worker ends the fork server that started it (which serves that
    batch alone) if that is still its parent, and then itself. A worker the
    fork server has already left belongs to init or a subreaper: that one
    is never touched.
    """
    import signal

    from .._pools import end_with_parent
    server = os.getppid()  # the fork server; with the spawn start method, the batch itself
    if server != pid:
        _let_go_of_forkserver()
    end_with_parent(server)

    def watch():
        while True:
            time.sleep(0.5)
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                # Still this worker's parent, so still the fork server (an orphan is re-parented).
                if server != pid and os.getppid() == server:
                    with contextlib.suppress(OSError):
                        os.kill(server, signal.SIGKILL)
                os._exit(1)
            except PermissionError:  # pragma: no cover - a pid reused by another user
                os._exit(1)

    threading.Thread(target=watch, name="slicelab-watch-batch", daemon=True).start()


def _let_go_of_forkserver() -> None:  # pragma: no cover - runs in the worker processes
    """Close this worker's end of the fork server's "alive" pipe, so that the server exits with the batch.

    The server runs until every process holding the writing end of that pipe
    has ended, and it hands one to each worker it forks: a worker stuck in
    compiled code (whose watching thread never runs) would keep the server
    alive, and the server, through the parent-death signal, the worker. A
    worker forks nothing through the server, so it does not need that end.
    """
    from multiprocessing import forkserver
    server = getattr(forkserver, "_forkserver", None)
    fd = getattr(server, "_forkserver_alive_fd", None)
    if isinstance(fd, int):
        with contextlib.suppress(OSError):
            os.close(fd)
        server._forkserver_alive_fd = None


_STARTS = None  # in a local worker: the writing end of the pipe on which it says which job it starts


def _worker_init(pid: int, starts, safepath) -> None:  # pragma: no cover - runs in the worker processes
    """A local worker's set-up: the environment as the user had it, the pipe to the client, `die_with_parent`."""
    global _STARTS
    _STARTS = starts
    # The fork server was started with PYTHONSAFEPATH=1 (`slicelab._pools.start_forkserver`): not the user's setting.
    if safepath is None:
        os.environ.pop("PYTHONSAFEPATH", None)
    else:
        os.environ["PYTHONSAFEPATH"] = safepath
    die_with_parent(pid)


def _timed(key, fn, *args):
    """``fn(*args)`` and the seconds it took; first, the worker tells the client that job `key` starts."""
    if isinstance(key, tuple):  # on a Dask worker: (topic, job) as an event, through the scheduler
        from distributed import get_worker
        with contextlib.suppress(ValueError):  # not in a Dask worker after all: nobody is timing the job
            get_worker().log_event(*key)
    elif key is not None and _STARTS is not None:
        with contextlib.suppress(OSError):  # one small write: atomic on a pipe, so no lock between workers
            _STARTS.send_bytes(_START.pack(key, os.getpid(), time.monotonic()))
    t0 = time.monotonic()
    result = fn(*args)
    return time.monotonic() - t0, result


def run_jobs(fn, jobs, *, workers: int | None = None, scheduler: str | None = None, on_done,
             preload=(), timeout: float | None = None) -> None:
    """Call ``fn(*job)`` for every job and ``on_done(job, result, lost)`` as each one finishes.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled by name).
    jobs : sequence of tuple
        The arguments of each call.
    workers : int, optional
        Local processes (default: CPU count); 1, or a single job, runs in this
        process, unless there is a `timeout`.
    scheduler : str, optional
        A Dask distributed scheduler's address (``tcp://host:8786``): the jobs run on
        its workers and `workers` is ignored.
    on_done : callable
        ``on_done(job, result, lost)``: `lost` is None, or why the job has no result
        (`DIED`, `LOST`: its worker went away; a `TimedOut`: it ran too long).
    preload : sequence of str
        Modules the local worker processes import once, before they are forked.
    timeout : float, optional
        Seconds a job may run, timed from when a worker starts it. A local
        job past it has its worker process killed (a job stuck in compiled
        code never comes back to Python, where a signal could stop it); the
        jobs that were running beside it start again in a fresh pool. So
        jobs always run in worker processes then, even with one worker. On
        Dask the job is cancelled, but a Dask worker cannot stop a task it
        has started: it may go on running it to its end, holding one of its
        threads. A job that ends past the limit before it is stopped is
        timed out too. None: no limit.

    Examples
    --------
    >>> done = []
    >>> run_jobs(pow, [(2, 3), (3, 2)], workers=1, on_done=lambda job, r, lost: done.append(r))
    >>> done
    [8, 9]
    >>> import time
    >>> run_jobs(time.sleep, [(60,)], timeout=0.5, on_done=lambda job, r, lost: print(type(lost).__name__))
    TimedOut
    """
    jobs = list(jobs)
    if not jobs:
        return
    if timeout is not None and not timeout > 0:
        raise ValueError(f"timeout must be a positive number of seconds, not {timeout!r}")
    if scheduler:
        _run_dask(fn, jobs, scheduler, on_done, timeout)
    elif timeout is None and ((workers or os.cpu_count() or 1) <= 1 or len(jobs) == 1):
        for job in jobs:  # in this process: simplest to debug, no start-up cost
            on_done(job, fn(*job), None)
    else:
        _run_local(fn, jobs, max(1, min(int(workers or os.cpu_count() or 1), len(jobs))), on_done, preload,
                   timeout)


class _Clock:
    """The time limit of the jobs in flight: when each one started, which ran too long, how to stop one.

    Each job is known to its worker by a number (`_timed`), through which the
    worker says when it starts it.
    """

    def __init__(self, timeout: float):
        self.timeout = timeout
        self.started: dict = {}  # future -> time.monotonic() when a worker took it
        self.keys, self.key_of, self.serial = {}, {}, itertools.count()  # number <-> future

    def submit(self, executor, fn, job):
        key = next(self.serial)
        fut = executor.submit(_timed, self.word(key), fn, *job)
        self.keys[key], self.key_of[fut] = fut, key
        return fut

    def word(self, key: int):
        """What `_timed` gets to say that job `key` starts."""
        return key

    def poll(self) -> None:
        """Learn which jobs have started."""

    def overdue(self, running) -> list:
        self.poll()
        now = time.monotonic()
        return [f for f in running if f in self.started and now - self.started[f] > self.timeout
                and not f.done()]

    def stop(self, fut) -> tuple[TimedOut, bool]:
        """Stop the job of `fut`: why, and whether stopping it broke the pool."""
        raise NotImplementedError

    def forget(self, fut) -> None:
        """Done with `fut`: not kept (nor its result) for the rest of the run."""
        self.started.pop(fut, None)
        self.keys.pop(self.key_of.pop(fut, None), None)

    def late(self, seconds: float) -> TimedOut:
        return TimedOut(f"took {seconds:.3g} s, past the time limit of {self.timeout:g} s: its result was "
                        f"set aside")


class _LocalClock(_Clock):
    """Start times from the workers' own words on a pipe; a job is stopped by killing its process."""

    def __init__(self, timeout: float, reader):
        super().__init__(timeout)
        self.reader, self.pids, self.current = reader, {}, {}  # future -> pid, pid -> its latest job

    def poll(self) -> None:
        while self.reader.poll():
            key, pid, t = _START.unpack(self.reader.recv_bytes())
            self.current[pid] = key
            fut = self.keys.get(key)
            if fut is not None:  # (else done with already: its word came after its result)
                self.started[fut], self.pids[fut] = t, pid  # the same clock: one machine

    def overdue(self, running) -> list:
        # A job whose process has started another one since has ended: its result is on its way.
        return [f for f in super().overdue(running) if self.current[self.pids[f]] == self.key_of[f]]

    def stop(self, fut) -> tuple[TimedOut, bool]:
        import signal
        with contextlib.suppress(OSError):
            os.kill(self.pids[fut], getattr(signal, "SIGKILL", signal.SIGTERM))
        return TimedOut(f"still running after {self.timeout:g} s, the time limit: its worker process was "
                        f"killed"), True

    def forget(self, fut) -> None:
        super().forget(fut)
        self.pids.pop(fut, None)


def _drain(executor, fn, queue: list, limit: int, on_done, lost: str, alive=None, clock=None):
    """Submit from the end of `queue`, at most `limit` in flight, until all are done.

    A job that raises is reported lost; with a `clock`, a job that runs too
    long is stopped and reported. Returns the jobs in flight when the
    executor broke (a local worker died, or was killed to stop a job), for
    the caller to retry, and whether a job was stopped. `alive`, when given,
    is asked every few seconds while nothing finishes; when it answers False
    the run stops with `NoWorkersLeft`, after reporting every job not done as
    lost.
    """
    running, stopped, asked = {}, False, time.monotonic()
    while queue or running:
        while queue and len(running) < limit:
            job = queue.pop()
            try:
                fut = executor.submit(fn, *job) if clock is None else clock.submit(executor, fn, job)
            except BrokenExecutor:
                queue.append(job)  # never submitted: it goes to the next executor, not astray
                return list(running.values()), stopped
            running[fut] = job
        tick = None if alive is None else 2.0
        if clock is not None:
            tick = min(tick or _TICK, _TICK)
        done, _ = wait(running, timeout=tick, return_when=FIRST_COMPLETED)
        broken = False
        for fut in done:
            if clock is not None:
                clock.forget(fut)
            try:
                result = fut.result()
            except BrokenExecutor:
                broken = True  # the job stays in `running`: it goes back to the caller
                continue
            except Exception as exc:  # noqa: BLE001 - a lost job is reported, the others go on
                on_done(running.pop(fut), None, f"{lost}: {type(exc).__name__}: {exc}")
                continue
            job = running.pop(fut)
            if clock is not None:
                seconds, result = result
                if seconds > clock.timeout:
                    on_done(job, None, clock.late(seconds))
                    continue
            on_done(job, result, None)
        if broken:
            return list(running.values()), stopped
        if clock is not None:
            for fut in clock.overdue(running):
                why, breaks = clock.stop(fut)
                clock.forget(fut)
                stopped |= breaks
                on_done(running.pop(fut), None, why)
        if alive is not None and running and not done and time.monotonic() - asked >= 2.0:
            asked = time.monotonic()
            if not alive():
                left = list(running.values()) + queue[::-1]
                for job in left:  # every job not done gets its report, then the run stops
                    on_done(job, None, f"{lost}: the cluster has no worker left")
                queue.clear()
                raise NoWorkersLeft(f"the Dask cluster has no worker left; {len(left)} jobs were not run "
                                    f"(their reports say so; rerun the batch to finish them)")
    return [], stopped


@contextlib.contextmanager
def _local_pool(ctx, workers: int, timeout: float | None):
    """A process pool, and the clock of its jobs when they have a time limit."""
    from .._pools import process_pool
    reader, writer = ctx.Pipe(duplex=False) if timeout is not None else (None, None)
    try:
        with process_pool(workers, context=ctx, initializer=_worker_init,
                          initargs=(os.getpid(), writer, os.environ.get("PYTHONSAFEPATH"))) as pool:
            yield pool, (None if timeout is None else _LocalClock(timeout, reader))
    finally:
        for end in (reader, writer):
            if end is not None:
                end.close()


def _run_local(fn, jobs, workers: int, on_done, preload, timeout=None) -> None:
    """A process pool; a crash costs only the job that caused it, a stopped job only itself."""
    from .._pools import forkserver_context
    ctx = forkserver_context(preload)
    queue = list(reversed(jobs))
    suspects = []
    while queue:
        with _local_pool(ctx, workers, timeout) as (pool, clock):
            # A short queue (twice the workers): a crash sends few jobs to the retry.
            left, stopped = _drain(pool, fn, queue, 2 * workers, on_done, _RAISED, clock=clock)
        if stopped:  # the pool broke because a job was stopped: the others were not at fault
            queue += left[::-1]
        else:
            suspects += left
    for job in suspects:  # one at a time, in a fresh process each
        with _local_pool(ctx, 1, timeout) as (pool, clock):
            left, stopped = _drain(pool, fn, [job], 1, on_done, _RAISED, clock=clock)
            if left and not stopped:
                on_done(job, None, DIED)


class _DaskTasks:
    """A Dask client seen as an executor: `concurrent.futures` futures that know their task."""

    def __init__(self, client):
        self.client, self.tasks = client, {}

    def submit(self, fn, *args):
        task = self.client.submit(fn, *args, pure=False)
        fut = Future()
        self.tasks[fut] = task

        def settle(task):  # in Dask's callback thread
            self.tasks.pop(fut, None)
            if task.status == "cancelled":
                fut.cancel()
                fut.set_running_or_notify_cancel()  # wakes a wait() on it
                return
            try:
                if task.status == "error":
                    fut.set_exception(task.exception())
                else:
                    fut.set_result(task.result())
            except BaseException as exc:  # noqa: BLE001 - the client went away: the job is lost
                if not fut.done():
                    fut.set_exception(exc)
        task.add_done_callback(settle)
        return fut


class _DaskClock(_Clock):
    """Start times from the workers' events (`_timed`); a job is stopped by cancelling its task."""

    def __init__(self, timeout: float, tasks: _DaskTasks):
        import uuid
        from collections import deque
        super().__init__(timeout)
        self.tasks, self.topic, self.heard = tasks, f"slicelab-start-{uuid.uuid4().hex}", deque()
        # The client's event loop calls this as each event arrives (a deque's ends are thread-safe).
        tasks.client.subscribe_topic(self.topic, lambda event: self.heard.append((time.monotonic(), event[1])))

    def word(self, key: int):
        return self.topic, key

    def poll(self) -> None:
        while self.heard:
            t, key = self.heard.popleft()
            fut = self.keys.get(key)
            if fut is not None:
                self.started.setdefault(fut, t)

    def stop(self, fut) -> tuple[TimedOut, bool]:
        task = self.tasks.tasks.get(fut)
        if task is not None:
            task.cancel()
        return TimedOut(f"still running after {self.timeout:g} s, the time limit: cancelled (its Dask "
                        f"worker may go on running it to its end)"), False

    def close(self) -> None:
        with contextlib.suppress(Exception):  # the client may be gone already
            self.tasks.client.unsubscribe_topic(self.topic)


def _run_dask(fn, jobs, scheduler: str, on_done, timeout=None) -> None:
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("a Dask scheduler needs Dask: pip install 'slicelab[cluster]'") from None
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
        tasks = _DaskTasks(client)
        clock = None if timeout is None else _DaskClock(timeout, tasks)
        try:
            _drain(tasks, fn, list(reversed(jobs)), len(jobs), on_done, LOST, alive=alive, clock=clock)
        finally:
            if clock is not None:
                clock.close()
    finally:
        client.close()
