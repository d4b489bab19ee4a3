"""Batch runs: one task over every STL under a folder, locally or on a Dask cluster.

Every file gets a JSON report (input SHA-256, parameters, outputs, timings,
status ok / warn / fail and the reasons) written next to its outputs, and a
row in ``summary.csv``. A broken file fails alone; the batch carries on. A file
whose report is up to date (same content, task, parameters and slicelab
version, outputs present) is skipped, so an interrupted batch resumes where it
stopped. Files run on a local process pool, or on a Dask distributed cluster
given its scheduler address (the optional extra ``slicelab[cluster]``): a lab
that outgrows one machine adds workers, not tools. Workers must see DIR and
OUT at the same paths (a shared file system); they write the outputs, the
client writes the reports, so a worker lost mid-file still leaves a report.
"""
from __future__ import annotations

import csv
import fnmatch
import hashlib
import json
import math
import os
import socket
import sys
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from .. import __version__
from ..export.files import atomic_open
from ..mesh.io import MeshFileError

__all__ = ["TASKS", "BatchResult", "task_parameters", "find_stl_files", "process_file", "run_batch",
           "write_summary"]

TASKS = ("inspect", "section", "split", "profile", "layers")
STATUSES = ("ok", "warn", "fail")
_FAILING = {"unreadable", "task_error", "task_unavailable", "worker_lost"}
_SUMMARY_TASK_COLUMNS = {
    "inspect": [],
    "section": ["area", "loops", "holes", "open_chains"],
    "split": ["front_facets", "rear_facets", "cut_facets", "section_area"],
    "profile": ["height", "rim_diameter", "max_diameter", "base_diameter", "wall_thickness_min",
                "wall_thickness_mean", "wall_thickness_max", "base_thickness", "capacity", "clay_volume",
                "relative_residual", "spread"],
    "layers": ["layers", "loops", "open_chains"],
}


class TaskUnavailable(RuntimeError):
    """A task whose implementation is not installed (reported, never raised out of a batch)."""


def task_parameters(task: str, *, origin=None, normal=None, layer_height=None, planes: int = 12,
                    side: str = "left", max_gap: float = 1.0, png: bool = True, min_size: float = 2.0,
                    max_size: float = 5000.0) -> dict:
    """Check and normalise a task's parameters into plain JSON values.

    The result is stored in every report and compared on reruns: a report
    made with other parameters is not up to date.

    Parameters
    ----------
    task : {"inspect", "section", "split", "profile", "layers"}
    origin, normal : 3 floats, optional
        The plane of ``section`` and ``split``; without them, the horizontal
        plane at each part's mid-height.
    layer_height : float
        Required by ``layers``.
    planes, side, png
        ``profile``: planes through the axis, side of the drawn section, also write a PNG.
    max_gap : float
        Open chains closer than this are joined (mm).
    min_size, max_size : float
        A part whose largest dimension lies outside is flagged "implausible size" (units?).

    Examples
    --------
    >>> task_parameters("section", origin=(0, 0, 5), normal=(0, 0, 2))["plane"]
    {'origin': [0.0, 0.0, 5.0], 'normal': [0.0, 0.0, 2.0]}
    """
    if task not in TASKS:
        raise ValueError(f"unknown task {task!r}; choose one of {', '.join(TASKS)}")
    p: dict = {"min_size": float(min_size), "max_size": float(max_size)}
    if not (0 <= p["min_size"] < p["max_size"]):
        raise ValueError("min_size must be >= 0 and below max_size")
    if task in ("section", "split", "layers", "profile"):
        if not (max_gap >= 0 and math.isfinite(max_gap)):
            raise ValueError(f"max_gap must be a non-negative number, got {max_gap!r}")
        p["max_gap"] = float(max_gap)
    if task in ("section", "split"):
        if (origin is None) != (normal is None):
            raise ValueError("give both origin and normal, or neither (mid-height horizontal plane)")
        if origin is None:
            p["plane"] = None
        else:
            o = [float(v) for v in np.asarray(origin, float).reshape(3)]
            n = [float(v) for v in np.asarray(normal, float).reshape(3)]
            if not (np.all(np.isfinite(o)) and np.all(np.isfinite(n)) and any(n)):
                raise ValueError("the plane needs a finite origin and a non-zero normal")
            p["plane"] = {"origin": o, "normal": n}
    if task == "layers":
        if layer_height is None or not (float(layer_height) > 0 and math.isfinite(float(layer_height))):
            raise ValueError("the layers task needs a positive layer height")
        p["layer_height"] = float(layer_height)
    if task == "profile":
        if int(planes) < 1:
            raise ValueError(f"planes must be at least 1, got {planes!r}")
        if side not in ("left", "right"):
            raise ValueError(f"side must be 'left' or 'right', got {side!r}")
        p.update(planes=int(planes), side=side, png=bool(png))
    return json.loads(json.dumps(p))


def find_stl_files(root, exclude=None, patterns=()) -> tuple[list[Path], int]:
    """Every ``*.stl`` file under `root` (any case), sorted; and how many other files were passed over.

    Hidden files and folders (a leading dot: temporary ``.part`` files),
    anything under `exclude` (the output folder) and paths relative to `root`
    matching one of the glob `patterns` (``large/*``, ``*_raw.stl``) are left out.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp()); (d / "a.STL").write_bytes(b""); (d / "b.txt").write_text("")
    0
    0
    >>> [p.name for p in find_stl_files(d)[0]], find_stl_files(d)[1]
    (['a.STL'], 1)
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
            if name.lower().endswith(".stl"):
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


def _reason(code: str, message: str) -> dict:
    return {"code": code, "message": message}


def _status(reasons) -> str:
    if any(r["code"] in _FAILING for r in reasons):
        return "fail"
    return "warn" if reasons else "ok"


def _paths(out: Path, rel: str) -> tuple[Path, Path]:
    """The report's path and the stem for a file's outputs, mirroring its place under DIR."""
    r = Path(rel)
    return out / r.parent / f"{r.name}.json", out / r.parent / Path(r.name).stem


def _mesh_reasons(report, params) -> list[dict]:
    reasons = []
    if not report.watertight:
        reasons.append(_reason("not_watertight", f"not watertight ({report.n_open_edges} open edges, "
                                                 f"{report.n_nonmanifold_edges} non-manifold edges)"))
    if report.n_shells > 1:
        reasons.append(_reason("several_shells", f"several shells ({report.n_shells})"))
    lo, hi = np.asarray(report.bounds, float)
    size = float((hi - lo).max())
    if not (params["min_size"] <= size <= params["max_size"]):
        reasons.append(_reason("implausible_size", f"implausible size: largest dimension {size:.6g} mm, "
                                                   f"expected {params['min_size']:g} to {params['max_size']:g} mm "
                                                   f"(wrong units?)"))
    return reasons


def _plane(mesh, params):
    if params.get("plane"):
        return np.array(params["plane"]["origin"]), np.array(params["plane"]["normal"])
    z = mesh.triangles[..., 2]
    return np.array([0.0, 0.0, (float(z.min()) + float(z.max())) / 2]), np.array([0.0, 0.0, 1.0])


def _rel(out: Path, p: Path) -> str:
    return p.relative_to(out).as_posix()


# ----------------------------------------------------------------------- tasks
# Each task: (mesh, check report, output stem, out folder, params) -> (outputs, results, reasons).
def _task_inspect(mesh, report, stem, out, params):
    return {}, {}, []


def _task_section(mesh, report, stem, out, params):
    from ..slicing.sections import section
    origin, normal = _plane(mesh, params)
    s = section(mesh, origin, normal, max_gap=params["max_gap"])
    svg = stem.with_name(stem.name + ".section.svg")
    s.to_svg(svg)
    holes = int(np.count_nonzero(s.loop_depth % 2 == 1)) if len(s.loops) else 0
    results = {"plane": {"origin": origin.tolist(), "normal": normal.tolist()}, "area": s.area,
               "loops": len(s.loops), "holes": holes, "open_chains": len(s.open_chains),
               "joined_gaps": len(s.joined_gaps)}
    reasons = []
    if s.open_chains:
        reasons.append(_reason("open_section", f"the section has {len(s.open_chains)} open chains"))
    return {"svg": _rel(out, svg)}, results, reasons


def _task_split(mesh, report, stem, out, params):
    from ..mesh.io import save
    from ..slicing.split import split
    origin, normal = _plane(mesh, params)
    sp = split(mesh, origin, normal, max_gap=params["max_gap"])
    outputs = {}
    for side in ("front", "rear"):
        piece = getattr(sp, side)
        if len(piece):
            path = stem.with_name(f"{stem.name}.{side}.stl")
            save(piece, path)
            outputs[side] = _rel(out, path)
    svg = stem.with_name(stem.name + ".section.svg")
    sp.section.to_svg(svg)
    outputs["svg"] = _rel(out, svg)
    results = {"plane": {"origin": origin.tolist(), "normal": normal.tolist()},
               "front_facets": len(sp.front), "rear_facets": len(sp.rear),
               "cut_facets": int(getattr(sp, "n_cut", -1)), "section_area": sp.section.area,
               "section_loops": len(sp.section.loops), "section_open_chains": len(sp.section.open_chains)}
    return outputs, results, []


def _task_profile(mesh, report, stem, out, params):
    from ..artefacts.profiles import profile
    p = profile(mesh, planes=params["planes"], max_gap=params["max_gap"], name=stem.name)
    svg = stem.with_name(stem.name + ".profile.svg")
    p.to_svg(svg, side=params["side"])
    outputs = {"svg": _rel(out, svg)}
    if params["png"]:
        png = stem.with_name(stem.name + ".profile.png")
        p.to_png(png, side=params["side"])
        outputs["png"] = _rel(out, png)
    data = stem.with_name(stem.name + ".profile.json")
    with atomic_open(data, "w", encoding="utf-8") as fh:
        json.dump(p.to_dict(), fh)
    outputs["json"] = _rel(out, data)
    a = p.alignment
    results = {**p.measurements.to_dict(), "relative_residual": a.relative_residual,
               "up_from": a.up_from, "axis": a.axis.tolist(), "origin": a.origin.tolist()}
    reasons = []
    if not p.is_revolution:
        reasons.append(_reason("not_revolution", f"not a solid of revolution: horizontal sections stray "
                                                 f"{a.residual:.3g} mm RMS ({100 * a.relative_residual:.3g} % "
                                                 f"of the radius) from circles about the best axis; "
                                                 f"half-sections differ by up to {p.measurements.spread:.3g} mm"))
    return outputs, results, reasons


def _task_layers(mesh, report, stem, out, params):
    from ..slicing.sections import slice_layers
    layers = slice_layers(mesh, params["layer_height"], max_gap=params["max_gap"])
    path = stem.with_name(stem.name + ".layers.json")
    with atomic_open(path, "w", encoding="utf-8") as fh:
        json.dump({"layer_height": params["layer_height"],
                   "layers": [{"index": k, "z": s.z, **s.to_dict()} for k, s in enumerate(layers)]}, fh)
    n_open = sum(len(s.open_chains) for s in layers)
    results = {"layers": len(layers), "loops": sum(len(s.loops) for s in layers), "open_chains": n_open}
    reasons = [_reason("open_section", f"{n_open} open chains over the layers")] if n_open else []
    return {"json": _rel(out, path)}, results, reasons


_TASK_FUNCTIONS = {"inspect": _task_inspect, "section": _task_section, "split": _task_split,
                   "profile": _task_profile, "layers": _task_layers}


def _jsonable(x):
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else None  # JSON has no NaN
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def process_file(path, root, out, task: str, params: dict) -> dict:
    """Run one task on one file and return its report (never raises for a bad file).

    Writes the task's outputs under `out` (mirroring the file's place under
    `root`); the report itself is returned, for the caller to write.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp()); (d / "x.stl").write_bytes(b"not a mesh")
    10
    >>> r = process_file(d / "x.stl", d, d / "out", "inspect", task_parameters("inspect"))
    >>> r["status"], r["reasons"][0]["code"]
    ('fail', 'unreadable')
    """
    from ..mesh.io import load
    from ..mesh.validation import check
    t_start = time.perf_counter()
    path, root, out = Path(path), Path(root), Path(out)
    rel = path.relative_to(root).as_posix()
    report_path, stem = _paths(out, rel)
    rep = {"slicelab": __version__, "file": rel, "path": str(path.resolve()), "task": task,
           "parameters": params, "status": "fail", "reasons": [], "input": {}, "check": None,
           "results": {}, "outputs": {}, "timings": {}, "worker": f"{socket.gethostname()}:{os.getpid()}",
           "started": _now()}
    reasons, timings = rep["reasons"], rep["timings"]
    try:
        t0 = time.perf_counter()
        st = path.stat()
        rep["input"] = {"sha256": _sha256(path), "size": st.st_size, "mtime_ns": st.st_mtime_ns}
        t1 = time.perf_counter()
        mesh = load(path)
        t2 = time.perf_counter()
        report = check(mesh)
        t3 = time.perf_counter()
        timings.update(hash=t1 - t0, load=t2 - t1, check=t3 - t2)
        rep["check"] = report.to_dict()
        reasons += _mesh_reasons(report, params)
        stem.parent.mkdir(parents=True, exist_ok=True)
        outputs, results, more = _TASK_FUNCTIONS[task](mesh, report, stem, out, params)
        timings["task"] = time.perf_counter() - t3
        rep["outputs"], rep["results"] = outputs, results
        reasons += more
    except MeshFileError as exc:
        reasons.append(_reason("unreadable", exc.reason))
    except OSError as exc:
        reasons.append(_reason("unreadable", f"cannot be read ({exc.strerror or exc})"))
    except TaskUnavailable as exc:
        reasons.append(_reason("task_unavailable", str(exc)))
    except Exception as exc:  # noqa: BLE001 - one bad file must not stop the batch
        msg = str(exc).splitlines()[0] if str(exc) else ""
        reasons.append(_reason("task_error", f"{task} failed: {type(exc).__name__}: {msg}".rstrip(": ")))
    rep["status"] = _status(reasons)
    timings["total"] = time.perf_counter() - t_start
    rep["finished"] = _now()
    return _jsonable(rep)


def _lost_report(path: Path, root: Path, task: str, params: dict, why: str) -> dict:
    """The report of a file whose worker died: written by the client, retried on the next run."""
    rel = path.relative_to(root).as_posix()
    return {"slicelab": __version__, "file": rel, "path": str(path.resolve()), "task": task,
            "parameters": params, "status": "fail", "reasons": [_reason("worker_lost", why)],
            "transient": True, "input": {}, "check": None, "results": {}, "outputs": {}, "timings": {},
            "started": _now(), "finished": _now()}


def _up_to_date(report_path: Path, path: Path, out: Path, task: str, params: dict, retry_failed: bool):
    try:
        rep = json.loads(report_path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if (rep.get("slicelab") != __version__ or rep.get("task") != task or rep.get("parameters") != params
            or rep.get("transient") or rep.get("status") not in STATUSES
            or (retry_failed and rep.get("status") == "fail")):
        return None
    try:
        st = path.stat()
    except OSError:
        return None
    inp = rep.get("input") or {}
    if inp.get("size") != st.st_size:
        return None
    if inp.get("mtime_ns") != st.st_mtime_ns and inp.get("sha256") != _sha256(path):
        return None
    if not all((out / o).exists() for o in (rep.get("outputs") or {}).values()):
        return None
    return rep


def _write_report(out: Path, rep: dict) -> None:
    report_path, _ = _paths(out, rep["file"])
    with atomic_open(report_path, "w", encoding="utf-8") as fh:
        json.dump(rep, fh, indent=1, allow_nan=False)
        fh.write("\n")


def _fmt(v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.10g}"
    return str(v)


def write_summary(out, reports: list[dict], task: str) -> Path:
    """Write ``summary.csv``: one row per file, in file order, no timings (reruns give the same file).

    Examples
    --------
    >>> import tempfile
    >>> p = write_summary(tempfile.mkdtemp(), [], "inspect")
    >>> p.read_text().splitlines()[0].split(",")[:3]
    ['file', 'status', 'reasons']
    """
    cols = ["file", "status", "reasons", "messages", "sha256", "facets", "watertight", "shells",
            "size_x", "size_y", "size_z", "volume", *_SUMMARY_TASK_COLUMNS[task], "report"]
    path = Path(out) / "summary.csv"
    with atomic_open(path, "w", encoding="utf-8", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for rep in sorted(reports, key=lambda r: r["file"]):
            chk = rep.get("check") or {}
            res = rep.get("results") or {}
            lo, hi = chk.get("bounds") or (None, None)
            size = [hi[k] - lo[k] for k in range(3)] if lo is not None else [None] * 3
            row = {"file": rep["file"], "status": rep["status"],
                   "reasons": ";".join(r["code"] for r in rep["reasons"]),
                   "messages": "; ".join(r["message"] for r in rep["reasons"]),
                   "sha256": (rep.get("input") or {}).get("sha256"), "facets": chk.get("n_facets"),
                   "watertight": chk.get("watertight"), "shells": chk.get("n_shells"),
                   "size_x": size[0], "size_y": size[1], "size_z": size[2], "volume": chk.get("volume"),
                   "report": _paths(Path("."), rep["file"])[0].as_posix()}
            row.update({c: res.get(c) for c in _SUMMARY_TASK_COLUMNS[task]})
            w.writerow([_fmt(row[c]) for c in cols])
    return path


@dataclass(frozen=True)
class BatchResult:
    """What a batch did.

    Attributes
    ----------
    reports : list of dict
        One per STL file, in file order (fresh or kept from an earlier run).
    ran, skipped : int
        Files processed now, and files whose report was up to date.
    ignored : int
        Files under DIR that are not ``*.stl``.
    summary : Path
    seconds : float
    """

    reports: list = field(default_factory=list)
    ran: int = 0
    skipped: int = 0
    ignored: int = 0
    summary: Path | None = None
    seconds: float = 0.0

    def count(self, status: str) -> int:
        """Files with this status."""
        return sum(r["status"] == status for r in self.reports)

    def __str__(self) -> str:
        return (f"{len(self.reports)} STL files: {self.count('ok')} ok, {self.count('warn')} warn, "
                f"{self.count('fail')} fail ({self.ran} run, {self.skipped} up to date, "
                f"{self.ignored} other files ignored) in {self.seconds:.1f} s")


_PRELOAD = ["slicelab.tasks.batch", "slicelab.artefacts.profiles", "slicelab.artefacts.drawing",
            "slicelab.mesh.validation", "slicelab.slicing.sections", "scipy.spatial", "matplotlib.figure", "matplotlib.backends.backend_agg"]


def _pool_context():
    """Worker processes forked from a server that has imported slicelab once (forkserver).

    Not a fork of this process, which may run threads (tqdm, BLAS); not a
    spawn, which would import numpy, scipy and matplotlib again in every
    worker of every batch and re-run an unguarded __main__.
    """
    import multiprocessing
    try:
        ctx = multiprocessing.get_context("forkserver")
    except ValueError:  # no forkserver on this platform (Windows)
        return multiprocessing.get_context("spawn")
    ctx.set_forkserver_preload(_PRELOAD)
    return ctx


def _run_local(jobs, workers: int, on_done):
    """A process pool; a crash is retried alone, so it costs only its own file."""
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool
    ctx = _pool_context()
    queue = list(reversed(jobs))
    suspects = []
    while queue:
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
            running = {}
            try:
                while queue or running:
                    while queue and len(running) < 2 * workers:  # a short queue: a crash loses little
                        job = queue.pop()
                        try:
                            fut = pool.submit(process_file, *job)
                        except BrokenProcessPool:
                            queue.append(job)  # never submitted: it goes to the next pool, not astray
                            raise
                        running[fut] = job
                    done, _ = wait(running, return_when=FIRST_COMPLETED)
                    for fut in done:
                        job = running.pop(fut)
                        try:
                            rep = fut.result()
                        except BrokenProcessPool:
                            suspects.append(job)
                            raise
                        on_done(job, rep)
            except BrokenProcessPool:
                suspects += list(running.values())
    for job in suspects:  # one at a time, in a fresh process each
        with ProcessPoolExecutor(max_workers=1, mp_context=ctx) as pool:
            try:
                on_done(job, pool.submit(process_file, *job).result())
            except BrokenProcessPool:
                on_done(job, None)


def _run_dask(jobs, scheduler: str, on_done):
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise ValueError("--scheduler needs Dask: pip install 'slicelab[cluster]'") from None
    client = Client(scheduler, timeout="30s", set_as_default=False)
    try:
        futures = {client.submit(process_file, *job, pure=False,
                                 key=f"slicelab-{job[3]}-{k}-{time.time_ns()}"): job
                   for k, job in enumerate(jobs)}
        for fut in as_completed(list(futures), loop=client.loop):
            job = futures[fut]
            try:
                rep = fut.result()
            except Exception as exc:  # noqa: BLE001 - a lost worker is reported, the batch goes on
                rep = None
                job = (*job, f"the cluster lost this file: {type(exc).__name__}: {exc}")
            on_done(job, rep)
    finally:
        client.close()


def run_batch(root, out, task: str = "inspect", params: dict | None = None, *, workers: int | None = None,
              scheduler: str | None = None, force: bool = False, retry_failed: bool = False,
              progress: bool | None = None, exclude=()) -> BatchResult:
    """Run `task` over every STL file under `root`, writing reports and outputs under `out`.

    Parameters
    ----------
    root : path
        Folder searched recursively for ``*.stl``.
    out : path
        Output folder: per file ``<name>.stl.json`` (the report) and the
        task's outputs, mirroring the tree under `root`; ``summary.csv``.
    task : {"inspect", "section", "split", "profile", "layers"}
    params : dict, optional
        From `task_parameters` (defaults for `task` if omitted).
    workers : int, optional
        Local processes (default: CPU count); 1 runs in this process.
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

    Returns
    -------
    BatchResult

    Examples
    --------
    >>> import pathlib, tempfile, slicelab
    >>> from slicelab.samples import box
    >>> d = pathlib.Path(tempfile.mkdtemp()); slicelab.save(box((0, 0, 0), (10, 10, 10)), d / "in" / "cube.stl")
    >>> r = run_batch(d / "in", d / "out", "inspect", workers=1, progress=False)
    >>> r.count("ok"), r.ran, run_batch(d / "in", d / "out", "inspect", workers=1, progress=False).skipped
    (1, 1, 1)
    """
    from tqdm import tqdm
    t0 = time.perf_counter()
    root, out = Path(root), Path(out)
    if not root.is_dir():
        raise ValueError(f"{root}: not a folder")
    params = task_parameters(task) if params is None else json.loads(json.dumps(params))
    if params != task_parameters(task, **{k: v for k, v in _as_options(params).items()}):
        raise ValueError(f"parameters do not fit the {task} task: {params}")
    out.mkdir(parents=True, exist_ok=True)
    files, ignored = find_stl_files(root, exclude=out, patterns=tuple(exclude))
    reports: dict[str, dict] = {}
    jobs = []
    for path in files:
        rel = path.relative_to(root).as_posix()
        kept = None if force else _up_to_date(_paths(out, rel)[0], path, out, task, params, retry_failed)
        if kept is not None:
            reports[rel] = kept
        else:
            jobs.append((str(path), str(root), str(out), task, params))
    bar = tqdm(total=len(files), initial=len(files) - len(jobs), unit="file", desc=f"slicelab {task}",
               disable=(not sys.stderr.isatty()) if progress is None else not progress, file=sys.stderr)

    def on_done(job, rep):
        if rep is None:
            why = job[5] if len(job) > 5 else ("the worker process died while processing this file (out of "
                                               "memory? or run_batch called from a script without an "
                                               "`if __name__ == '__main__':` guard)")
            rep = _lost_report(Path(job[0]), Path(job[1]), task, params, why)
        _write_report(out, rep)
        reports[rep["file"]] = rep
        bar.update(1)
        bar.set_postfix_str(f"{rep['file']}: {rep['status']}", refresh=False)

    try:
        if not jobs:
            pass
        elif scheduler:
            _run_dask(jobs, scheduler, on_done)
        elif (workers or os.cpu_count() or 1) <= 1 or len(jobs) == 1:
            for job in jobs:  # in this process: simplest to debug, no start-up cost
                on_done(job, process_file(*job))
        else:
            _run_local(jobs, min(int(workers or os.cpu_count() or 1), len(jobs)), on_done)
    finally:
        bar.close()
        ordered = [reports[k] for k in sorted(reports)]
        summary = write_summary(out, ordered, task)
    return BatchResult(ordered, len(jobs), len(files) - len(jobs), ignored, summary, time.perf_counter() - t0)


def _as_options(params: dict) -> dict:
    """`task_parameters` keyword arguments that reproduce `params`."""
    o = {k: v for k, v in params.items() if k != "plane"}
    if params.get("plane"):
        o["origin"], o["normal"] = params["plane"]["origin"], params["plane"]["normal"]
    return o
