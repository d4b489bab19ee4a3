"""Compiled G-code text: extrusion moves formatted as Python's ``%.3f`` / ``%.5f`` would, in one pass.

A layer's G-code is mostly lines ``G1 X.. Y.. E..``, some thousands of them; Python's
``%`` formatting of them was a third of the writer's time. `format_moves` writes them
all into one byte buffer in a compiled loop (`slicelab.geometry.compiled`), digit for digit
what ``"G1 X%.3f Y%.3f E%.5f\\n" % (x, y, e)`` gives: each number is rounded exactly
(the product by 10^d taken with its rounding error, ties to even, as Python rounds the
exact binary value), with Python's sign (``-0.000`` for a small negative number).

See Also
--------
slicelab.export.gcode.write_gcode : the writer that uses it.

References
----------
.. [1] T. J. Dekker, "A floating-point technique for extending the available precision",
   Numerische Mathematik 18, 1971 (the exact product of two doubles as a sum of two).
"""
from __future__ import annotations

import numpy as np

from ..geometry.compiled import njit

__all__ = ["format_moves", "fixed", "warm"]

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
def _put(out, pos, x, digits, scale):
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
def format_moves(values, out, offsets):
    """Lines ``G1 X<x> Y<y> E<e>`` (3, 3 and 5 decimals) for rows 1.. of `values`.

    Parameters
    ----------
    values : (n, 3) float64 ndarray
        x, y and the filament of the move to each row's point (row 0 has no move).
    out : (m,) uint8 ndarray
        Room for the text: 80 bytes a row is enough for any number under 9e10.
    offsets : (n + 1,) int64 ndarray
        Filled: the line of row i is ``out[offsets[i]:offsets[i + 1]]`` (i >= 1).

    Returns
    -------
    int
        The text's length, or -1 if a value is not finite or too large to format here.
    """
    n = values.shape[0]
    pos = 0
    offsets[0] = 0
    if n > 0:
        offsets[1] = 0
    for i in range(1, n):
        out[pos] = 71  # "G1 X"
        out[pos + 1] = 49
        out[pos + 2] = 32
        out[pos + 3] = 88
        pos = _put(out, pos + 4, values[i, 0], 3, 1000.0)
        if pos < 0:
            return -1
        out[pos] = 32  # " Y"
        out[pos + 1] = 89
        pos = _put(out, pos + 2, values[i, 1], 3, 1000.0)
        if pos < 0:
            return -1
        out[pos] = 32  # " E"
        out[pos + 1] = 69
        pos = _put(out, pos + 2, values[i, 2], 5, 100000.0)
        if pos < 0:
            return -1
        out[pos] = 10
        pos += 1
        offsets[i + 1] = pos
    return pos


def fixed(values: np.ndarray) -> tuple[str, np.ndarray] | None:
    """The moves' text for rows 1.. of (n, 3) `values` and each row's line offsets, or None if a
    value cannot be formatted here (the caller formats those with Python).

    Examples
    --------
    >>> text, off = fixed(np.array([[0, 0, 0], [1.0625, -0.0001, 0.123456], [2.5, 10.0, 1e-6]]))
    >>> text[off[1]:off[3]]
    'G1 X1.062 Y-0.000 E0.12346\\nG1 X2.500 Y10.000 E0.00000\\n'
    >>> text[off[1]:off[3]] == "G1 X%.3f Y%.3f E%.5f\\n" % (1.0625, -0.0001, 0.123456) + \\
    ...     "G1 X%.3f Y%.3f E%.5f\\n" % (2.5, 10.0, 1e-6)
    True
    """
    v = np.ascontiguousarray(values, np.float64)
    n = len(v)
    out = np.empty(80 * max(n, 1), np.uint8)
    offsets = np.zeros(n + 1, np.int64)
    size = format_moves(v, out, offsets)
    if size < 0:
        return None
    return out[:size].tobytes().decode("ascii"), offsets


def warm() -> None:
    """Call the kernel once with the types the writer uses (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    fixed(np.zeros((2, 3)))
