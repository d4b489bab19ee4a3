"""One small SVG writer for every drawing: sections, profiles, toolpath layers.

Drawings are at true scale: 1 user unit is 1 mm, and the page is the
rectangle ``(x0, y0) .. (x1, y1)`` of the drawing's own plane with y up.
SVG's y grows downwards, so the writer flips every coordinate it is given:
callers pass plane coordinates and never think about it.

Examples
--------
>>> import xml.etree.ElementTree as ET
>>> svg = SvgDrawing((0, 0, 10, 5), title="a square")
>>> with svg.group("material", fill="black"):
...     svg.path([np.array([[1, 1], [3, 1], [3, 3], [1, 3]])], closed=True)
>>> root = ET.fromstring(svg.to_string())
>>> root.get("width"), root.find("{http://www.w3.org/2000/svg}g/{http://www.w3.org/2000/svg}path").get("d")
('10mm', 'M1,4 L3,4 L3,2 L1,2 Z')
"""
from __future__ import annotations

import contextlib
from html import escape as _escape

import numpy as np

__all__ = ["SvgDrawing"]


def _quoted(value: str) -> str:
    """An attribute's value in double quotes, escaped (``&``, ``<``, ``>`` and both quotes).

    `html.escape` rather than `xml.sax.saxutils.quoteattr`: importing the latter loads
    `urllib.request` (and `ssl`), 8 ms of every command that writes G-code.

    Examples
    --------
    >>> _quoted('a "b" & c')
    '"a &quot;b&quot; &amp; c"'
    """
    return f'"{_escape(value)}"'


def _attrs(attrs: dict) -> str:
    # Python names for SVG attributes: stroke_width -> stroke-width; None leaves one out.
    return "".join(f" {k.rstrip('_').replace('_', '-')}={_quoted(_num(v) if not isinstance(v, str) else v)}"
                   for k, v in attrs.items() if v is not None)


def _path_tail(title: str | None, attrs: dict) -> str:
    """What follows a ``<path>``'s data: its attributes, and its title inside it, or its end."""
    if title is None:
        return _attrs(attrs) + "/>"
    return f"{_attrs(attrs)}><title>{_escape(title, quote=False)}</title></path>"


def _num(v) -> str:
    return f"{float(v):.6g}"


class SvgDrawing:
    """An SVG document built element by element, in millimetres, y up.

    Parameters
    ----------
    page : (x0, y0, x1, y1)
        The drawing's extent in its own coordinates (mm).
    title, desc : str, optional
        The document's ``<title>`` and ``<desc>`` (escaped here).
    digits : int, default 4
        Decimals written for coordinates (4 is 0.1 micrometre).

    See Also
    --------
    slicelab.slicing.Section.svg, slicelab.artefacts.profile_svg, slicelab.gcode.write_svgs
    """

    def __init__(self, page, *, title: str | None = None, desc: str | None = None, digits: int = 4):
        self.x0, self.y0, self.x1, self.y1 = (float(v) for v in page)
        self.digits = digits
        w, h = self.x1 - self.x0, self.y1 - self.y0
        self._out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(w)}mm" height="{_num(h)}mm" '
                     f'viewBox="0 0 {_num(w)} {_num(h)}">']
        if title is not None:
            self._out.append(f"<title>{_escape(title, quote=False)}</title>")
        if desc is not None:
            self._out.append(f"<desc>{_escape(desc, quote=False)}</desc>")

    # ------------------------------------------------------------ coordinates
    def _xy(self, points) -> np.ndarray:
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        return np.column_stack([p[:, 0] - self.x0, self.y1 - p[:, 1]])

    def _fmt(self, q: np.ndarray) -> list[str]:
        r = np.round(q, self.digits) + 0.0  # + 0.0: no "-0"
        return [f"{x:.{self.digits}f}".rstrip("0").rstrip(".") + "," + f"{y:.{self.digits}f}".rstrip("0").rstrip(".")
                for x, y in r]

    def path_data(self, polylines, *, closed: bool = False) -> str:
        """SVG path data of polylines (``M .. L .. [Z]`` for each)."""
        return " ".join(d for d in self._each_path_data(polylines, closed) if d)

    def _each_path_data(self, polylines, closed: bool = False) -> list[str]:
        """Each polyline's path data ("" for one without points)."""
        from .numbers import path_data
        raw = [np.asarray(p, dtype=np.float64).reshape(-1, 2) for p in polylines]
        full = [i for i, x in enumerate(raw) if len(x)]
        out = [""] * len(raw)
        if not full:
            return out
        # Every point moved onto the page at once, then written in one compiled pass (the numbers
        # Python's format gives); Python's own format where that pass cannot write a value.
        sizes = np.array([len(raw[i]) for i in full])
        bounds = np.concatenate([[0], np.cumsum(sizes)])
        xy = self._xy(np.concatenate([raw[i] for i in full]))
        r = np.round(xy, self.digits) + 0.0  # + 0.0: no "-0"
        parts = path_data(r, bounds, self.digits, closed)
        if parts is None:
            parts = ["M" + " L".join(self._fmt(xy[a:b])) + (" Z" if closed else "")
                     for a, b in zip(bounds[:-1], bounds[1:])]
        for i, d in zip(full, parts):
            out[i] = d
        return out

    # ---------------------------------------------------------------- elements
    @contextlib.contextmanager
    def group(self, id: str | None = None, **attrs):
        """A ``<g>`` around what is drawn inside the ``with`` block."""
        self._out.append(f"<g{_attrs({'id': id, **attrs})}>")
        try:
            yield self
        finally:
            self._out.append("</g>")

    def path(self, polylines, *, closed: bool = False, title: str | None = None, **attrs) -> None:
        """One ``<path>`` through several polylines (rings when `closed`)."""
        d = self.path_data(polylines, closed=closed)
        if not d:
            return
        self._out.append(f"<path d={_quoted(d)}{_path_tail(title, attrs)}")

    def paths(self, polylines, looks) -> None:
        """One ``<path>`` per polyline, as `path` draws each alone, its ``(title, attrs)`` from
        `looks`: the path data of all in one pass, each look's attributes formatted once.

        Examples
        --------
        >>> a, b = SvgDrawing((0, 0, 9, 9)), SvgDrawing((0, 0, 9, 9))
        >>> lines, looks = [np.array([[0, 0], [1, 2]]), np.array([[3, 3], [4, 4]])], [("one", {"stroke": "red"})] * 2
        >>> a.paths(lines, looks)
        >>> for q, (title, attrs) in zip(lines, looks):
        ...     b.path([q], title=title, **attrs)
        >>> a.to_string() == b.to_string()
        True
        """
        made: dict = {}
        for d, (title, attrs) in zip(self._each_path_data(polylines), looks):  # over paths
            if not d:
                continue
            key = (title, tuple(attrs.items()))
            tail = made.get(key)
            if tail is None:
                tail = made[key] = _path_tail(title, attrs)
            self._out.append(f"<path d={_quoted(d)}{tail}")

    def polyline(self, points, **attrs) -> None:
        """A ``<polyline>``."""
        self._out.append(f"<polyline points={_quoted(' '.join(self._fmt(self._xy(points))))}{_attrs(attrs)}/>")

    def rect(self, x: float, y: float, width: float, height: float, **attrs) -> None:
        """A rectangle whose lower-left corner is (x, y)."""
        (qx, qy), = self._xy([[x, y + height]])
        self._out.append(f'<rect x="{_num(qx)}" y="{_num(qy)}" width="{_num(width)}" height="{_num(height)}"'
                         f"{_attrs(attrs)}/>")

    def text(self, x: float, y: float, text: str, **attrs) -> None:
        """Text whose baseline starts (or is anchored) at (x, y)."""
        (qx, qy), = self._xy([[x, y]])
        self._out.append(f'<text x="{_num(qx)}" y="{_num(qy)}"{_attrs(attrs)}>{_escape(text, quote=False)}</text>')

    def to_string(self) -> str:
        """The whole document."""
        return "\n".join(self._out + ["</svg>"]) + "\n"

    def write(self, path) -> None:
        """Write the document to `path`, atomically."""
        from .atomic import atomic_open
        with atomic_open(path, "w", encoding="utf-8") as fh:
            fh.write(self.to_string())
