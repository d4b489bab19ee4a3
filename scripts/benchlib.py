"""Helpers shared by ``scripts/bench_*.py``: one measurement per child process.

Every measurement runs in a fresh Python process, so its peak memory (read
with ``os.wait4``, which reports that child's own rusage) is not contaminated
by earlier measurements, and no cache warmed by one tool helps the next.
Times are taken inside the child around the measured call only (interpreter
start-up and imports are not counted); the file is read once beforehand so
every tool reads it from the page cache.
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LARGE = ROOT / "data" / "large"
LARGE_FILES = ("torus_1m.stl", "torus_5m.stl", "pot_5m.stl")
CHILD_FLAG = "--child"


def ensure_large_data() -> None:
    """Write data/large/ with scripts/make_data.py if any file is missing."""
    if all((LARGE / name).exists() for name in LARGE_FILES):
        return
    print("data/large/ incomplete: running scripts/make_data.py --large", flush=True)
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_data.py"), "--large"], check=True)


def warm(path: Path) -> None:
    """Read a file once so that every measurement finds it in the page cache."""
    with open(path, "rb") as fh:
        while fh.read(1 << 24):
            pass


def run_child(script: str, *args: str) -> dict:
    """Run ``python script --child args...`` and return its JSON result plus ``peak_mb``.

    ``peak_mb`` is the child's peak resident set size (MiB), read from the
    rusage of that child alone.
    """
    cmd = [sys.executable, script, CHILD_FLAG, *args]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True, cwd=ROOT)
    out = proc.stdout.read()
    proc.stdout.close()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)  # we reaped it ourselves
    if proc.returncode != 0:
        raise RuntimeError(f"measurement failed ({proc.returncode}): {' '.join(cmd[1:])}")
    result = json.loads(out.strip().splitlines()[-1])
    result["peak_mb"] = usage.ru_maxrss / 1024  # Linux reports KiB
    return result


def measure(script: str, *args: str, repeat: int = 1) -> dict:
    """`run_child` `repeat` times: median of ``seconds``, largest ``peak_mb``."""
    runs = [run_child(script, *args) for _ in range(repeat)]
    out = dict(runs[-1])
    out["seconds"] = statistics.median(r["seconds"] for r in runs)
    out["all_seconds"] = [r["seconds"] for r in runs]
    out["peak_mb"] = max(r["peak_mb"] for r in runs)
    return out


def child_report(seconds: float, **extra) -> None:
    """Print the child's result as one JSON line (the parent reads the last line)."""
    import resource
    extra["seconds"] = seconds
    extra["self_peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(extra), flush=True)


def mark(ok: bool) -> str:
    return "PASS" if ok else "MISS"


NOISE_NOTE = ("Timings come from a shared 2-core machine (other jobs may run at the same time): "
              "treat them as noisy, compare ratios from the same run.")



def run_command(*args: str) -> tuple[float, float, str]:
    """Wall-clock seconds, peak memory (MiB) and stdout of ``python -m slicelab ARGS``, as a user runs it
    (interpreter start-up and imports included). Exit status 0 or 1 (a warned result) is accepted;
    anything else raises with the command's error line."""
    import tempfile
    import time
    with tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen([sys.executable, "-m", "slicelab", *map(str, args)], stdout=subprocess.PIPE,
                                stderr=err, text=True, cwd=ROOT)
        stdout = proc.stdout.read()
        proc.stdout.close()
        _, status, usage = os.wait4(proc.pid, 0)
        seconds = time.perf_counter() - t0
        err.seek(0)
        code = os.waitstatus_to_exitcode(status)
        if code not in (0, 1):
            raise RuntimeError(f"slicelab {' '.join(map(str, args))} failed: {err.read().strip()}")
    return seconds, usage.ru_maxrss / 1024, stdout.strip()


# --- Tables for the documentation -------------------------------------------------------------------
# A benchmark run with ``--docs`` also writes what it printed, with the machine and the date, to
# docs/performance/tables/NAME.rst, which the "Validation and performance" pages include (the
# ``bench-result`` directive of docs/_ext/benchresults.py); without the file they say how to make it.

DOCS_RESULTS = ROOT / "docs" / "performance" / "tables"


def machine_facts() -> dict[str, str]:
    """The machine and software a measurement ran on: CPU model, cores, RAM, OS, Python, numpy,
    how the compiled kernels load, the commit measured (``+`` if the tree had changes) and the
    load average when it ended (other work on the machine makes timings noisy)."""
    import datetime
    import platform

    import numpy as np

    cpu = platform.processor() or platform.machine()
    ram = ""
    try:
        cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                    if line.startswith("model name")), cpu)
        kib = next(int(line.split()[1]) for line in open("/proc/meminfo") if line.startswith("MemTotal"))
        ram = f", {kib / 2**20:.1f} GiB RAM"
    except (OSError, StopIteration, ValueError):
        pass

    def run(*cmd: str) -> str:
        try:
            return subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=60).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""

    commit = run("git", "rev-parse", "--short", "HEAD") or "unknown"
    if run("git", "status", "--porcelain", "--untracked-files=no", "--", "slicelab", "scripts"):
        commit += "+"
    version = run(sys.executable, "-m", "slicelab", "--version") or "slicelab (version unknown)"
    load = f", load average {os.getloadavg()[0]:.1f} at the end" if hasattr(os, "getloadavg") else ""
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC") + load,
        "machine": f"{cpu}, {os.cpu_count()} cores{ram}, {platform.system()} {platform.release()} "
                   f"{platform.machine()}",
        "software": f"Python {platform.python_version()}, numpy {np.__version__}, {version}",
        "commit": commit,
    }


def write_docs_results(name: str, text: str, command: str) -> Path:
    """Write `text` (what benchmark `name` printed) to ``docs/performance/tables/NAME.rst`` as a
    literal block under the command that made it, the date and the machine; return the path."""
    facts = machine_facts()
    body = "".join(f"   {line}".rstrip() + "\n" for line in text.rstrip().splitlines())
    page = (f".. Written by ``{command}`` (scripts/benchlib.py, docs_output): run it again rather\n"
            f"   than editing this file.\n\n"
            f":Command: ``{command}``\n"
            f":Measured: {facts['date']}, commit {facts['commit']}\n"
            f":Machine: {facts['machine']}\n"
            f":Software: {facts['software']}\n\n"
            f".. code-block:: text\n\n{body}")
    DOCS_RESULTS.mkdir(parents=True, exist_ok=True)
    path = DOCS_RESULTS / f"{name}.rst"
    path.write_text(page)
    return path


class _Tee:
    """A stdout that also keeps a copy of what is printed."""

    def __init__(self, stream, copy):
        self.stream, self.copy = stream, copy

    def write(self, text):
        self.copy.write(text)
        return self.stream.write(text)

    def flush(self):
        self.stream.flush()

    def __getattr__(self, name):
        return getattr(self.stream, name)


class docs_output:
    """``with docs_output("bench_io", args.docs): ...``: when `enabled`, what the block prints also
    goes to `write_docs_results` once the block ends without an error (``SystemExit(0)`` counts as
    success), so the docs' table is the one the run printed, never copied by hand."""

    def __init__(self, name: str, enabled: bool = True):
        self.name, self.enabled = name, enabled
        # (the command as typed, read now: a script may take ``--docs`` out of sys.argv for its parser)
        self.command = " ".join(["python", f"scripts/{Path(sys.argv[0]).name}", *sys.argv[1:]])

    def __enter__(self):
        if self.enabled:
            import io
            self.saved, self.buffer = sys.stdout, io.StringIO()
            sys.stdout = _Tee(sys.stdout, self.buffer)
        return self

    def __exit__(self, kind, exc, tb):
        if not self.enabled:
            return False
        sys.stdout = self.saved
        if kind is None or (kind is SystemExit and exc.code in (0, None)):
            path = write_docs_results(self.name, self.buffer.getvalue(), self.command)
            print(f"wrote {path.relative_to(ROOT)}", flush=True)
        return False
