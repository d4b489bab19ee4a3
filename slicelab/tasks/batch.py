"""Batch runs: one job over every mesh file under a folder, locally or on a Dask cluster.

Every file gets a JSON report (input SHA-256, parameters, outputs, timings,
status ok / warn / fail and the reasons) and a row in ``summary.csv`` (units in
the column names; for profiles an EVE table beside a rim-diameter chart,
`slicelab.tasks.summary`); its
outputs go to a folder of their own named after it, extension kept, under
the job's own file names (the same as on the command line: ``pot.stl`` ->
``OUT/pot.stl.json`` and ``OUT/pot.stl/section.svg``; names that would
clash get a suffix, see `slicelab.tasks.outputs`). A broken file fails
alone; the batch carries on. So does a file that is not a regular file (a
named pipe, a device: never opened) and a file that runs past the time
limit. A file whose report is up to date (same content, job, parameters
and slicelab version, outputs present) is skipped, so an interrupted batch
resumes where it stopped. Files run on a local process pool, or on a Dask
distributed cluster given its scheduler address (the optional extra
``slicelab[cluster]``), through `slicelab.tasks.executors.run_jobs`: a lab
that outgrows one machine adds workers, not tools. Workers must see DIR and
OUT at the same paths (a shared file system); they write the outputs, the
client writes the reports, so a worker lost mid-file still leaves a report.
"""
from __future__ import annotations

import contextlib
import fnmatch
import hashlib
import json
import os
import socket
import stat
import sys
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from .. import __version__
from ..files.atomic import atomic_open
from ..mesh.io import MeshFileError
from .executors import TimedOut, run_jobs
from .limits import likely_units
from .jobs import JOBS, TASKS, job_parameters, run_job
from .outputs import output_names
from .spec import ParameterError, choice, number, plain, reason
from .summary import write_batch_files, write_summary

__all__ = ["TASKS", "BatchResult", "task_parameters", "find_mesh_files", "process_file", "run_batch",
           "write_summary"]

STATUSES = ("ok", "warn", "fail")
_FAILING = {"unreadable", "not_a_file", "task_error", "task_unavailable", "worker_lost", "timeout"}
_BATCH = ("min_size", "max_size", "units", "scale")  # parameters of the batch itself, beside the job's


def task_parameters(task: str, *, origin=None, normal=None, min_size: float = 2.0, max_size: float = 5000.0,
                    units: str | None = None, scale: float | None = None, **options) -> dict:
    """Check and normalise a batch's parameters into plain JSON values.

    The result is stored in every report and compared on reruns: a report
    made with other parameters is not up to date.

    Parameters
    ----------
    task : {"inspect", "section", "split", "profile", "layers"}
    origin, normal : 3 floats, optional
        The plane of ``section`` and ``split``; without them, the horizontal
        plane at each part's mid-height.
    min_size, max_size : float
        A part whose largest dimension (mm) lies outside is flagged
        ``units?``, with the unit that would make it plausible.
    units, scale : optional
        How the files are written (`slicelab.load`): their coordinates are
        scaled to millimetres.
    **options
        The job's parameters (`slicelab.tasks.jobs.job_parameters`), such as
        ``layer_height`` for ``layers`` or ``planes``, ``side``, ``png`` for ``profile``.

    Raises
    ------
    ParameterError
        A ValueError naming the bad parameter.

    Examples
    --------
    >>> task_parameters("section", origin=(0, 0, 5), normal=(0, 0, 2))["plane"]
    {'origin': [0.0, 0.0, 5.0], 'normal': [0.0, 0.0, 2.0]}
    >>> task_parameters("layers")
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: layer_height is required (a positive number, mm)
    """
    if task not in TASKS:
        raise ValueError(f"unknown task {task!r}; choose one of {', '.join(TASKS)}")
    p = {"min_size": number("min_size", min_size, low=0), "max_size": number("max_size", max_size)}
    if not p["min_size"] < p["max_size"]:
        raise ParameterError("min_size", "must be >= 0 and below max_size")
    if units is not None:
        from ..mesh import UNITS
        p["units"] = choice("units", units, tuple(UNITS))
    if scale is not None:
        p["scale"] = number("scale", scale, positive=True)
    if origin is not None or normal is not None:
        if (origin is None) != (normal is None):
            raise ParameterError("origin", "and normal go together: give both, or neither "
                                           "(the horizontal plane at mid-height)")
        options["plane"] = (origin, normal)
    if "plane" in options and "plane" not in JOBS[task].defaults:
        raise ParameterError("plane", f"is not a parameter of the {task} task")
    return {**p, **job_parameters(task, **options)}


_MESH_ENDINGS = (".stl", ".ply", ".obj", ".3mf")


def find_mesh_files(root, exclude=None, patterns=()) -> tuple[list[Path], int]:
    """Every mesh file (``.stl``, ``.ply``, ``.obj``, ``.3mf``, any case) under `root`, sorted; and how
    many other files were passed over.

    Files are picked by their names alone: one that is not a regular file (a
    named pipe, a device) is found too, for `process_file` to report.
    Hidden files and folders (a leading dot: temporary ``.part`` files),
    anything under `exclude` (the output folder) and paths relative to `root`
    matching one of the glob `patterns` (``large/*``, ``*_raw.stl``) are left out.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> for name in ("a.STL", "b.txt", "c.ply", "d.obj"): _ = (d / name).write_text("")
    >>> [p.name for p in find_mesh_files(d)[0]], find_mesh_files(d)[1]
    (['a.STL', 'c.ply', 'd.obj'], 1)
    """
    root = Path(root)
    ex = Path(exclude).resolve() if exclude is not None else None
    found, other = [], 0
    for dirpath, dirnames, filenames in os.walk(root):
        here = Path(dirpath)
        dirnames[:] = sorted(d for d in dirnames if not d.startswith(".")
                             and (ex is None or (here / d).resolve() != ex))
        for name in filenames:
            if name.startswith("."):
                continue
            if any(fnmatch.fnmatch((here / name).relative_to(root).as_posix(), pat) for pat in patterns):
                continue
            if name.lower().endswith(_MESH_ENDINGS):
                found.append(here / name)
            else:
                other += 1
    return sorted(found, key=lambda p: p.relative_to(root).as_posix()), other


def _sha256(path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds")


def _status(reasons) -> str:
    if any(r["code"] in _FAILING for r in reasons):
        return "fail"
    return "warn" if reasons else "ok"


_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _not_a_file(st: os.stat_result) -> str | None:
    """What the file is, when it is not a regular file: reading a pipe or a device may never end."""
    if stat.S_ISREG(st.st_mode):
        return None
    return next((what for test, what in _KINDS if test(st.st_mode)), "not a regular file")


def _mesh_reasons(report, params) -> list[dict]:
    reasons = []
    if not report.watertight:
        reasons.append(reason("not_watertight", f"not watertight ({report.n_open_edges} open edges, "
                                                 f"{report.n_nonmanifold_edges} non-manifold edges)"))
    if report.n_shells > 1:
        reasons.append(reason("several_shells", f"several shells ({report.n_shells})"))
    lo, hi = np.asarray(report.bounds, float)
    size = float((hi - lo).max())
    hint = likely_units(size, params["min_size"], params["max_size"])
    if hint is not None:
        reasons.append(reason("units?", f"implausible size: {hint}"))
    return reasons


class _Refused(Exception):
    """A file refused before it is opened, with the reason for its report."""

    def __init__(self, why: dict):
        super().__init__(why["message"])
        self.reason = why


def process_file(path, root, out, task: str, params: dict, name: str | None = None) -> dict:
    """Run one job on one file and return its report (never raises for a bad file).

    Writes the job's outputs under `out`, in the folder `name` (default: the
    file's path under `root`, as `slicelab.tasks.outputs.output_names` names
    it when nothing clashes); the report itself is returned, for the caller
    to write. A file that is not a regular file (a named pipe, a device) is
    never opened: it fails with the reason ``not_a_file``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp()); (d / "x.stl").write_bytes(b"not a mesh")
    10
    >>> r = process_file(d / "x.stl", d, d / "out", "inspect", task_parameters("inspect"))
    >>> r["status"], r["reasons"][0]["code"]
    ('fail', 'unreadable')
    """
    from ..mesh import check, load
    t_start = time.perf_counter()
    path, root, out = Path(path), Path(root), Path(out)
    rel = path.relative_to(root).as_posix()
    folder = out / (name or rel)
    rep = {"slicelab": __version__, "file": rel, "path": str(path.resolve()), "task": task,
           "parameters": params, "status": "fail", "reasons": [], "input": {}, "check": None,
           "results": {}, "outputs": {}, "timings": {}, "worker": f"{socket.gethostname()}:{os.getpid()}",
           "started": _now()}
    reasons, timings = rep["reasons"], rep["timings"]
    try:
        t0 = time.perf_counter()
        st = path.stat()
        what = _not_a_file(st)
        if what is not None:
            raise _Refused(reason("not_a_file", f"not a regular file but {what}: not read"))
        rep["input"] = {"sha256": _sha256(path), "size": st.st_size, "mtime_ns": st.st_mtime_ns}
        t1 = time.perf_counter()
        mesh = load(path, **{k: params[k] for k in ("units", "scale") if params.get(k) is not None})
        t2 = time.perf_counter()
        report = check(mesh)
        t3 = time.perf_counter()
        timings.update(hash=t1 - t0, load=t2 - t1, check=t3 - t2)
        rep["check"] = report.to_dict()
        reasons += _mesh_reasons(report, params)
        job_params = {k: v for k, v in params.items() if k not in _BATCH}
        result = run_job(task, path, job_params, folder, mesh=mesh, check=report)
        timings["task"] = time.perf_counter() - t3
        rep["outputs"], rep["results"] = result.relative_outputs(out), result.results
        reasons += [r for r in result.reasons if r["code"] not in {q["code"] for q in reasons}]
    except _Refused as exc:
        reasons.append(exc.reason)
    except MeshFileError as exc:
        reasons.append(reason("unreadable", exc.reason))
    except OSError as exc:
        reasons.append(reason("unreadable", f"cannot be read ({exc.strerror or exc})"))
    except ImportError as exc:  # an optional dependency of the job is missing
        reasons.append(reason("task_unavailable", f"{task} needs {exc.name or exc}: not installed"))
    except Exception as exc:  # noqa: BLE001 - one bad file must not stop the batch
        msg = str(exc).splitlines()[0] if str(exc) else ""
        reasons.append(reason("task_error", f"{task} failed: {type(exc).__name__}: {msg}".rstrip(": ")))
    rep["status"] = _status(reasons)
    timings["total"] = time.perf_counter() - t_start
    rep["finished"] = _now()
    return plain(rep)


def _lost_report(path: Path, root: Path, task: str, params: dict, why: str, timeout: float | None) -> dict:
    """The report of a file whose worker died (retried on the next run) or that ran past the time
    limit (retried when the limit is raised): written by the client."""
    rel = path.relative_to(root).as_posix()
    timed_out = isinstance(why, TimedOut)
    rep = {"slicelab": __version__, "file": rel, "path": str(path.resolve()), "task": task, "parameters": params,
           "status": "fail", "reasons": [reason("timeout" if timed_out else "worker_lost", str(why))],
           "input": {}, "check": None, "results": {}, "outputs": {}, "timings": {}, "started": _now(),
           "finished": _now()}
    rep.update({"time_limit": timeout} if timed_out else {"transient": True})
    with contextlib.suppress(OSError):  # not read (it may be what took so long): a rerun compares these
        st = path.stat()
        rep["input"] = {"size": st.st_size, "mtime_ns": st.st_mtime_ns}
    return rep


def _output_files(outputs: dict) -> list[str]:
    files = []
    for v in outputs.values():
        files += v if isinstance(v, list) else [v]
    return files


def _up_to_date(name: str, rel: str, path: Path, out: Path, task: str, params: dict, retry_failed: bool,
                timeout: float | None = None):
    try:
        rep = json.loads((out / f"{name}.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if (rep.get("file") != rel or rep.get("slicelab") != __version__ or rep.get("task") != task
            or rep.get("parameters") != params or rep.get("transient") or rep.get("status") not in STATUSES
            or (retry_failed and rep.get("status") == "fail")):
        return None
    if any(r.get("code") == "timeout" for r in rep.get("reasons") or []) and (
            timeout is None or timeout > (rep.get("time_limit") or float("inf"))):
        return None  # more time now than the run that stopped it had
    try:
        st = path.stat()
    except OSError:
        return None
    if _not_a_file(st) is not None:  # never hashed: reading a pipe may never end
        return None
    inp = rep.get("input") or {}
    if inp.get("size") != st.st_size:
        return None
    if inp.get("mtime_ns") != st.st_mtime_ns and inp.get("sha256") != _sha256(path):
        return None
    files = _output_files(rep.get("outputs") or {})
    # Each output in the file's own folder (not in one an older layout shared), and there.
    if not all(o.startswith(f"{name}/") and (out / o).exists() for o in files):
        return None
    return rep


def _write_report(out: Path, name: str, rep: dict) -> None:
    with atomic_open(out / f"{name}.json", "w", encoding="utf-8") as fh:
        json.dump(rep, fh, indent=1, allow_nan=False)
        fh.write("\n")


@dataclass(frozen=True)
class BatchResult:
    """What a batch did.

    Attributes
    ----------
    reports : list of dict
        One per mesh file, in file order (fresh or kept from an earlier run).
    ran, skipped : int
        Files processed now, and files whose report was up to date.
    ignored : int
        Files under DIR that are not mesh files (by their endings).
    summary : Path
        ``summary.csv`` (`slicelab.tasks.summary`).
    seconds : float
    files : dict
        The batch's other files beside the summary: for the profile task ``chart``
        (``rim_diameters.png``) and ``chart_data`` (``rim_diameters.csv``).
    """

    reports: list = field(default_factory=list)
    ran: int = 0
    skipped: int = 0
    ignored: int = 0
    summary: Path | None = None
    seconds: float = 0.0
    files: dict = field(default_factory=dict)

    def count(self, status: str) -> int:
        """Files with this status."""
        return sum(r["status"] == status for r in self.reports)

    def __str__(self) -> str:
        return (f"{len(self.reports)} mesh files: {self.count('ok')} ok, {self.count('warn')} warn, "
                f"{self.count('fail')} fail ({self.ran} run, {self.skipped} up to date, "
                f"{self.ignored} other files ignored) in {self.seconds:.1f} s")


# Modules the local worker processes import once, before they are forked: the batch, the
# jobs' libraries (mesh and slicing load whole; artefacts loads by name) and their drawing.
_PRELOAD = ["slicelab.tasks.batch", "slicelab.mesh", "slicelab.slicing", "slicelab.artefacts.profiles",
            "slicelab.artefacts.drawing", "slicelab.viz.profile", "slicelab.viz.preview", "scipy.spatial",
            "matplotlib.figure", "matplotlib.backends.backend_agg", "slicelab.tasks.threads", "threadpoolctl",
            "slicelab.artefacts.profile_files", "ezdxf"]


def run_batch(root, out, task: str = "inspect", params: dict | None = None, *, workers: int | None = None,
              scheduler: str | None = None, force: bool = False, retry_failed: bool = False,
              progress: bool | None = None, exclude=(), timeout: float | None = None) -> BatchResult:
    """Run `task` over every mesh file under `root`, writing reports and outputs under `out`.

    Parameters
    ----------
    root : path
        Folder searched recursively for mesh files (`find_mesh_files`: ``.stl``,
        ``.ply``, ``.obj``, ``.3mf``, any case).
    out : path
        Output folder, mirroring the tree under `root`: per file, its report
        ``pot.stl.json`` and a folder ``pot.stl/`` of the job's outputs (the
        same file names as on the command line), extension kept, with a
        suffix (``~2``) for names that would clash, even if only by case
        (`slicelab.tasks.outputs.output_names`); and ``summary.csv`` (every number's unit in its
        column's name; for the profile task an EVE table), with, for the profile task, the
        rim-diameter chart ``rim_diameters.png`` and its numbers ``rim_diameters.csv``
        (`slicelab.tasks.summary`).
    task : {"inspect", "section", "split", "profile", "layers"}
    params : dict, optional
        From `task_parameters` (checked again here; defaults for `task` if omitted).
    workers : int, optional
        Local processes (default: CPU count); 1 runs in this process, or with
        a `timeout` in one worker process.
    scheduler : str, optional
        Address of a Dask distributed scheduler (``tcp://host:8786``); the
        files then run on its workers and `workers` is ignored.
    force : bool
        Rerun files whose reports are up to date.
    retry_failed : bool
        Rerun files whose up-to-date report says fail.
    progress : bool, optional
        tqdm progress bar on stderr (default: when stderr is a terminal).
    exclude : sequence of str
        Glob patterns of paths under `root` to leave out (``large/*``).
    timeout : float, optional
        Seconds one file may take (None: no limit; the command line's default
        is 900). A file past it fails with the reason ``timeout`` and the batch
        goes on; locally its worker process is killed and replaced, on Dask its
        task is cancelled, though the Dask worker may go on running it
        (`slicelab.tasks.executors.run_jobs`). It is not retried by reruns
        unless the limit is raised, or with `retry_failed`.

    Returns
    -------
    BatchResult
        Every file's report, and where the summary is; a second run skips the
        files whose reports are up to date.

    Examples
    --------
    >>> import pathlib, tempfile, slicelab
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> slicelab.save(slicelab.samples.box((0, 0, 0), (10, 10, 10)), d / "in" / "cube.stl")
    >>> r = run_batch(d / "in", d / "out", "inspect", workers=1, progress=False)
    >>> r.count("ok"), r.ran, run_batch(d / "in", d / "out", "inspect", workers=1, progress=False).skipped
    (1, 1, 1)
    """
    from tqdm import tqdm
    t0 = time.perf_counter()
    # Absolute paths: a Dask worker runs in its own working directory.
    root, out = Path(root).resolve(), Path(out).resolve()
    if not root.is_dir():
        raise ValueError(f"{root}: not a folder")
    if timeout is not None and not timeout > 0:
        raise ValueError(f"timeout must be a positive number of seconds, not {timeout!r}")
    params = task_parameters(task, **(params or {}))  # checked, whoever made them
    out.mkdir(parents=True, exist_ok=True)
    files, ignored = find_mesh_files(root, exclude=out, patterns=tuple(exclude))
    names = output_names(path.relative_to(root).as_posix() for path in files)
    reports: dict[str, dict] = {}
    jobs, refused = [], []
    for path in files:
        rel = path.relative_to(root).as_posix()
        job = (str(path), str(root), str(out), task, params, names[rel])
        try:
            odd = _not_a_file(path.stat()) is not None
        except OSError:  # gone, or a broken link: the job says so
            odd = False
        kept = None if force or odd else _up_to_date(names[rel], rel, path, out, task, params, retry_failed,
                                                     timeout)
        if kept is not None:
            reports[rel] = kept
        else:
            (refused if odd else jobs).append(job)
    bar = tqdm(total=len(files), initial=len(reports), unit="file", desc=f"slicelab {task}",
               disable=(not sys.stderr.isatty()) if progress is None else not progress, file=sys.stderr)

    def on_done(job, rep, lost):
        if rep is None:
            rep = _lost_report(Path(job[0]), Path(job[1]), task, params, lost, timeout)
        _write_report(out, names[rep["file"]], rep)
        reports[rep["file"]] = rep
        bar.update(1)
        bar.set_postfix_str(f"{rep['file']}: {rep['status']}", refresh=False)

    try:
        for job in refused:  # a pipe or a device: refused here at once, unread, without a worker
            on_done(job, process_file(*job), None)
        run_jobs(process_file, jobs, workers=workers, scheduler=scheduler, on_done=on_done, preload=_PRELOAD,
                 timeout=timeout)
    finally:
        bar.close()
        ordered = [reports[k] for k in sorted(reports)]
        summary = write_summary(out, ordered, task, names)
        extra = write_batch_files(out, ordered, task, names)
    ran = len(jobs) + len(refused)
    return BatchResult(ordered, ran, len(files) - ran, ignored, summary, time.perf_counter() - t0, extra)


