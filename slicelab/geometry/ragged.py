"""Ragged arrays: groups of varying length laid end to end, handled without a Python loop.

A ragged array is a flat array plus the length of each group. The idiom
``arange(total) - repeat(cumsum(counts) - counts, counts)`` (the position of
each element within its group) underlies every vectorised expansion of
"for each item, for each of its k pieces" in the package.

Examples
--------
>>> within_group([2, 0, 3]).tolist()
[0, 1, 0, 1, 2]
>>> owner, values = expand_ranges([10, 5, 7], [2, 0, 3])
>>> owner.tolist(), values.tolist()
([0, 0, 2, 2, 2], [10, 11, 7, 8, 9])
"""
from __future__ import annotations

import numpy as np

__all__ = ["group_starts", "within_group", "expand_ranges"]


def group_starts(counts) -> np.ndarray:
    """Offset of each group's first element in the flat array (exclusive cumulative sum).

    Examples
    --------
    >>> group_starts([2, 0, 3]).tolist()
    [0, 2, 2]
    """
    c = np.asarray(counts, dtype=np.int64)
    return np.cumsum(c) - c


def within_group(counts) -> np.ndarray:
    """Position of every element within its group, for groups of the given lengths."""
    c = np.asarray(counts, dtype=np.int64)
    return np.arange(int(c.sum()), dtype=np.int64) - np.repeat(group_starts(c), c)


def expand_ranges(starts, counts) -> tuple[np.ndarray, np.ndarray]:
    """Every integer of the ranges ``starts[i]`` to ``starts[i] + counts[i] - 1``, with its range.

    Returns
    -------
    owner : (total,) int ndarray
        The range each value comes from.
    values : (total,) int ndarray
    """
    c = np.asarray(counts, dtype=np.int64)
    owner = np.repeat(np.arange(len(c), dtype=np.int64), c)
    return owner, np.asarray(starts, dtype=np.int64)[owner] + within_group(c)
