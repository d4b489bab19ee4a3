"""Worker processes: a time limit that stops a stuck job, workers that end with the process that started
them (kill -9 included), and pools that work from any folder."""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import slicelab
from slicelab import samples
from slicelab.tasks import run_jobs
from slicelab.tasks.executors import TimedOut

DATA = Path(__file__).resolve().parents[1] / "data"
# sum() over it runs in C, holding the GIL, for days: a job stuck in compiled code, deaf to signals.
STUCK = range(10 ** 15)
linux_only = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")


def _collect(done):
    return lambda job, result, lost: done.append((job, result, lost))


def test_a_job_past_the_time_limit_is_killed_and_the_others_go_on():
    done = []
    jobs = [(STUCK,), (range(10),), (range(100),), (range(10 ** 15 + 1),), (range(1000),)]
    t0 = time.monotonic()
    run_jobs(sum, jobs, workers=2, timeout=1.0, on_done=_collect(done))
    assert time.monotonic() - t0 < 60
    got = {job[0]: (result, lost) for job, result, lost in done}
    assert len(done) == len(jobs)
    assert [got[range(n)] for n in (10, 100, 1000)] == [(45, None), (4950, None), (499500, None)]
    for stuck in (STUCK, range(10 ** 15 + 1)):
        result, lost = got[stuck]
        assert result is None and isinstance(lost, TimedOut) and "killed" in lost and "1 s" in lost


def test_one_worker_with_a_time_limit_runs_in_a_worker_process_replaced_when_stuck():
    done = []
    run_jobs(sum, [(STUCK,), (range(10),)], workers=1, timeout=1.0, on_done=_collect(done))
    assert [(job[0], result, type(lost)) for job, result, lost in done] == \
        [(STUCK, None, TimedOut), (range(10), 45, type(None))]
    pids = []
    run_jobs(os.getpid, [()], workers=1, timeout=60, on_done=lambda job, r, lost: pids.append(r))
    assert pids and pids[0] != os.getpid()


def test_a_job_that_ends_past_the_limit_is_timed_out_too():
    """Between two looks at the clock a job may end late: it is timed out all the same, whatever the timing."""
    done = []
    run_jobs(time.sleep, [(0.05,)], workers=1, timeout=0.001, on_done=_collect(done))
    ((_, result, lost),) = done
    assert result is None and isinstance(lost, TimedOut)


def test_dask_time_limit_cancels_the_task():
    distributed = pytest.importorskip("distributed")
    done = []
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None,
                                  silence_logs=50) as cluster:
        run_jobs(time.sleep, [(4,), (0.01,)], scheduler=cluster.scheduler_address, timeout=1.0,
                 on_done=_collect(done))
    got = {job[0]: (result, lost) for job, result, lost in done}
    assert got[0.01] == (None, None)
    assert isinstance(got[4][1], TimedOut) and "cancelled" in got[4][1]


def test_workers_see_the_users_environment():
    """The fork server starts with PYTHONSAFEPATH=1; the workers get the user's value back."""
    before = dict(os.environ)
    seen = []
    run_jobs(os.getenv, [("PYTHONSAFEPATH",), ("PYTHONSAFEPATH",)], workers=2, timeout=60,
             on_done=lambda job, r, lost: seen.append((r, lost)))
    assert seen == [(os.environ.get("PYTHONSAFEPATH"), None)] * 2
    assert dict(os.environ) == before


def test_batch_runs_from_a_folder_that_holds_a_slicelab_package(tmp_path):
    """The fork server runs `python -c`, whose sys.path starts with the current folder: here it would
    import the empty slicelab/ below instead of slicelab, and every file would fail in its worker."""
    here = tmp_path / "work"
    (here / "slicelab").mkdir(parents=True)
    (here / "slicelab" / "__init__.py").write_text("")
    for name in ("sphere.stl", "torus.stl"):
        (here / "in").mkdir(exist_ok=True)
        (here / "in" / name).write_bytes((DATA / name).read_bytes())
    # The command's own script lives elsewhere (as an installed `slicelab` does): its sys.path is fine.
    runner = tmp_path / "bin" / "runner.py"
    runner.parent.mkdir()
    runner.write_text("from slicelab.cli import run\n\nif __name__ == '__main__':\n    raise SystemExit(run())\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONSAFEPATH"}
    proc = subprocess.run([sys.executable, str(runner), "batch", "in", "-o", "out", "--task", "section",
                           "--workers", "2", "--no-progress"], cwd=here, env=env, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "2 mesh files: 2 ok" in proc.stdout
    assert (here / "out" / "sphere.stl" / "section.svg").is_file()


def _descendants(pid: int) -> set[int]:
    """Every living process below `pid` (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    ppid = int(fh.read().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            children.setdefault(ppid, []).append(int(entry))
    out, stack = set(), [pid]
    while stack:
        for c in children.get(stack.pop(), []):
            out.add(c)
            stack.append(c)
    return out


def _running(pids) -> set[int]:
    alive = set()
    for p in pids:
        try:
            state = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            continue
        if state != "Z":  # a zombie has ended: only its parent's wait is missing
            alive.add(p)
    return alive


def _kill_and_watch(proc, wanted: int, patience: float = 120.0, settle: float = 0.0) -> set[int]:
    """Kill -9 `proc` once it has `wanted` processes below it; what of them still runs 20 s later."""
    deadline = time.time() + patience
    below = set()
    try:
        while time.time() < deadline and len(below) < wanted and proc.poll() is None:
            time.sleep(0.1)
            below = _descendants(proc.pid)
        assert len(below) >= wanted, f"the command never started its workers ({proc.poll()=})"
        time.sleep(settle)
        below |= _descendants(proc.pid)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        deadline = time.time() + 20
        alive = _running(below)
        while alive and time.time() < deadline:
            time.sleep(0.2)
            alive = _running(alive)
        return alive
    finally:
        for p in _running(below):  # whatever the outcome, no process of the test is left behind
            try:
                os.kill(p, signal.SIGKILL)
            except OSError:
                pass
        if proc.poll() is None:
            proc.kill()


@linux_only
def test_killing_slice_ends_its_forked_workers(tmp_path):
    """The forked planner workers wait on a pipe whose writing end they hold themselves: without the
    parent-death signal they would wait for good once `slice` is killed."""
    proc = subprocess.Popen([sys.executable, "-m", "slicelab", "slice", str(DATA / "pot.stl"), "--layer-height",
                             "0.1", "--workers", "2", "-o", str(tmp_path / "pot.gcode")], cwd=tmp_path,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    alive = _kill_and_watch(proc, 2)
    assert not alive, f"worker processes still running after slice was killed: {sorted(alive)}"


@linux_only
def test_killing_a_batch_ends_its_worker_processes(tmp_path):
    scans = tmp_path / "scans"
    for k in range(8):
        slicelab.save(samples.pot(40, 120), scans / f"pot{k}.stl")
    proc = subprocess.Popen([sys.executable, "-m", "slicelab", "batch", str(scans), "-o", str(tmp_path / "out"),
                             "--task", "profile", "--workers", "2", "--no-progress"], cwd=tmp_path,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    alive = _kill_and_watch(proc, 3)  # the fork server and two workers
    assert not alive, f"worker processes still running after the batch was killed: {sorted(alive)}"


@linux_only
def test_killing_a_batch_ends_workers_stuck_in_compiled_code(tmp_path):
    """A worker stuck in C holding the GIL never runs its watching thread: the kernel's signal ends it
    when the fork server, which exits with the batch, goes."""
    script = tmp_path / "stuck.py"
    script.write_text("from slicelab.tasks import run_jobs\n\n"
                      "if __name__ == '__main__':\n"
                      "    run_jobs(sum, [(range(10 ** 15 + k),) for k in range(2)], workers=2,\n"
                      "             on_done=lambda job, r, lost: None)\n")
    proc = subprocess.Popen([sys.executable, str(script)], cwd=tmp_path, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    alive = _kill_and_watch(proc, 3, settle=1.0)  # the fork server and two workers, busy
    assert not alive, f"worker processes still running after the batch was killed: {sorted(alive)}"
