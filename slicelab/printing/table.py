"""A layer's toolpaths as a table: one row per path, its kind, polyline and width, in print order.

The slicer design's lists (``external_contour_segments``,
``internal_contour_segments``, ``filling_segments``) and one list per role are
views of the table; writers (`slicelab.gcode.writer`, the SVGs and plots of
`slicelab.viz`) read its rows.

See Also
--------
slicelab.printing.pipeline.layer_paths : makes the table of a layer.
slicelab.printing.roles : the kinds and roles, their G-code words and colours.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from .roles import KINDS, ROLE_OF

__all__ = ["LayerPaths"]


@dataclass(frozen=True, eq=False)
class LayerPaths:
    """Toolpaths of one layer: a table with one row per path, in print order.

    Each row is an extrusion: its kind (one of `slicelab.printing.roles.KINDS`:
    skirt, brim, support and its interface, outer perimeter, hole wall, inner
    perimeter, gap fill, sparse, solid, top and bridge infill), its polyline and
    its width. Row order
    is print order. The lists of the slicer design (``external_contour_segments``,
    ``internal_contour_segments``, ``filling_segments``) and the others are
    views of the table, one per role (`slicelab.printing.roles.ROLES`).

    Attributes
    ----------
    kind : tuple of str
        Each row's kind.
    paths : tuple of (k, 2) ndarray
        Each row's polyline (mm); loops are closed (first point repeated).
    widths : tuple of float or (k,) ndarray
        Each row's extrusion width (mm), or its width at each vertex (gap fill).
    travel_length : float
        Length of the moves between consecutive paths (mm).
    line_width : float
    z : float
        Height of the section (NaN if not horizontal).
    thin_walls : int
        Islands too thin for one perimeter (printed as gap fill only).
    hang : tuple of (None or (k - 1,) bool ndarray)
        Per row, which of its segments lie over nothing (overhang perimeters,
        `slicelab.printing.steps.overhangs.mark_overhangs`); empty when none was marked.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> lp = slicelab.layer_paths(s, slicelab.PrintSettings(infill_density=1.0, pixel_size=0.1))
    >>> lp.kind
    ('internal', 'external', 'sparse')
    >>> len(lp), [len(v) for v in (lp.external_contour_segments, lp.internal_contour_segments,
    ...                            lp.filling_segments)]
    (3, [1, 1, 1])
    """

    kind: tuple
    paths: tuple
    widths: tuple
    travel_length: float
    line_width: float
    z: float = float("nan")
    thin_walls: int = 0
    hang: tuple = ()

    def __post_init__(self):
        unknown = set(self.kind) - set(KINDS)
        if unknown:
            raise ValueError(f"unknown path kinds {sorted(unknown)}; expected some of {KINDS}")
        if not len(self.kind) == len(self.paths) == len(self.widths):
            raise ValueError("kind, paths and widths need one entry per row")
        if self.hang and len(self.hang) != len(self.kind):
            raise ValueError("hang needs one entry per row (or none at all)")

    def __len__(self) -> int:
        return len(self.kind)

    def __repr__(self) -> str:
        return (f"LayerPaths(z={self.z:g}, {len(self.external_contour_segments)} external, "
                f"{len(self.internal_contour_segments)} internal, {len(self.filling_segments)} filling, "
                f"{len(self.gap_fill_segments)} gap fill, extrusion {self.extrusion_length:.1f} mm, "
                f"travel {self.travel_length:.1f} mm)")

    @classmethod
    def from_rows(cls, rows, **kw) -> "LayerPaths":
        """A table from (kind, path, width) rows in print order; `kw` fills the other fields."""
        rows = list(rows)
        return cls(tuple(r[0] for r in rows), tuple(r[1] for r in rows), tuple(r[2] for r in rows), **kw)

    def pieces(self):
        """Yield (kind, polyline, width) in print order, each row cut where it starts or stops
        hanging over nothing: those stretches come as kind ``"overhang"``. Consecutive pieces of a
        row share their end points, so they print as one move."""
        hang = self.hang or (None,) * len(self.kind)
        for k, q, w, h in zip(self.kind, self.paths, self.widths, hang):
            if h is None or not np.any(h):
                yield k, q, w
                continue
            cuts = np.flatnonzero(np.diff(h.astype(np.int8))) + 1  # segment index where a run starts
            for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(h)]):  # over the runs, few
                ww = w if np.ndim(w) == 0 else w[a:b + 1]
                yield ("overhang" if h[a] else k), q[a:b + 1], ww

    def rows(self, kinds=None):
        """Yield (kind, polyline, width) in print order, of the given kinds only if given."""
        for k, q, w in zip(self.kind, self.paths, self.widths):
            if kinds is None or k in kinds:
                yield k, q, w

    def inserted(self, at: int, rows) -> "LayerPaths":
        """The table with (kind, polyline, width) rows put before row `at`, the travel counted again.

        Examples
        --------
        >>> lp = LayerPaths(("external",), (np.array([[0.0, 0], [1, 0], [1, 1], [0, 0]]),), (0.4,), 0.0, 0.4)
        >>> more = lp.inserted(0, [("skirt", np.array([[5.0, 0], [5, 5]]), 0.4)])
        >>> more.kind, round(more.travel_length, 3)
        (('skirt', 'external'), 7.071)
        """
        rows = list(rows)
        if not rows:
            return self
        paths = self.paths[:at] + tuple(r[1] for r in rows) + self.paths[at:]
        travel = float(sum(np.hypot(*(b[0] - a[-1])) for a, b in zip(paths, paths[1:])))
        return replace(self, kind=self.kind[:at] + tuple(r[0] for r in rows) + self.kind[at:], paths=paths,
                       widths=self.widths[:at] + tuple(r[2] for r in rows) + self.widths[at:],
                       hang=(self.hang[:at] + (None,) * len(rows) + self.hang[at:]) if self.hang else (),
                       travel_length=travel)

    def role_list(self, role: str) -> list:
        """The paths of one role (one of `slicelab.printing.roles.ROLES`), in print order."""
        return [q for k, q in zip(self.kind, self.paths) if ROLE_OF[k] == role]

    @property
    def external_contour_segments(self) -> list:
        """Closed polylines, one per island's outer boundary."""
        return self.role_list("external")

    @property
    def internal_contour_segments(self) -> list:
        """Closed polylines: hole boundaries and inner perimeters."""
        return self.role_list("internal")

    @property
    def filling_segments(self) -> list:
        """Polylines of the filling (sparse, solid, top skin and bridges)."""
        return self.role_list("filling")

    @property
    def filling_kinds(self) -> tuple:
        """The kind of each of `filling_segments`."""
        return tuple(k for k in self.kind if ROLE_OF[k] == "filling")

    @property
    def gap_fill_segments(self) -> list:
        """Open polylines along thin walls and gaps between perimeters."""
        return self.role_list("gap_fill")

    @property
    def gap_fill_widths(self) -> list:
        """The width at each vertex of each of `gap_fill_segments`."""
        return [w for k, w in zip(self.kind, self.widths) if k == "gap_fill"]

    @property
    def skirt_segments(self) -> list:
        """The skirt's loops (first layer only)."""
        return self.role_list("skirt")

    @property
    def brim_segments(self) -> list:
        """The brim's loops (first layer only)."""
        return self.role_list("brim")

    @property
    def sequence(self) -> tuple:
        """Print order as (role, index into that role's list) pairs."""
        seen: dict = {}
        out = []
        for k in self.kind:
            r = ROLE_OF[k]
            out.append((r, seen.get(r, 0)))
            seen[r] = seen.get(r, 0) + 1
        return tuple(out)

    def ordered(self):
        """Yield (role, polyline, width) in print order; width is a scalar or per-vertex array."""
        for k, q, w in zip(self.kind, self.paths, self.widths):
            yield ROLE_OF[k], q, w

    def kinds(self) -> list[str]:
        """The kind of each path in print order (the keys of `slicelab.printing.roles.STYLES`)."""
        return list(self.kind)

    @property
    def extrusion_length(self) -> float:
        """Total length of all extrusions (mm)."""
        return self._sums[0]

    def extruded_area(self) -> float:
        """Sum of length x width over the extrusions (mm^2): the material laid per unit height."""
        return self._sums[1]

    @cached_property
    def _sums(self) -> tuple[float, float]:
        """Length and length x width of every extrusion, summed over the layer at once (the rows'
        points in one array, the segments that join two rows left out), once per table."""
        rows = [(q, w) for q, w in zip(self.paths, self.widths) if len(q)]
        if not rows:
            return 0.0, 0.0
        counts = np.array([len(q) for q, _ in rows])
        xy = np.concatenate([q for q, _ in rows])
        width = np.concatenate([np.full(m, w) if np.ndim(w) == 0 else np.asarray(w, np.float64)
                                for m, (_, w) in zip(counts, rows)])
        d = np.diff(xy, axis=0)
        seg = np.hypot(d[:, 0], d[:, 1])
        seg[np.cumsum(counts)[:-1] - 1] = 0.0  # from the last point of a row to the next row's first
        return float(seg.sum()), float(np.dot(seg, 0.5 * (width[:-1] + width[1:])))


