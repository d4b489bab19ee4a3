"""Work a job's parameters would ask of the machine, estimated before any is done.

A parameter that is valid on its own can still ask for the impossible on a
given part: layers of a nanometre, pixels of ten nanometres, a hundred
thousand perimeters. Each check here estimates the layers, pixels, memory or
pieces from the part's size first and refuses, naming the parameter and the
estimate, what no machine of this size could finish (or what makes no
physical sense), so a command ends in a second with one clear line instead
of a MemoryError or an hour of work.
"""
from __future__ import annotations

import math
import os

import numpy as np

from .spec import ParameterError

__all__ = ["likely_units", "MIN_LAYER_HEIGHT", "MIN_PIXEL_SIZE", "MAX_LAYERS", "MAX_PLANES", "MAX_STAIR_BANDS", "MAX_LAYER_PIXELS",
           "MAX_PRINT_PIXELS", "memory_budget",
           "check_layers", "check_print", "check_planes", "check_partition"]

MIN_LAYER_HEIGHT = 1e-3   # mm: one micrometre, far below any printer or scanner
MIN_PIXEL_SIZE = 5e-3     # mm: five micrometres, a tenth of the finest nozzle's line
MAX_LAYERS = 100_000      # a 10 m part at 0.1 mm
MAX_PLANES = 3600         # a plane every tenth of a degree
MAX_STAIR_BANDS = 2000    # teeth across one joint
_SEGMENT_BYTES = 200      # memory per section segment while slicing every layer at once
_PIXEL_BYTES = 40         # memory per raster pixel of a layer (masks, distance field, labels)
#: Pixels a print layer's raster may hold: 8 M, a 570 mm square at the default 0.2 mm pixel,
#: larger than any bed. A layer's cost grows faster than its pixels beyond a few million (a 40 mm
#: sphere: 3 M pixels a layer, 11 s; 12 M, 121 s), so finer grids are refused before they start.
MAX_LAYER_PIXELS = 8_000_000
#: Pixels over all layers of a print (pixels a layer x layers): some minutes of planning.
MAX_PRINT_PIXELS = 2e10


def memory_budget() -> int:
    """Half the machine's physical memory (bytes): what one job may plan to use.

    Examples
    --------
    >>> memory_budget() > 0
    True
    """
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        total = 8 << 30
    return int(total // 2)


def _gib(n: float) -> str:
    return f"{n / 2 ** 30:.3g} GiB"


def check_layers(mesh, layer_height: float, name: str = "layer_height") -> int:
    """Refuse a layer height that is absurd or whose sections would not fit in memory.

    Returns the number of layers.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> check_layers(box((0, 0, 0), (10, 10, 10)), 0.2)
    50
    >>> check_layers(box((0, 0, 0), (10, 10, 10)), 1e-9)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: layer_height 1e-09 mm is thinner than 0.001 mm (one micrometre): 10000000000 layers for a part 10 mm tall
    """
    lo, hi = mesh.bounds
    height = float(hi[2] - lo[2])
    n = int(math.ceil(height / layer_height)) if height > 0 else 1
    if layer_height < MIN_LAYER_HEIGHT:
        raise ParameterError(name, f"{layer_height:g} mm is thinner than {MIN_LAYER_HEIGHT:g} mm (one "
                                   f"micrometre): {n} layers for a part {height:.4g} mm tall")
    if n > MAX_LAYERS:
        raise ParameterError(name, f"{layer_height:g} mm makes {n} layers of a part {height:.4g} mm tall "
                                   f"(at most {MAX_LAYERS})")
    # Segments: each facet meets about (its height / layer height) planes.
    z = mesh.triangles[..., 2]
    crossings = float((z.max(axis=1) - z.min(axis=1)).sum()) / layer_height + len(mesh)
    need = crossings * _SEGMENT_BYTES
    if need > memory_budget():
        raise ParameterError(name, f"{layer_height:g} mm makes about {crossings:.3g} section segments, "
                                   f"{_gib(need)} of memory (this machine allows {_gib(memory_budget())})")
    return n


def check_print(mesh, *, layer_height: float, pixel_size: float, line_width: float, n_perimeters: int) -> None:
    """Refuse print settings the part cannot take: layers, pixels per layer, perimeters.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> part = box((0, 0, 0), (20, 20, 10))
    >>> check_print(part, layer_height=0.2, pixel_size=0.05, line_width=0.4, n_perimeters=2)
    >>> check_print(part, layer_height=0.2, pixel_size=0.05, line_width=0.4, n_perimeters=1000)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: n_perimeters 1000 would reach 400 mm inward from the outline of a part 20 mm across: at most 25 fit
    >>> check_print(part, layer_height=0.2, pixel_size=0.005, line_width=0.4, n_perimeters=2)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: pixel_size 0.005 mm makes 21.5 M pixels a layer for a part 20 x 20 mm (at most 8 M): a pixel_size of 0.0083 mm or coarser (--pixel-size) brings it within reach
    """
    check_layers(mesh, layer_height)
    lo, hi = mesh.bounds
    x, y = float(hi[0] - lo[0]), float(hi[1] - lo[1])
    fit = int(math.ceil(max(x, y) / (2 * line_width)))
    if n_perimeters > fit + 1:
        raise ParameterError("n_perimeters", f"{n_perimeters} would reach {n_perimeters * line_width:.4g} mm "
                                             f"inward from the outline of a part {max(x, y):.4g} mm across: "
                                             f"at most {fit} fit")
    if pixel_size < MIN_PIXEL_SIZE:
        raise ParameterError("pixel_size", f"{pixel_size:g} mm is finer than {MIN_PIXEL_SIZE:g} mm "
                                           f"(a tenth of a fine nozzle's line)")
    margin = 2 * (n_perimeters + 2) * line_width
    area = (x + margin) * (y + margin)
    pixels = area / pixel_size ** 2
    if pixels > MAX_LAYER_PIXELS:
        coarse = math.sqrt(area / MAX_LAYER_PIXELS)
        raise ParameterError("pixel_size", f"{pixel_size:g} mm makes {pixels / 1e6:.3g} M pixels a layer for a part "
                                           f"{x:.4g} x {y:.4g} mm (at most {MAX_LAYER_PIXELS / 1e6:g} M): "
                                           f"a pixel_size of {_up(coarse)} mm or coarser (--pixel-size) brings it "
                                           f"within reach")
    lo, hi = mesh.bounds
    layers = max(1.0, float(hi[2] - lo[2]) / layer_height)
    if pixels * layers > MAX_PRINT_PIXELS:
        fewer = float(hi[2] - lo[2]) * pixels / MAX_PRINT_PIXELS
        raise ParameterError("layer_height", f"{layer_height:g} mm makes {layers:.0f} layers of {pixels / 1e6:.3g} M "
                                             f"pixels ({pixels * layers:.3g} in all, at most {MAX_PRINT_PIXELS:.3g}): "
                                             f"a layer_height of {_up(fewer)} mm (--layer-height) or a coarser "
                                             f"pixel_size brings it within reach")
    need = pixels * _PIXEL_BYTES
    if need > memory_budget():
        raise ParameterError("pixel_size", f"{pixel_size:g} mm makes {pixels:.3g} pixels a layer for a part "
                                           f"{x:.4g} x {y:.4g} mm, {_gib(need)} of memory (this machine allows "
                                           f"{_gib(memory_budget())})")


def _up(value: float) -> str:
    """`value` rounded up to two significant digits (a setting that is surely enough)."""
    digits = 10 ** (math.floor(math.log10(value)) - 1)
    return f"{math.ceil(value / digits) * digits:.2g}"


def check_planes(planes: int, name: str = "planes") -> None:
    """Refuse more planes through an axis than a drawing or a measurement can use.

    Examples
    --------
    >>> check_planes(100000)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: planes 100000 is more than 3600 (a plane every 0.1 degree)
    """
    if planes > MAX_PLANES:
        raise ParameterError(name, f"{planes} is more than {MAX_PLANES} (a plane every 0.1 degree)")


def check_partition(mesh, volume, *, joint: str, step, max_pieces: int = 512) -> None:
    """Refuse a partition that needs more pieces, or stair teeth, than can be made.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> check_partition(box((0, 0, 0), (100, 100, 100)), (50, 50, 50), joint="stair", step=(1e-6, 1e-6))
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: step 1e-06 mm makes about 100000000 stair teeth across a joint of a part 100 mm across (at most 2000)
    """
    lo, hi = mesh.bounds
    e = hi - lo
    V = np.asarray(volume, dtype=np.float64)
    pieces = int(np.prod(np.maximum(np.ceil(e / V), 1)))
    if pieces > max_pieces:
        raise ParameterError("volume", f"{'x'.join(f'{v:g}' for v in V)} mm needs at least {pieces} pieces for a "
                                       f"part {' x '.join(f'{v:.4g}' for v in e)} mm (at most {max_pieces})")
    if joint == "stair":
        h, d = (float(v) for v in step)
        bands = float(e.max()) / min(h, d)
        if bands > MAX_STAIR_BANDS:
            raise ParameterError("step", f"{min(h, d):g} mm makes about {bands:.0f} stair teeth across a joint "
                                         f"of a part {float(e.max()):.4g} mm across (at most {MAX_STAIR_BANDS})")


def likely_units(size: float, low: float = 2.0, high: float = 5000.0) -> str | None:
    """A sentence naming the unit a part of largest dimension `size` (read as mm) was likely written in,
    when that size is implausible for a lab's objects; None when it is plausible.

    Examples
    --------
    >>> likely_units(0.14)
    'the part is 0.14 mm across: written in metres? (--units m makes it 140 mm)'
    >>> likely_units(120.0) is None
    True
    """
    if low <= size <= high:
        return None
    from ..mesh.formats import UNITS
    # The unit that brings the size nearest the middle of the plausible range (in log scale).
    target = math.sqrt(low * high)
    names = {"m": "metres", "cm": "centimetres", "in": "inches"}
    if size < low:
        unit = min(names, key=lambda u: abs(math.log(size * UNITS[u] / target)))
        return (f"the part is {size:.4g} mm across: written in {names[unit]}? "
                f"(--units {unit} makes it {size * UNITS[unit]:.4g} mm)")
    factor = 10 ** math.ceil(math.log10(size / target))
    return f"the part is {size:.4g} mm across: written in a smaller unit? (--scale {1 / factor:g} makes it " \
           f"{size / factor:.4g} mm)"

