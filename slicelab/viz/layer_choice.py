"""Which layers a preview draws: the ``--preview-layers`` of ``slicelab slice`` read and resolved.

`preview_layers` reads what a user asks (layer numbers, heights, words,
``0,57,z=12.5,last``), `pick_preview_layers` resolves it against a plan's
layers, and `default_preview_layers` chooses when nothing is asked: the
first, middle and last layers and the one with the most bridge and
overhang area.

See Also
--------
slicelab.viz.layers.preview_png : draws the layers chosen here.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["preview_layers", "pick_preview_layers", "default_preview_layers", "LAYER_WORDS",
           "PREVIEW_LAYERS_FORM", "MAX_PREVIEW_LAYERS"]

#: Words that name a layer by what it holds: the first, the middle one (number n // 2), the last,
#: the one with the most bridge and overhang area, the one with the most material.
LAYER_WORDS = ("first", "middle", "last", "overhang", "largest")
#: What `preview_layers` reads, in words (the refusals say it).
PREVIEW_LAYERS_FORM = ("layer numbers (0 is the first, as in layer_NNNN.svg), z=HEIGHT (mm above the bed), "
                       "first, middle, last, overhang or largest, separated by commas")
#: Layers a preview draws at most.
MAX_PREVIEW_LAYERS = 12


def preview_layers(value) -> tuple | None:
    """The layers a preview is asked to draw, as plain values: layer numbers (int), heights
    (``"z=12.5"``: the layer printed at that height above the bed) and words (`LAYER_WORDS`).

    `value` is text such as ``"0,57,z=12.5,last"`` or a sequence of such items (numbers or
    text); None is None (the default choice). Whether the layers exist is for
    `pick_preview_layers` to say, once the layers are known.

    Raises
    ------
    ValueError
        Saying what was expected (`PREVIEW_LAYERS_FORM`) and what was given.

    Examples
    --------
    >>> preview_layers("0, 57,Z=12.50,last")
    (0, 57, 'z=12.5', 'last')
    >>> preview_layers([3, "middle"])
    (3, 'middle')
    >>> preview_layers("0,top")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: must be layer numbers ..., got 'top'
    """
    if value is None:
        return None
    if isinstance(value, str):
        parts = value.split(",")
    elif isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        parts = [value]
    else:
        parts = list(value)
    items = []
    for part in parts:  # over the items asked for, a few
        if isinstance(part, (int, np.integer)) and not isinstance(part, bool) and part >= 0:
            items.append(int(part))
            continue
        text = str(part).strip().lower().replace(" ", "")
        if text in LAYER_WORDS:
            items.append(text)
        elif text.isdigit():
            items.append(int(text))
        elif text.startswith("z="):
            try:
                height = float(text[2:])
            except ValueError:
                height = float("nan")
            if not (math.isfinite(height) and height >= 0):
                raise ValueError(f"heights must be z=HEIGHT in mm, 0 or more, such as z=12.5, got {str(part)!r}")
            items.append(f"z={height:g}")
        else:
            raise ValueError(f"must be {PREVIEW_LAYERS_FORM}, got {str(part).strip()!r}")
    if not items:
        raise ValueError(f"must name at least one layer: {PREVIEW_LAYERS_FORM}")
    if len(items) > MAX_PREVIEW_LAYERS:
        raise ValueError(f"names {len(items)} layers: a preview draws {MAX_PREVIEW_LAYERS} at most")
    return tuple(items)


def _kind_area(lp, kinds) -> float:
    """Length x width of a layer's extrusions of some kinds (mm^2)."""
    area = 0.0
    for _, q, w in lp.rows(kinds):  # over those rows, a few
        if len(q) > 1:
            seg = np.hypot(*np.diff(q, axis=0).T)
            area += float(np.sum(seg * (w if np.ndim(w) == 0 else 0.5 * (w[:-1] + w[1:]))))
    return area


def _hanging(plan) -> np.ndarray:
    """Per layer, the area over nothing: overhang not bridged plus the bridges laid (mm^2)."""
    ov = plan.overhangs
    n = len(plan.layers)
    area = np.zeros(n) if len(ov) != n else np.asarray(ov["area"], dtype=float).copy()
    bridged = np.flatnonzero(ov["bridges"]) if len(ov) == n else range(n)
    for k in bridged:  # over the layers with bridges, few
        area[k] += _kind_area(plan.layers[k], ("bridge",))
    return area


def _material(plan) -> np.ndarray:
    a = plan.areas
    return np.asarray(a["material"], dtype=float) if len(a) == len(plan.layers) else \
        np.array([lp.extruded_area() for lp in plan.layers])


def _word_layer(plan, word: str, n: int) -> tuple[int, str]:
    if word == "first":
        return 0, "first"
    if word == "middle":
        return n // 2, "middle"
    if word == "last":
        return n - 1, "last"
    if word == "overhang":
        hang = _hanging(plan)
        if hang.max(initial=0.0) > 0:
            k = int(np.argmax(hang))
            return k, f"most bridges and overhangs, {hang[k]:.3g} mm2"
        word = "largest"  # nothing hangs: the layer with the most material says most
    k = int(np.argmax(_material(plan)))
    return k, "largest area" + (" (nothing hangs)" if word != "largest" else "")


def pick_preview_layers(items, tops, plan=None) -> list[tuple[int, str]]:
    """The layers `items` (from `preview_layers`) name, with what each was asked as, in the order
    asked, each once.

    Parameters
    ----------
    items : sequence
        Layer numbers, ``"z=H"`` heights and `LAYER_WORDS`.
    tops : (n,) array
        Each layer's top above the bed (mm; `PrintPlan.z`): a height names the layer printed there.
    plan : PrintPlan, optional
        Needed for ``overhang`` and ``largest``; without it (a check before planning) they are
        left out.

    Raises
    ------
    ValueError
        For a layer the part does not have, saying which it has.

    Examples
    --------
    >>> pick_preview_layers([0, "z=0.5", "last", 2], [0.2, 0.4, 0.6, 0.8])
    [(0, ''), (2, 'z=0.5'), (3, 'last')]
    >>> pick_preview_layers([7], [0.2, 0.4, 0.6, 0.8])
    Traceback (most recent call last):
    ...
    ValueError: 7 is not a layer of this part: it has 4 layers, 0 to 3 (give one of those, or last)
    """
    tops = np.asarray(tops, dtype=float)
    n = len(tops)
    if n == 0:
        raise ValueError("has no layer to draw: the part has none")
    out, seen = [], set()
    for it in items:  # over the items asked for, a few
        if isinstance(it, (int, np.integer)):
            if not 0 <= it < n:
                raise ValueError(f"{it} is not a layer of this part: it has {n} layers, 0 to {n - 1} "
                                 f"(give one of those, or last)")
            k, why = int(it), ""
        elif str(it).startswith("z="):
            height = float(it[2:])
            if height > tops[-1] + 1e-6:
                raise ValueError(f"{it} is above the part's last layer ({n - 1}, z = {tops[-1]:.2f} mm): "
                                 f"give a height up to {tops[-1]:g}")
            k, why = int(np.searchsorted(tops, height - 1e-6)), it  # the first layer whose top is that high
        elif it in ("first", "middle", "last") or plan is not None:
            k, why = _word_layer(plan, it, n)
        else:
            continue
        if k not in seen:
            seen.add(k)
            out.append((k, why))
    return out


def default_preview_layers(plan) -> list[tuple[int, str]]:
    """The layers a preview draws unless told: the first, the middle and the last, and the one with
    the most bridge and overhang area (`PrintPlan.overhangs` and the bridges laid); where two of
    these are one layer, the layer with the most material, then those a quarter and three quarters
    up. Bottom to top, each with why it was chosen.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (4, 4, 1)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> default_preview_layers(p)   # 5 layers, nothing hangs: the fourth has the most material (float noise)
    [(0, 'first'), (1, 'a quarter up'), (2, 'middle'), (4, 'last')]
    """
    n = len(plan.layers)
    if n == 0:
        return []
    chosen: dict = {}
    for k, why in ((0, "first"), (n // 2, "middle"), (n - 1, "last")):
        chosen.setdefault(k, []).append(why)
    hang = _hanging(plan)
    if hang.max(initial=0.0) > 0:
        k = int(np.argmax(hang))
        chosen.setdefault(k, []).append(f"most bridges and overhangs, {hang[k]:.3g} mm2")
    fallbacks = [(int(np.argmax(_material(plan))), "largest area"), (n // 4, "a quarter up"),
                 ((3 * n) // 4, "three quarters up")]
    for k, why in fallbacks:  # three at most
        if len(chosen) >= min(4, n):
            break
        chosen.setdefault(k, [why])
    return [(k, "; ".join(chosen[k])) for k in sorted(chosen)]
