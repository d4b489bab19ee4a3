"""What a job is: its checked parameters, its input, where it writes and what it reports.

A `Job` bundles four functions and two tables: ``parameters`` checks and
normalises keyword arguments into plain JSON values (raising `ParameterError`,
which names the parameter), ``compute`` turns a `JobInput` into a value,
``write`` writes that value's files through `Outputs`, ``report`` turns it
into a results dict and a list of reasons; ``outputs`` names the files (the
same names whoever runs the job), ``columns`` the results a batch summary
keeps. `slicelab.tasks.jobs` defines the jobs and runs them.
"""
from __future__ import annotations

import contextlib
import inspect
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["ParameterError", "number", "whole", "choice", "vector", "plane", "resolve_plane", "reason", "plain",
           "JobInput", "Outputs", "JobResult", "Job", "drawn_meanwhile"]


class ParameterError(ValueError):
    """A job parameter that makes no sense; the message begins with the parameter's name.

    Examples
    --------
    >>> e = ParameterError("max_gap", "must be a number >= 0, got -1")
    >>> str(e), e.name
    ('max_gap must be a number >= 0, got -1', 'max_gap')
    """

    def __init__(self, name: str, problem: str):
        super().__init__(f"{name} {problem}")
        self.name, self.problem = name, problem

    def __reduce__(self):
        return type(self), (self.name, self.problem)


# ------------------------------------------------------------------ checkers
def number(name: str, value, *, low: float | None = None, positive: bool = False) -> float:
    """`value` as a finite float, at least `low` or above zero when `positive`.

    Examples
    --------
    >>> number("max_gap", "1.5", low=0)
    1.5
    >>> number("layer_height", 0, positive=True)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: layer_height must be a positive number, got 0
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if positive and not (v > 0 and math.isfinite(v)):
        raise ParameterError(name, f"must be a positive number, got {value!r}")
    if low is not None and not (v >= low and math.isfinite(v)):
        raise ParameterError(name, f"must be a number >= {low:g}, got {value!r}")
    if not math.isfinite(v):
        raise ParameterError(name, f"must be a finite number, got {value!r}")
    return v


def whole(name: str, value, *, low: int = 0) -> int:
    """`value` as an int of at least `low` (a float with a fraction is refused).

    Examples
    --------
    >>> whole("planes", 3.0, low=1)
    3
    >>> whole("planes", 0, low=1)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: planes must be a whole number >= 1, got 0
    """
    ok = isinstance(value, (int, np.integer, float)) and not isinstance(value, bool) \
        and math.isfinite(value) and float(value).is_integer() and value >= low
    if not ok:
        raise ParameterError(name, f"must be a whole number >= {low}, got {value!r}")
    return int(value)


def choice(name: str, value, options) -> str:
    """`value` if it is one of `options`.

    Examples
    --------
    >>> choice("side", "middle", ("left", "right"))
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: side must be 'left' or 'right', got 'middle'
    """
    if value not in options:
        raise ParameterError(name, f"must be {' or '.join(map(repr, options))}, got {value!r}")
    return value


def vector(name: str, value, *, size: int = 3, nonzero: bool = False, positive: bool = False) -> list:
    """`value` as a list of `size` finite floats (not all zero, or all positive, if asked).

    Examples
    --------
    >>> vector("normal", (0, 0, 2), nonzero=True)
    [0.0, 0.0, 2.0]
    >>> vector("normal", (0, 0, 0), nonzero=True)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: normal must not be the zero vector
    """
    try:
        v = np.asarray(value, float).reshape(size)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be {size} numbers, got {value!r}") from None
    if not np.all(np.isfinite(v)):
        raise ParameterError(name, f"must be {size} finite numbers, got {value!r}")
    if nonzero and not np.any(v):
        raise ParameterError(name, "must not be the zero vector")
    if positive and not np.all(v > 0):
        raise ParameterError(name, f"must be {size} positive numbers, got {value!r}")
    return [float(x) for x in v]


def plane(value) -> dict | None:
    """A plane given as None, ``(origin, normal)`` or ``{"origin": ..., "normal": ...}``, as plain lists.

    None stands for the horizontal plane at the part's mid-height.

    Examples
    --------
    >>> plane(((0, 0, 5), (0, 0, 2)))
    {'origin': [0.0, 0.0, 5.0], 'normal': [0.0, 0.0, 2.0]}
    >>> plane(None) is None
    True
    """
    if value is None:
        return None
    if isinstance(value, Mapping):
        origin, normal = value.get("origin"), value.get("normal")
    else:
        try:
            origin, normal = value
        except (TypeError, ValueError):
            raise ParameterError("plane", f"must be (origin, normal), got {value!r}") from None
    return {"origin": vector("origin", origin), "normal": vector("normal", normal, nonzero=True)}


def resolve_plane(mesh, p: dict | None) -> tuple[np.ndarray, np.ndarray]:
    """The plane of a ``plane`` parameter: as given, or horizontal at the mesh's mid-height when None.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> [v.tolist() for v in resolve_plane(box((0, 0, 0), (1, 1, 4)), None)]
    [[0.0, 0.0, 2.0], [0.0, 0.0, 1.0]]
    """
    if p:
        return np.array(p["origin"], float), np.array(p["normal"], float)
    z = mesh.triangles[..., 2]
    return np.array([0.0, 0.0, (float(z.min()) + float(z.max())) / 2]), np.array([0.0, 0.0, 1.0])


def reason(code: str, message: str) -> dict:
    """Why a file is not simply "ok": a short code and a sentence.

    Examples
    --------
    >>> reason("open_section", "the section has 2 open chains")["code"]
    'open_section'
    """
    return {"code": code, "message": message}


def plain(x):
    """`x` with numpy scalars made Python numbers and NaN or infinity made None (JSON has neither).

    Examples
    --------
    >>> plain({"a": np.float64("nan"), "b": [np.int64(2), (np.bool_(True),)]})
    {'a': None, 'b': [2, [True]]}
    """
    if isinstance(x, Mapping):
        return {k: plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [plain(v) for v in x]
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, np.ndarray):
        return plain(x.tolist())
    return x


# ------------------------------------------------------------------ the parts
@dataclass(frozen=True)
class JobInput:
    """A job's input: the file it came from, the mesh, its check (computed once, when asked) and,
    when the mesh was repaired on the way in, the `slicelab.mesh.RepairReport`.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> JobInput(Path("cube.stl"), box()).check.watertight
    True
    """

    path: Path
    mesh: Any = field(repr=False)
    given_check: Any = field(default=None, repr=False)
    repair: Any = field(default=None, repr=False)

    @cached_property
    def check(self):
        """The mesh's `slicelab.mesh.MeshReport`."""
        if self.given_check is not None:
            return self.given_check
        from ..mesh import check
        return check(self.mesh)


class Outputs:
    """Where a job writes: its own file names under `folder`, or paths given for some roles.

    Every path handed out is recorded in `written` (role -> path, or a list of paths
    for a role that names many files, such as one SVG per layer).

    Examples
    --------
    >>> o = Outputs({"svg": "section.svg"}, Path("out"), {"png": Path("p.png")})
    >>> o.path("svg").as_posix(), o.path("png").as_posix(), o.path("layer", "layer_0.svg").as_posix()
    ('out/section.svg', 'p.png', 'out/layer_0.svg')
    >>> sorted(o.written)
    ['layer', 'png', 'svg']
    """

    def __init__(self, names: Mapping[str, str], folder=None, paths: Mapping | None = None):
        self.names = dict(names)
        self.folder = None if folder is None else Path(folder)
        self.paths = {k: Path(v) for k, v in (paths or {}).items() if v is not None}
        self.written: dict[str, Path | list[Path]] = {}

    def _under(self, name: str) -> Path:
        if self.folder is None:
            raise ValueError(f"no output folder for {name}")
        return self.folder / name

    def path(self, role: str, name: str | None = None) -> Path:
        """The path to write `role` to; with `name`, one more file of a many-file role."""
        if name is not None:
            p = self._under(name)
            self.written.setdefault(role, []).append(p)
            return p
        p = self.paths.get(role) or self._under(self.names[role])
        self.written[role] = p
        return p

    def record(self, role: str, paths) -> None:
        """Record files a writer named itself (a many-file role)."""
        self.written.setdefault(role, []).extend(Path(p) for p in paths)

    def moved(self, where: Mapping) -> None:
        """Rename the paths recorded by `where` ({old: new}: the staged files moved into place)."""
        def new(p):
            return where.get(p, p)
        self.written = {k: [new(p) for p in v] if isinstance(v, list) else new(v) for k, v in self.written.items()}


@dataclass(frozen=True)
class JobResult:
    """What a job did: its outputs, results (plain JSON values), reasons and timings.

    Attributes
    ----------
    name : str
        The job.
    source : Path
        The input file.
    parameters : dict
        The checked parameters.
    outputs : dict
        Role -> path written (a list of paths for many-file roles).
    results : dict
        Plain numbers for JSON.
    reasons : list of dict
        Warnings found by the job (`reason`), for a batch report's status.
    timings : dict
        Seconds: ``load`` (when the job loaded the file), ``compute``, ``write``.
    n_facets : int
        Facets of the input mesh.
    value : object
        What ``compute`` made (a `Section`, `Split`, `Profile`...), for printing.
    """

    name: str
    source: Path
    parameters: dict
    outputs: dict
    results: dict
    reasons: list
    timings: dict
    n_facets: int
    value: Any = field(default=None, repr=False)

    def files(self) -> list[Path]:
        """Every file written, in role order."""
        out = []
        for v in self.outputs.values():
            out += v if isinstance(v, list) else [v]
        return out

    def relative_outputs(self, root) -> dict:
        """`outputs` as POSIX paths relative to `root` (for a report)."""
        root = Path(root)

        def rel(p):
            return Path(p).relative_to(root).as_posix()
        return {k: [rel(p) for p in v] if isinstance(v, list) else rel(v) for k, v in self.outputs.items()}


@dataclass(frozen=True)
class Job:
    """One job on a mesh file, defined once for the command line and batches.

    Attributes
    ----------
    name : str
    description : str
        One line.
    parameters : callable
        Keyword arguments -> checked dict of plain JSON values; its signature
        gives the parameter names and defaults, and checking is idempotent
        (``parameters(**parameters(...))`` returns the same dict).
    outputs : mapping
        Output role -> file name (a pattern for many-file roles).
    compute : callable
        ``(JobInput, params) -> value``.
    write : callable
        ``(value, JobInput, params, Outputs) -> dict or None``; every file is
        written atomically. A dict returned holds results about the files as
        written (their own checks), added to the report's.
    report : callable
        ``(value, JobInput, params) -> (results, reasons)``.
    columns : tuple of str
        Results a batch's ``summary.csv`` keeps.
    feasible : callable, optional
        ``(JobInput, params) -> None``: raises `ParameterError` when the
        parameters ask more of this part than can be done (`slicelab.tasks.limits`).
    """

    name: str
    description: str
    parameters: Callable[..., dict]
    outputs: Mapping[str, str]
    compute: Callable
    write: Callable
    report: Callable
    columns: tuple = ()
    feasible: Callable | None = None

    @property
    def defaults(self) -> dict:
        """Parameter name -> default (``**kwargs`` left out)."""
        return {k: p.default for k, p in inspect.signature(self.parameters).parameters.items()
                if p.kind is not inspect.Parameter.VAR_KEYWORD}

    def check_parameters(self, **options) -> dict:
        """`parameters` applied to `options`, refusing names the job does not take (a job whose
        `parameters` takes ``**kwargs`` checks those names itself)."""
        names = self.defaults
        open_ended = any(p.kind is inspect.Parameter.VAR_KEYWORD
                         for p in inspect.signature(self.parameters).parameters.values())
        for key in options:
            if key not in names and not open_ended:
                raise ParameterError(key, f"is not a parameter of the {self.name} job "
                                          f"(it takes {', '.join(names) or 'none'})")
        return plain(self.parameters(**options))


@contextlib.contextmanager
def drawn_meanwhile(draw: Callable | None, *args, **kwargs):
    """``draw(*args, **kwargs)`` run on a thread while the block runs (nothing if `draw` is None).

    A job's picture (projecting and depth-testing a million facets) and the
    writing of its parts (packing, writing and checking STL files) are both
    numpy work on large arrays that lets go of the GIL: on two cores the
    picture then costs little more than the writing alone. An error in the
    drawing is raised when the block is done.

    Examples
    --------
    >>> seen = []
    >>> with drawn_meanwhile(seen.append, "picture"):
    ...     seen.append("parts")
    >>> sorted(seen)
    ['parts', 'picture']
    >>> def broken():
    ...     raise OSError("no room for the picture")
    >>> with drawn_meanwhile(broken):
    ...     seen.append("more parts")
    Traceback (most recent call last):
    OSError: no room for the picture
    >>> seen[-1]
    'more parts'
    """
    if draw is None:
        yield
        return
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(max_workers=1) as pool:
        done = pool.submit(draw, *args, **kwargs)
        yield
        done.result()
