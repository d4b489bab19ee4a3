"""Which runs of layers the planner's workers take first: the costliest, by an estimate of each layer's cost.

A print plan hands its runs of layers to a pool of workers a few at a time;
handed out costliest first (longest processing time first), no worker is left
with a big one at the end while the others idle. A layer's cost is estimated
from its outline alone, before any of it is planned: its boundary's length,
as pixels are held only along the boundaries, and its skin's area, which solid
lines fill; a layer that likely repeats the one two below counts a fraction.
`scripts/profile_layers.py FILE --costs` fits the weights to each layer's time.

See Also
--------
slicelab.printing.planner.plan : the runs handed out.
"""
from __future__ import annotations

import numpy as np

from .config.settings import PrintSettings

__all__ = ["SKIN_COST", "REPEAT_COST", "layer_costs", "costliest_first"]


#: A layer's cost per mm^2 of skin against its cost per mm of boundary (solid lines fill a skin's
#: whole area): `scripts/profile_layers.py --costs` fits it to each layer's time (0.14-0.39 on the
#: block, the pot and the teapot).
SKIN_COST = 0.4


def layer_costs(sections: list, s: PrintSettings, size: list | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each layer's boundary length (mm) and skin area (mm^2): the area it has and a neighbour
    within the skins' reach lacks (or lacks and it has), all of it on the first and last layers.
    From each layer's `slicelab.printing._reuse.outline_size` (`size`, made here if not given).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = lambda a: np.array([[0, 0], [a, 0], [a, a], [0, a]], float)  # noqa: E731
    >>> layer = lambda a: SimpleNamespace(segments=np.stack([sq(a), np.roll(sq(a), -1, axis=0)], 1))  # noqa: E731
    >>> length, skin = layer_costs([layer(4)] * 8 + [layer(2)] * 8, PrintSettings())
    >>> length[[0, 8]].tolist(), skin.tolist()   # (3 bottom layers, a step at 8, 3 top layers)
    ([16.0, 8.0], [16.0, 16.0, 16.0, 0.0, 0.0, 12.0, 12.0, 12.0, 12.0, 12.0, 12.0, 0.0, 0.0, 4.0, 4.0, 4.0])
    """
    from ._reuse import outline_size
    n = len(sections)
    size = [outline_size(sec) for sec in sections] if size is None else size  # over layers
    area, length = np.abs([a for a, _ in size]).reshape(n), np.array([b for _, b in size]).reshape(n)
    skin = np.zeros(n)
    below, above = s.bottom_layers, s.top_layers
    for d in range(1, min(n, max(below, above) + 1)):  # over the neighbours the skins read
        change = np.abs(area[d:] - area[:-d])
        if d <= above:
            skin[:-d] = np.maximum(skin[:-d], change)
        if d <= below:
            skin[d:] = np.maximum(skin[d:], change)
    skin[:below] = area[:below]
    skin[max(0, n - above):] = area[max(0, n - above):]
    return length, skin


#: A layer of a prismatic stretch takes the toolpaths of the layer two below (`slicelab.printing.planner`): its
#: cost against a layer planned afresh (the block's, the bridge's: rasters of neighbours, G-code text).
REPEAT_COST = 0.2


def costliest_first(chunks: list, sections: list, s: PrintSettings, tolerance: float = 1e-9,
                    size: list | None = None) -> list:
    """The runs of layers in the order to hand them out: the costliest first, so that no worker
    is left with a big one at the end while the others idle (longest processing time first).

    A layer's cost is taken as its boundary's length, as pixels are held only along the
    boundaries, plus `SKIN_COST` times its skin's area (`layer_costs`), times `REPEAT_COST`
    where it and every layer its skins read have the same area within `tolerance` (it likely
    repeats the layer two below: `slicelab.printing._reuse.may_repeat`). `size` (optional)
    holds each layer's `slicelab.printing._reuse.outline_size`.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = lambda a: np.array([[0, 0], [a, 0], [a, a], [0, a]], float)  # noqa: E731
    >>> layer = lambda a: SimpleNamespace(segments=np.stack([sq(a), np.roll(sq(a), -1, axis=0)], 1))  # noqa: E731
    >>> costliest_first([(0, 20), (20, 40)], [layer(4)] * 36 + [layer(9)] * 4, PrintSettings())
    [(20, 40), (0, 20)]
    """
    from ._reuse import may_repeat, outline_size
    size = [outline_size(sec) for sec in sections] if size is None else size  # over layers: once
    length, skin = layer_costs(sections, s, size)
    alike = np.array([False] + [may_repeat(a, b, tolerance) for a, b in zip(size[1:], size[:-1])])  # over layers
    n, below, above = len(sections), s.bottom_layers, s.top_layers
    ends = np.concatenate([[0], np.cumsum(~alike)])  # layers unlike the one below, up to each
    k = np.arange(n)
    lo, hi = np.clip(k - below, 0, n), np.clip(k + above + 1, 0, n)
    repeats = (k - below - 1 >= 0) & (k + above < n) & (ends[hi] - ends[lo] == 0)
    cost = length + SKIN_COST * skin
    cost = np.concatenate([[0.0], np.cumsum(np.where(repeats, REPEAT_COST * cost, cost))])
    return sorted(chunks, key=lambda c: cost[c[1]] - cost[c[0]], reverse=True)
