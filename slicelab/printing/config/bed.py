"""Does the part fit the printer? Its footprint on the bed, its height, its skirt and brim.

The part is centred on the bed at `PrintSettings.centre`; its footprint (x
and y extent) with the first layer's skirt and brim must lie on the bed
(`bed_size`), and its height must not pass `max_height`. A part that does
not fit is refused before anything is sliced, with a message that begins
with the setting it breaks.

See Also
--------
slicelab.printing.planner.plan : checks it.
slicelab.printing.steps.skirt.skirt_margin : how far the skirt and brim reach.
"""
from __future__ import annotations

import numpy as np

from ..steps.skirt import skirt_margin

__all__ = ["check_bed", "footprint_extent"]


def check_bed(mesh, settings, first_layer=None) -> None:
    """Refuse a part that does not fit the printer: its footprint centred on the bed, its height.

    Parameters
    ----------
    mesh : Mesh
    settings : PrintSettings
        `bed_size`, `centre` (`bed_center` or the bed's middle), `max_height`, and the
        skirt and brim's settings.
    first_layer : Section, optional
        The first layer (part coordinates): its skirt and brim must fit the bed too.

    Raises
    ------
    ValueError
        Its message begins with the setting the part breaks (``bed_size``,
        ``bed_center`` or ``max_height``).

    See Also
    --------
    slicelab.printing.planner.plan : checks it before slicing and once the first layer is cut.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.printing.planner import PrintSettings
    >>> check_bed(box((0, 0, 0), (200, 200, 10)), PrintSettings())
    Traceback (most recent call last):
    ...
    ValueError: bed_size 250 x 210 mm: the part's footprint is 200 x 200 mm, with its skirt 212.8 x 212.8 mm
    >>> check_bed(box((0, 0, 0), (406, 610, 10)), PrintSettings())
    Traceback (most recent call last):
    ...
    ValueError: bed_size 250 x 210 mm: the part's footprint is 406 x 610 mm
    >>> check_bed(box((0, 0, 0), (20, 20, 250)), PrintSettings())
    Traceback (most recent call last):
    ...
    ValueError: max_height 210 mm: the part is 250 mm tall
    """
    s = settings
    lo, hi = (np.asarray(b, np.float64) for b in mesh.bounds)
    size = hi - lo
    bed = np.asarray(s.bed_size)
    bed_text = f"bed_size {bed[0]:g} x {bed[1]:g} mm"
    if size[2] > s.max_height:
        raise ValueError(f"max_height {s.max_height:g} mm: the part is {size[2]:.4g} mm tall")
    if np.any(size[:2] > bed):
        raise ValueError(f"{bed_text}: the part's footprint is {size[0]:.4g} x {size[1]:.4g} mm")
    centre = np.asarray(s.centre)
    margin = skirt_margin(s.line_width, s.skirt_loops, s.skirt_distance, s.brim_width)
    if first_layer is not None and len(first_layer.segments):
        flo, fhi = first_layer.bounds()
        flo, fhi = flo[:2] - margin, fhi[:2] + margin
    else:  # the first layer is not known yet: the whole footprint stands for it
        flo, fhi = lo[:2] - margin, hi[:2] + margin
    shift = centre - (lo[:2] + hi[:2]) / 2
    flo, fhi = flo + shift, fhi + shift
    if np.any(fhi - flo > bed):
        raise ValueError(f"{bed_text}: the part's footprint is {size[0]:.4g} x {size[1]:.4g} mm, with its skirt "
                         f"{fhi[0] - flo[0]:.4g} x {fhi[1] - flo[1]:.4g} mm")
    if np.any(flo < -1e-9) or np.any(fhi > bed + 1e-9):
        raise ValueError(f"bed_center ({centre[0]:g}, {centre[1]:g}): the part centred there, "
                         f"{fhi[0] - flo[0]:.4g} x {fhi[1] - flo[1]:.4g} mm with its skirt, reaches past the "
                         f"bed's edge ({bed[0]:g} x {bed[1]:g} mm)")


def footprint_extent(lo: np.ndarray, hi: np.ndarray, first, settings) -> tuple:
    """``(x0, y0, x1, y1)`` (part coordinates): the footprint's box (`lo`, `hi`), and the first
    layer's box widened by how far its skirt and brim reach (`slicelab.printing.PrintPlan.extent`)."""
    s = settings
    margin = skirt_margin(s.line_width, s.skirt_loops, s.skirt_distance, s.brim_width)
    if margin > 0 and len(first.segments):
        flo, fhi = first.bounds()
        lo, hi = np.minimum(lo, flo[:2] - margin), np.maximum(hi, fhi[:2] + margin)
    return tuple(float(v) for v in (*lo, *hi))
