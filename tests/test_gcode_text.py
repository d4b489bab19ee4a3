"""The compiled G-code text and SVG path data against Python's own formatting, digit for digit, ties and signs included."""
from __future__ import annotations

import numpy as np
import pytest

from slicelab.files.svg import SvgDrawing
from slicelab.files.numbers import path_data
from slicelab.gcode.text_kernels import fixed

LINE = "G1 X%.3f Y%.3f E%.5f\n"


def _python(values: np.ndarray) -> str:
    return "".join(LINE % tuple(row) for row in values[1:].tolist())


def test_random_moves_are_python_text():
    rng = np.random.default_rng(0)
    v = np.c_[rng.uniform(-1000, 1000, 200_000), rng.uniform(0, 500, 200_000), rng.exponential(0.05, 200_000)]
    text, offsets = fixed(v)
    assert text == _python(v)
    lines = text.splitlines(keepends=True)
    assert [text[offsets[i]:offsets[i + 1]] for i in range(1, len(v))] == lines


def test_ties_round_to_even_as_python_does():
    # Binary fractions that lie exactly halfway at 3 decimals (odd sixteenths) and at 5 (odd
    # sixty-fourths), the doubles either side of them, and values rounding to a signed zero.
    j = np.arange(-4001, 4001, 2)
    ties3 = j / 16.0
    ties5 = np.abs(j) / 64.0
    near3 = np.r_[ties3, np.nextafter(ties3, np.inf), np.nextafter(ties3, -np.inf)]
    near5 = np.r_[ties5, np.nextafter(ties5, np.inf), np.nextafter(ties5, -np.inf)]
    near5 = np.resize(near5, len(near3))
    zeros = np.array([0.0, -0.0, -0.0004, 0.0004999, -0.0005, 0.0005, -1e-300, 1e-12])
    x = np.r_[near3, zeros]
    y = np.r_[near3[::-1], zeros[::-1]]
    e = np.r_[near5, np.abs(zeros) * 0.01]
    v = np.c_[x, y, e]
    assert fixed(v)[0] == _python(v)
    assert "G1 X0.062 Y" in fixed(np.array([[0, 0, 0], [0.0625, 1, 0]]))[0]       # 62.5 -> 62
    assert "G1 X0.188 Y" in fixed(np.array([[0, 0, 0], [0.1875, 1, 0]]))[0]       # 187.5 -> 188
    assert fixed(np.array([[0, 0, 0], [-0.0001, -0.0, 0]]))[0] == "G1 X-0.000 Y-0.000 E0.00000\n"


def test_large_and_unformattable_values():
    v = np.array([[0, 0, 0], [123456789.0625, -98765.4321, 12345.678901]])
    assert fixed(v)[0] == _python(v)
    for bad in (np.nan, np.inf, -np.inf, 1e20):
        assert fixed(np.array([[0, 0, 0], [bad, 0, 0]])) is None
    assert fixed(np.zeros((1, 3)))[0] == "" and fixed(np.zeros((0, 3)))[0] == ""


def _python_path_data(polylines, digits: int, closed: bool) -> str:
    """SVG path data as Python writes it: each number rounded, formatted, trailing zeros dropped."""
    def num(v):
        return f"{v:.{digits}f}".rstrip("0").rstrip(".")
    parts = []
    for p in polylines:
        r = np.round(p, digits) + 0.0
        if len(r):
            parts.append("M" + " L".join(num(x) + "," + num(y) for x, y in r.tolist()) + (" Z" if closed else ""))
    return " ".join(parts)


@pytest.mark.parametrize("digits", [1, 3, 4, 6])
def test_svg_path_data_is_python_text(digits):
    # Random polylines over eight decades, ties at the digits, numbers rounding to zero from either
    # side, an empty polyline; drawn on a page whose corner is the origin (no shift), written
    # compiled by SvgDrawing and by Python above, digit for digit.
    rng = np.random.default_rng(digits)
    polys = [rng.normal(0, 10.0 ** rng.integers(-4, 5), (rng.integers(1, 40), 2)) for _ in range(60)]
    ties = (np.arange(-41, 43, 2) / 2.0 ** (digits + 1)).reshape(-1, 2)  # exact ties at the digits
    polys += [ties, np.nextafter(ties, np.inf), np.array([[-0.4 * 10.0 ** -digits, 0.5 * 10.0 ** -digits]]),
              np.zeros((0, 2)), np.array([[123456.789, -98765.4321]])]
    flip = [np.c_[p[:, 0], -p[:, 1]] for p in polys]  # SvgDrawing's y runs down from the page's top
    for closed in (False, True):
        assert SvgDrawing((0, 0, 1, 0), digits=digits).path_data(flip, closed=closed) == \
            _python_path_data(polys, digits, closed)


def test_svg_path_data_leaves_what_it_cannot_write_to_python():
    assert path_data(np.array([[np.nan, 1.0]]), np.array([0, 1]), 3, False) is None
    assert path_data(np.array([[1e20, 1.0]]), np.array([0, 1]), 3, False) is None
    assert path_data(np.array([[1.0, 1.0]]), np.array([0, 1]), 0, False) is None  # digits 0: Python's
    assert SvgDrawing((0, 0, 1, 0), digits=3).path_data([np.array([[np.nan, -2.0], [1.5, -1.0]])]) == "Mnan,2 L1.5,1"
