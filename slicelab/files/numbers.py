"""Numbers written as text by compiled loops, digit for digit as Python writes them: the one
number formatter of every file slicelab writes (SVG path data here; G-code's moves in
`slicelab.gcode.text_kernels`, which writes its numbers with `put_number`).

Each number is rounded exactly (the product by 10^d taken with its rounding
error, ties to even, as Python rounds the exact binary value), with Python's
sign (``-0.000`` for a small negative number); a number it cannot write (not
finite, or too large) is said (-1), for the caller to write another way.

References
----------
.. [1] T. J. Dekker, "A floating-point technique for extending the available precision",
   Numerische Mathematik 18, 1971 (the exact product of two doubles as a sum of two).
"""
from __future__ import annotations

import numpy as np

from ..geometry.compiled import njit

__all__ = ["put_number", "put_text", "format_path_data", "path_data", "warm"]

#: Veltkamp's splitter for doubles (2^27 + 1).
_SPLIT = 134217729.0


@njit(cache=True, nogil=True)
def _rounded(x, scale):
    """|x| x scale rounded to the nearest integer, ties to even, from the exact product; -1 if
    the result would not fit an int64 (the caller then formats another way)."""
    a = abs(x)
    p = a * scale
    if not p < 9.0e15:
        return -1
    # Dekker's product: p + err == a * scale exactly.
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * scale
    bh = t - (t - scale)
    bl = scale - bh
    err = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    f = np.floor(p)
    d = (p - f) - 0.5  # exact: p < 2^53, so its fraction and 1/2 share its last bit
    r = d + err  # its sign is the exact sum's sign
    q = np.int64(f)
    if r > 0 or (r == 0 and q % 2 == 1):
        q += 1
    return q


@njit(cache=True, nogil=True)
def put_number(out, pos, x, digits, scale):
    """Write x with `digits` decimals at out[pos:]; the new position, or -1 if x is not finite
    or too large."""
    if not np.isfinite(x):
        return -1
    q = _rounded(x, scale)
    if q < 0:
        return -1
    if x < 0 or (x == 0 and np.signbit(x)):
        out[pos] = 45  # "-"
        pos += 1
    whole = q // np.int64(scale)
    frac = q - whole * np.int64(scale)
    # The whole part's digits, most significant first.
    n = 1
    w = whole
    while w >= 10:
        w //= 10
        n += 1
    w = whole
    for i in range(n - 1, -1, -1):
        out[pos + i] = 48 + w % 10
        w //= 10
    pos += n
    if digits > 0:
        out[pos] = 46  # "."
        pos += 1
        for i in range(digits - 1, -1, -1):
            out[pos + i] = 48 + frac % 10
            frac //= 10
        pos += digits
    return pos


@njit(cache=True, nogil=True)
def put_text(out, pos, word):
    """Copy the bytes of `word` to out[pos:]; the new position."""
    for i in range(len(word)):
        out[pos + i] = word[i]
    return pos + len(word)


@njit(cache=True, nogil=True)
def _trimmed(out, start, pos):
    """The end of the number written at out[start:pos] with its fraction's trailing zeros (and a
    bare point) dropped, as Python's ``.rstrip("0").rstrip(".")`` of a number with decimals."""
    while pos > start and out[pos - 1] == 48:  # "0"
        pos -= 1
    if pos > start and out[pos - 1] == 46:  # "."
        pos -= 1
    return pos


@njit(cache=True, nogil=True)
def format_path_data(xy, bounds, digits, scale, closed, out, offsets):
    """SVG path data ``M x,y L x,y ...`` (and `` Z`` when `closed`) of each polyline, numbers with
    `digits` decimals (>= 1), trailing zeros dropped.

    Parameters
    ----------
    xy : (n, 2) float64 ndarray
        The polylines' points, one after another (already rounded to `digits`, no -0).
    bounds : (m + 1,) int64 ndarray
        Polyline i is ``xy[bounds[i]:bounds[i + 1]]``, of one point or more.
    digits : int
    scale : float
        10^digits.
    closed : bool
    out : (k,) uint8 ndarray
        Room for the text: 2 (24 + digits) bytes a point and 3 a polyline are enough.
    offsets : (m + 1,) int64 ndarray
        Filled: polyline i's data is ``out[offsets[i]:offsets[i + 1]]``.

    Returns
    -------
    int
        The text's length, or -1 if a value is not finite or too large to format here.
    """
    pos = 0
    for i in range(len(bounds) - 1):  # over polylines
        offsets[i] = pos
        for j in range(bounds[i], bounds[i + 1]):  # over points
            if j == bounds[i]:
                out[pos] = 77  # "M"
                pos += 1
            else:
                out[pos] = 32  # " L"
                out[pos + 1] = 76
                pos += 2
            for c in range(2):  # x, y
                start = pos
                pos = put_number(out, pos, xy[j, c], digits, scale)
                if pos < 0:
                    return -1
                pos = _trimmed(out, start, pos)
                if c == 0:
                    out[pos] = 44  # ","
                    pos += 1
        if closed:
            out[pos] = 32  # " Z"
            out[pos + 1] = 90
            pos += 2
    offsets[len(bounds) - 1] = pos
    return pos


def path_data(xy: np.ndarray, bounds: np.ndarray, digits: int, closed: bool) -> list[str] | None:
    """Each polyline's SVG path data (see `format_path_data`), or None if a value cannot be
    formatted here or `digits` is below 1 (the caller formats those with Python).

    Examples
    --------
    >>> path_data(np.array([[0.0, 1.5], [2.25, -0.1], [3.0, 4.0]]), np.array([0, 2, 3]), 4, True)
    ['M0,1.5 L2.25,-0.1 Z', 'M3,4 Z']
    """
    if digits < 1:
        return None
    v = np.ascontiguousarray(xy, np.float64).reshape(-1, 2)
    b = np.ascontiguousarray(bounds, np.int64)
    out = np.empty(2 * (24 + int(digits)) * len(v) + 3 * len(b), np.uint8)
    offsets = np.zeros(len(b), np.int64)
    size = format_path_data(v, b, int(digits), float(10 ** int(digits)), bool(closed), out, offsets)
    if size < 0:
        return None
    text = out[:size].tobytes().decode("ascii")
    return [text[offsets[i]:offsets[i + 1]] for i in range(len(b) - 1)]


def warm() -> None:
    """Call the kernels once with the types the writers use (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    path_data(np.zeros((2, 2)), np.array([0, 2]), 3, False)
