"""The rim-diameter chart of a batch of vessels and sherds, weighted by rim EVE.

A rim sherd keeping a fifth of its rim stands for a fifth of a vessel
(0.2 estimated vessel equivalents, EVE): archaeologists chart rim diameters
with each piece weighted by its rim fraction, so that many small sherds of
one pot do not count as many pots [1]_ [2]_. `rim_chart` sums the rim EVE of
the pieces in bins of diameter (a whole vessel counts 1); the pieces whose
axis cannot be trusted have no diameter to chart and are counted apart
(their EVE is in the total, not in a bin). `RimChart` holds the numbers the
picture draws (`rim_chart_png`, matplotlib, imported when drawn) and writes
them as CSV.

References
----------
.. [1] C. Orton, P. Tyers and A. Vince, *Pottery in Archaeology*, Cambridge
   University Press, 1993 (quantification: estimated vessel equivalents).
.. [2] C. Orton and M. Hughes, *Pottery in Archaeology*, 2nd ed., Cambridge
   University Press, 2013 (rim diameters and their charts).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["RimChart", "rim_chart", "rim_chart_png", "CHART_COLUMNS"]

#: The columns of the chart's CSV.
CHART_COLUMNS = ("diameter_from_mm", "diameter_to_mm", "rim_eve", "pieces", "charted")
_WIDTHS = (10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0)  # mm: 1 cm bins unless there would be too many
_MOST_BINS = 40


@dataclass(frozen=True)
class RimChart:
    """Rim EVE per bin of rim diameter: what the chart draws.

    Attributes
    ----------
    edges : (k + 1,) ndarray
        Bin edges (mm), `bin_width` apart; a diameter on an edge goes to the bin above it.
    eve : (k,) ndarray
        Sum of the rim EVE of the pieces in each bin.
    pieces : (k,) int ndarray
        How many pieces each bin holds.
    left_out_eve : float
        Rim EVE of the pieces with a rim but no diameter to trust (their axis is not trusted).
    left_out : tuple of str
        Those pieces' names.
    """

    edges: np.ndarray
    eve: np.ndarray
    pieces: np.ndarray
    left_out_eve: float = 0.0
    left_out: tuple = field(default=())

    @property
    def bin_width(self) -> float:
        """Bin width (mm)."""
        return float(self.edges[1] - self.edges[0]) if len(self.edges) > 1 else _WIDTHS[0]

    @property
    def charted_eve(self) -> float:
        """Rim EVE in the bins."""
        return math.fsum(self.eve)

    @property
    def total_eve(self) -> float:
        """Rim EVE of every piece with a rim: the charted and the left out."""
        return math.fsum([*self.eve, self.left_out_eve])

    def rows(self) -> list[dict]:
        """The chart as rows of `CHART_COLUMNS`: a row per bin, and one ``charted`` "no" row (no
        diameters) for the pieces left out, when there are any."""
        out = [{"diameter_from_mm": float(a), "diameter_to_mm": float(b), "rim_eve": float(e), "pieces": int(n),
                "charted": "yes"} for a, b, e, n in zip(self.edges[:-1], self.edges[1:], self.eve, self.pieces)]
        if self.left_out:
            out.append({"diameter_from_mm": "", "diameter_to_mm": "", "rim_eve": self.left_out_eve,
                        "pieces": len(self.left_out), "charted": "no"})
        return out

    def to_csv(self, path) -> None:
        """Write `rows` as CSV, atomically."""
        import csv

        from ..files.atomic import atomic_open
        with atomic_open(path, "w", encoding="utf-8", newline="") as fh:
            w = csv.DictWriter(fh, CHART_COLUMNS)
            w.writeheader()
            w.writerows({k: (f"{v:.10g}" if isinstance(v, float) else v) for k, v in row.items()}
                        for row in self.rows())


def rim_chart(pieces, bin_width: float | None = None) -> RimChart:
    """Sum the rim EVE of `pieces` in bins of rim diameter.

    Parameters
    ----------
    pieces : iterable of (name, rim_diameter_mm, rim_eve, axis_trusted)
        One per piece with a rim (a whole vessel's rim EVE is 1, a rim
        sherd's its rim fraction); pieces without a rim EVE are passed over.
        A piece whose axis is not trusted, or without a diameter, is left
        out of the bins and counted apart.
    bin_width : float, optional
        Bin width (mm); default 10 mm (1 cm), or the next of 20, 50, 100...
        mm that needs at most 40 bins.

    Returns
    -------
    RimChart

    See Also
    --------
    rim_chart_png : draws it.

    Examples
    --------
    >>> c = rim_chart([("a", 96.0, 0.25, True), ("b", 104.0, 1.0, True), ("c", 98.5, 0.5, True),
    ...                ("d", 120.0, 0.1, False), ("e", None, None, True)])
    >>> c.edges.tolist(), c.eve.tolist(), c.pieces.tolist(), c.left_out, c.total_eve
    ([90.0, 100.0, 110.0], [0.75, 1.0], [2, 1], ('d',), 1.85)
    >>> rim_chart([("a", 96.0, 0.2, True)]).edges.tolist(), rim_chart([("a", 5.0, 1, True), ("b", 2e6, 1, True)]).bin_width
    ([90.0, 100.0], 100000.0)
    """
    charted, left, left_eve = [], [], []
    for name, diameter, eve, trusted in pieces:  # one per file of a batch
        if eve is None or not math.isfinite(eve):
            continue
        if trusted and diameter is not None and math.isfinite(diameter) and diameter > 0:
            charted.append((float(diameter), float(eve)))
        else:
            left.append(str(name))
            left_eve.append(float(eve))
    d = np.array([x for x, _ in charted], dtype=float)
    if not len(d):
        return RimChart(np.zeros(1), np.zeros(0), np.zeros(0, np.int64), math.fsum(left_eve), tuple(left))
    if bin_width is None:
        span = float(d.max() - d.min())
        bin_width = next((w for w in _WIDTHS if span / w < _MOST_BINS), None) or \
            10.0 ** math.ceil(math.log10(span / _MOST_BINS))  # kilometres of rim: a mistaken scale
    lo = math.floor(float(d.min()) / bin_width) * bin_width
    k = np.floor((d - lo) / bin_width).astype(np.int64)
    n = int(k.max()) + 1
    eve = np.array([math.fsum(e for (_, e), kk in zip(charted, k) if kk == b) for b in range(n)])
    return RimChart(lo + bin_width * np.arange(n + 1), eve, np.bincount(k, minlength=n), math.fsum(left_eve),
                    tuple(left))


def rim_chart_png(chart: RimChart, path, *, title: str | None = None, dpi: float = 150.0) -> None:
    """Draw the chart (bars of rim EVE over rim diameter) as a PNG, atomically (matplotlib, no pyplot).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "rims.png")
    >>> rim_chart_png(rim_chart([("a", 96.0, 0.25, True), ("b", 104.0, 1.0, True)]), path, dpi=40)
    >>> open(path, "rb").read(4)
    b'\\x89PNG'
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ..files.atomic import atomic_path
    fig = Figure(figsize=(7.0, 4.0), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    if len(chart.eve):
        ax.bar(chart.edges[:-1], chart.eve, width=chart.bin_width, align="edge", color="0.25", edgecolor="black",
               linewidth=0.5)
        ax.set_xlim(float(chart.edges[0]) - chart.bin_width / 2, float(chart.edges[-1]) + chart.bin_width / 2)
        if len(chart.edges) <= 21:  # a tick at every bin's edge while they fit
            ax.set_xticks(chart.edges)
    else:
        ax.text(0.5, 0.5, "no rim with a diameter to chart", ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel(f"rim diameter (mm; bins of {chart.bin_width:g} mm)")
    ax.set_ylabel("rim EVE (vessel equivalents)")
    n = int(chart.pieces.sum())
    head = title or "Rim diameters, weighted by rim EVE"
    tail = f"{n} pieces, {chart.charted_eve:.2f} EVE"
    if chart.left_out:
        tail += f"; {len(chart.left_out)} more ({chart.left_out_eve:.2f} EVE) without a trusted axis, not charted"
    ax.set_title(f"{head}\n{tail}", fontsize=9)
    ax.spines[["top", "right"]].set_visible(False)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi, metadata={"Software": None})
