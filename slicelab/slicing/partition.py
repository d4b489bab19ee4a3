"""Partition a part too big for the printer into closed printable pieces, with flat or stair joints.

`partition` cuts recursively until every piece fits the build volume: a
piece that does not fit is cut across the axis that needs the most pieces,
at the candidate position with the smallest section, with a flat joint
(`slicelab.slicing.cut.cut`) or an interlocking stair joint
(`slicelab.slicing.stair.stair_cut`); separate bodies are separated, not
cut; pieces may be turned about z to fit (`fit_rotation`). `Partition`
holds the pieces and a `PartitionReport` (`Piece` and `Joint` records).

See Also
--------
slicelab.slicing.cut.cut : the flat cut.
slicelab.slicing.stair.stair_cut : the stair joint.
slicelab.viz.plot_exploded : the pieces pushed apart, in a figure.

References
----------
.. [1] L. Luo, I. Baran, S. Rusinkiewicz, W. Matusik, "Chopper: partitioning
   models into 3D-printable parts", ACM Transactions on Graphics 31(6)
   (SIGGRAPH Asia), 2012 (recursive planar cuts until every part fits the
   printing volume; there a beam search over the cuts, here a greedy choice
   per piece).
.. [2] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development of
   slicing algorithm for rapid prototyping building about big sized objects"
   (cutting big solids into glued parts; stair-shaped joints).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..geometry.topology import manifold_summary, shells, weld
from ..mesh.core import Mesh
from ..mesh.validation import signed_volume
from .cut import cut
from .sections import section
from .placement import Placement, place_for_printing
from .stair import StairCutError, axis_plane, stair_cut

__all__ = ["Joint", "Piece", "PartitionReport", "Partition", "partition"]

_AXES = "xyz"


# ------------------------------------------------------------------ reports
@dataclass(frozen=True)
class Joint:
    """One cut of a partition.

    Attributes
    ----------
    axis : int
        0, 1, 2 for a cut across x, y, z.
    position : float
        The flat plane (mm); a stair's treads lie at ``position`` and beyond.
    kind : str
        ``"flat"`` or ``"stair"`` (or ``"flat (stair failed)"``).
    flat_area : float
        Area of the flat section at `position` (mm^2).
    glue_area : float
        Area of the faces that are glued, on one part (mm^2).
    step_axis : int or None
        In-plane axis along which the stair's bands run.
    step : tuple or None
        (height, depth) of the stair's steps as built (mm).
    """

    axis: int
    position: float
    kind: str
    flat_area: float
    glue_area: float
    step_axis: int | None = None
    step: tuple | None = None

    @property
    def ratio(self) -> float:
        """Glue area over the flat section's area."""
        return self.glue_area / self.flat_area if self.flat_area > 0 else float("nan")


@dataclass(frozen=True)
class Piece:
    """A piece of a partition: its size and how it sits in the printer.

    Attributes
    ----------
    size : tuple of float
        Bounding-box size (x, y, z) as placed for printing (mm).
    rotation : float
        Turn about z (degrees) after it is laid down.
    volume : float
        mm^3.
    watertight : bool
        Every edge shared by two facets walking it opposite ways.
    n_facets : int
    placement : Placement
        The rigid motion from the part's coordinates to the printer's: a flat
        cut face down where there is one, turned to fit, centred on the bed.
    """

    size: tuple
    rotation: float
    volume: float
    watertight: bool
    n_facets: int
    placement: Placement | None = None


@dataclass(frozen=True)
class PartitionReport:
    """What `partition` made: pieces, joints and glue area."""

    build_volume: tuple
    joint: str
    clearance: float
    pieces: list = field(default_factory=list)
    joints: list = field(default_factory=list)

    @property
    def glue_area(self) -> float:
        """Glue area of all joints (one side each, mm^2)."""
        return float(sum(j.glue_area for j in self.joints))

    @property
    def flat_area(self) -> float:
        """What flat cuts at the same positions would have given (mm^2)."""
        return float(sum(j.flat_area for j in self.joints))

    @property
    def watertight(self) -> bool:
        return all(p.watertight for p in self.pieces)

    def describe(self, watertight=None) -> str:
        """A small table for people; `watertight` (one bool a piece) replaces the in-memory
        check, e.g. by the check of each piece's file as written."""
        tight = [p.watertight for p in self.pieces] if watertight is None else list(watertight)
        bx = "x".join(f"{v:g}" for v in self.build_volume)
        lines = [f"{len(self.pieces)} pieces for a {bx} mm build volume, {self.joint} joints, "
                 f"clearance {self.clearance:g} mm; glue area {self.glue_area:.6g} mm2 "
                 f"(flat cuts: {self.flat_area:.6g} mm2)",
                 "piece  size x y z (mm)               turn   volume (mm3)   facets  watertight"]
        for k, (p, ok) in enumerate(zip(self.pieces, tight)):
            size = " x ".join(f"{v:7.2f}" for v in p.size)
            lines.append(f"{k:5d}  {size}  {p.rotation:5.1f}  {p.volume:13.6g}  {p.n_facets:7d}  "
                         f"{'yes' if ok else 'NO'}")
        lines.append("joint  axis  position   kind        flat (mm2)   glue (mm2)  ratio")
        for k, j in enumerate(self.joints):
            lines.append(f"{k:5d}  {_AXES[j.axis]:>4}  {j.position:9.3f}  {j.kind:<10}  {j.flat_area:11.6g}  "
                         f"{j.glue_area:11.6g}  {j.ratio:5.2f}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"build_volume": list(self.build_volume), "joint": self.joint, "clearance": self.clearance,
                "glue_area": self.glue_area, "flat_area": self.flat_area,
                "pieces": [{"size": list(p.size), "rotation": p.rotation, "volume": p.volume,
                            "watertight": p.watertight, "n_facets": p.n_facets,
                            "placement": None if p.placement is None else p.placement.to_dict()}
                           for p in self.pieces],
                "joints": [{"axis": _AXES[j.axis], "position": j.position, "kind": j.kind,
                            "flat_area": j.flat_area, "glue_area": j.glue_area, "ratio": j.ratio,
                            "step_axis": None if j.step_axis is None else _AXES[j.step_axis],
                            "step": None if j.step is None else list(j.step)} for j in self.joints]}

@dataclass(frozen=True, eq=False)
class Partition:
    """The pieces of a partition, and the `report` of how they were made.

    Attributes
    ----------
    pieces : tuple of Mesh
        In the part's own coordinates: they assemble into the input.
    report : PartitionReport
        Each piece's size, turn and volume (in the order of `pieces`), each
        joint's flat and glue area.

    ``len(partition)`` counts the pieces and iterating gives them.
    """

    pieces: tuple
    report: PartitionReport

    def __len__(self) -> int:
        return len(self.pieces)

    def __iter__(self):
        return iter(self.pieces)

    def __repr__(self) -> str:
        r = self.report
        return (f"Partition({len(self.pieces)} pieces, {len(r.joints)} joints ({r.joint}), "
                f"glue area {r.glue_area:.6g} mm2)")


# ------------------------------------------------------------------ fitting
def _counts(e: np.ndarray, V: np.ndarray, margin: float) -> np.ndarray:
    step = V - margin
    return np.where(e <= V, 1, np.ceil((e - margin) / np.maximum(step, 1e-300))).astype(int)


def _components(t: np.ndarray) -> tuple[int, np.ndarray]:
    """Facets grouped into edge-connected shells: (count, label of each facet)."""
    if len(t) == 0:
        return 0, np.zeros(0, np.int64)
    return shells(weld(t)[1])


def _n_shells(t: np.ndarray) -> int:
    return _components(t)[0]


def _bodies(m: Mesh) -> list[Mesh]:
    """Split a part into separate bodies: each outer shell with the cavities inside it.

    A shell of negative volume (a cavity) goes with the smallest outer shell
    whose box holds it; anything unclear stays together.
    """
    k, lab = _components(m.triangles)
    if k < 2:
        return [m]
    t = m.triangles
    order = np.argsort(lab, kind="stable")
    cuts = np.searchsorted(lab[order], np.arange(k + 1))
    shell_facets = [t[order[cuts[i]:cuts[i + 1]]] for i in range(k)]
    vol = np.array([signed_volume(s) for s in shell_facets])
    box = np.array([[s.reshape(-1, 3).min(axis=0), s.reshape(-1, 3).max(axis=0)] for s in shell_facets])
    outer = np.flatnonzero(vol > 0)
    if len(outer) < 2:
        return [m]
    groups = {int(i): [i] for i in outer}
    for i in np.flatnonzero(vol <= 0):  # cavities: into the smallest outer shell around them
        holds = [j for j in outer if np.all(box[j, 0] <= box[i, 0]) and np.all(box[i, 1] <= box[j, 1])]
        if not holds:
            return [m]
        groups[int(min(holds, key=lambda j: vol[j]))].append(i)
    # Outer shells inside another's box may be islands in its cavity: keep those together.
    merged = {}
    for j in sorted(groups, key=lambda j: -vol[j]):
        home = next((r for r in merged if np.all(box[r, 0] <= box[j, 0]) and np.all(box[j, 1] <= box[r, 1])), None)
        if home is None:
            merged[j] = list(groups[j])
        else:
            merged[home] += groups[j]
    if len(merged) < 2:
        return [m]
    return [Mesh(np.concatenate([shell_facets[i] for i in members])) for members in merged.values()]


# ------------------------------------------------------------------ partition
def partition(mesh: Mesh, build_volume=(200.0, 200.0, 200.0), *, joint: str = "flat", clearance: float = 0.0,
              step=(10.0, 20.0), flight: int = 1, rotate: bool = True, candidates: int = 9,
              max_pieces: int = 512) -> Partition:
    """Cut a solid recursively until every piece fits the build volume.

    Each piece that does not fit is cut across the axis that needs the most
    pieces (``ceil(size / usable build size)``, with the part turned by 90
    degrees about z when that needs fewer), at the position, among
    `candidates` spread over the range that keeps that count, whose section
    is smallest. Pieces may be turned about z to fit (`rotate`).

    Parameters
    ----------
    mesh : Mesh
        Watertight, normals outward (check it first with `slicelab.check`).
    build_volume : (X, Y, Z)
        The printer's build volume (mm).
    joint : {"flat", "stair"}
        Flat cuts, or stair joints (`stair_cut`) that interlock and at least
        double the glue area for the default step. A stair that would not
        close, or would leave loose fragments, falls back to a flat cut (see
        the report's joints).
    clearance : float, default 0
        Glue gap between mating faces (mm); the upper piece is cut back.
    step, flight
        The stair's (height, depth) and flight, as in `stair_cut`.
    rotate : bool, default True
        Allow turning pieces about z to fit.
    candidates : int, default 9
        Cut positions tried per cut.
    max_pieces : int, default 512
        Safety limit.

    Returns
    -------
    Partition
        ``pieces``, `Mesh` in the part's own coordinates (they assemble into
        the input), and ``report`` (`PartitionReport`): each piece's size,
        turn and volume, each joint's flat and glue area.

    See Also
    --------
    slicelab.slicing.cut.cut : the flat cut of each joint.
    slicelab.slicing.stair.stair_cut : the stair joint.
    slicelab.slicing.placement.place_for_printing : how each piece is laid on the bed.
    slicelab.viz.save_exploded_png : a picture of the pieces pushed apart.

    References
    ----------
    .. [1] L. Luo, I. Baran, S. Rusinkiewicz, W. Matusik, "Chopper:
       partitioning models into 3D-printable parts", ACM Transactions on
       Graphics 31(6) (SIGGRAPH Asia), 2012.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> parts = partition(box((0, 0, 0), (300, 120, 80)), (200, 200, 200))
    >>> len(parts.pieces), [p.watertight for p in parts.report.pieces]
    (2, [True, True])
    >>> round(sum(p.volume for p in parts.report.pieces), 6)
    2880000.0
    """
    V = np.asarray(build_volume, dtype=np.float64).reshape(-1)
    if V.shape != (3,) or not np.all(np.isfinite(V)) or np.any(V <= 0):
        raise ValueError(f"build volume must be three positive sizes, got {build_volume!r}")
    if joint not in ("flat", "stair"):
        raise ValueError(f"joint must be 'flat' or 'stair', got {joint!r}")
    if not (clearance >= 0 and np.isfinite(clearance)):
        raise ValueError(f"clearance must be >= 0, got {clearance!r}")
    h, d = (float(v) for v in step)
    margin = clearance + (flight * d if joint == "stair" else 0.0)
    if np.any(V <= margin):
        raise ValueError(f"the joint ({margin:g} mm deep with clearance) does not fit the build volume")
    if len(mesh) == 0:
        raise ValueError("the mesh has no facets")

    done, joints = [], []
    pending = [mesh]
    while pending:  # over pieces
        m = pending.pop()
        placed = place_for_printing(m, V, rotate=rotate)
        if placed is not None:
            done.append((m, placed))
            continue
        bodies = _bodies(m)
        if len(bodies) > 1:  # separate bodies are printed apart: no cut needed between them
            pending += bodies
            continue
        if len(done) + len(pending) + 2 > max_pieces:
            raise ValueError(f"more than {max_pieces} pieces needed: is the build volume right?")
        axis, V_axis, n = _plan(m, V, margin, rotate)
        lo, hi = m.bounds[:, axis]
        usable = V_axis - margin
        w0, w1 = hi - (n - 1) * usable, lo + usable
        pad = 1e-3 * (w1 - w0) if w1 > w0 else 0.0
        pos = np.linspace(w0 + pad, w1 - pad, max(int(candidates), 1)) if w1 > w0 else np.array([(w0 + w1) / 2])
        areas = np.array([section(m, *axis_plane(axis, p), max_gap=0.0).area for p in pos])
        order = np.argsort(areas + 1e-9 * np.abs(pos - (w0 + w1) / 2), kind="stable")
        best = float(pos[order[0]])
        rear, front, jt = _cut_joint(m, axis, best, joint, clearance, (h, d), flight)
        joints.append(jt)
        pending += [p for p in (front, rear) if len(p)]

    pieces = [m for m, _ in done]
    infos = []
    for m, placed in done:  # over pieces
        infos.append(Piece(placed.size, placed.turn, signed_volume(m.triangles),
                           manifold_summary(m.triangles).closed, len(m), placed))
    report = PartitionReport(tuple(float(v) for v in V), joint, float(clearance), infos, joints)
    return Partition(tuple(pieces), report)


def _plan(m: Mesh, V: np.ndarray, margin: float, rotate: bool):
    """Axis to cut, its build size, and how many pieces it needs along it."""
    e = np.ptp(m.triangles.reshape(-1, 3), axis=0)
    options = [V] + ([V[[1, 0, 2]]] if rotate else [])
    best = None
    for W in options:  # as it lies, turned by 90 degrees
        n = _counts(e, W, margin)
        key = (int(np.prod(n)), -int(n.max()))
        if best is None or key < best[0]:
            best = (key, W, n)
    _, W, n = best
    cand = np.flatnonzero(n == n.max())
    axis = int(cand[np.argmax(e[cand] / W[cand])])
    return axis, float(W[axis]), int(n[axis])


def _cut_joint(m: Mesh, axis: int, pos: float, joint: str, clearance: float, step, flight: int):
    plane = axis_plane(axis, pos)
    flat_area = section(m, *plane, max_gap=0.0).area
    kind = "flat"
    if joint == "stair":
        # Teeth that cross a hole can leave loose fragments: try the other phase and the
        # other step axis, and keep the first stair with no more bodies than a flat cut.
        flat_shells = None
        others = [k for k in range(3) if k != axis]
        for step_axis in (None, *others):
            for phase in (0, 1):
                h = float(step[0])
                for _ in range(3):  # narrower bands add risers where the glue area falls short of 2x
                    try:
                        sc = stair_cut(m, axis, pos, step=(h, step[1]), flight=flight, step_axis=step_axis,
                                       phase=phase, clearance=clearance)
                    except (StairCutError, ValueError):
                        sc = None
                        break
                    ratio = sc.glue_area / sc.flat_area if sc.flat_area > 0 else 0.0
                    if ratio >= 2.0 or ratio <= 1.0:
                        break
                    h = min(sc.step[0], h) * (ratio - 1.0) / 1.15
                if sc is None:
                    continue
                if flat_shells is None:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        flat = cut(m, *plane)
                    flat_shells = _n_shells(flat.rear.triangles) + _n_shells(flat.front.triangles)
                if _n_shells(sc.rear.triangles) + _n_shells(sc.front.triangles) <= flat_shells:
                    return sc.rear, sc.front, Joint(axis, pos, "stair", sc.flat_area, sc.glue_area,
                                                    sc.step_axis, tuple(float(v) for v in sc.step))
        kind = "flat (stair failed)"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = cut(m, *plane)
        front = res.front
        if clearance > 0:
            front = cut(m, *axis_plane(axis, pos + clearance)).front
    return res.rear, front, Joint(axis, pos, kind, flat_area, res.report.rear_cap.area)
