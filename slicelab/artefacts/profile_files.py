"""A vessel's profile for CAD and GIS: the section as DXF polylines and its outline points as CSV, in mm.

Both are written from `slicelab.artefacts.drawing.parts`, the same
geometry the SVG and PNG drawings show, in the profile's own (r, z) plane:
r >= 0 away from the axis, z up from the base, 1 unit = 1 mm, unmirrored
(a drawing puts the section on either side; CAD gets it as measured).

DXF (ezdxf, imported only here), one layer per part:

==================  ==================================================================
``SECTION``         the drawn half-section: its outline and voids, closed polylines
``EXTERIOR``        the outline where it is the vessel's outer surface
``INTERIOR``        where it is the inner surface
``RIM``             the lip, or a whole vessel's top between the two
``BREAKS``          a sherd's ends that are breaks, not the vessel's surface
``BREAK_SYMBOLS``   the jagged line drawn beside each break
``AXIS``            the axis of revolution (r = 0), and where a half meets it
``APPENDAGE``       each handle, spout or lug outlined in the plane through it
``APPENDAGE_SECTION``  each handle's cross-section beside it, and where it is cut
``NOTES``           the name, and "orientation uncertain" where up is a guess
==================  ==================================================================

The surface layers walk the section's outline once together (each stretch
ends on the point where the next begins). CSV: one row per outline point
of every half-section (``half``, ``angle_deg``, ``drawn``, ``ring``,
``point``, ``r_mm``, ``z_mm``, ``surface``), the numbers written so that
they read back exactly.
"""
from __future__ import annotations

import csv
import math
import threading

import numpy as np

from ..files.atomic import atomic_open, atomic_path

__all__ = ["profile_dxf", "profile_csv", "CSV_COLUMNS", "DXF_LAYERS"]

#: The columns of the outline CSV.
CSV_COLUMNS = ("half", "angle_deg", "drawn", "ring", "point", "r_mm", "z_mm", "surface")
#: Each DXF layer and its colour (AutoCAD colour index).
DXF_LAYERS = {"SECTION": 7, "EXTERIOR": 5, "INTERIOR": 3, "RIM": 1, "BREAKS": 6, "BREAK_SYMBOLS": 6, "AXIS": 8,
              "APPENDAGE": 7, "APPENDAGE_SECTION": 7, "NOTES": 7}
_LAYER_OF = {"exterior": "EXTERIOR", "interior": "INTERIOR", "rim": "RIM", "break": "BREAKS", "axis": "AXIS"}
# ezdxf stamps every file with the time and random ids unless told otherwise (a process-wide
# option): held under a lock while a document is made and written, so that two threads' files are
# both fixed.
_FIXED = threading.Lock()


def profile_dxf(profile, path) -> None:
    """Write the profile as a DXF drawing (R2010, millimetres), atomically.

    The file is the same, byte for byte, whenever the profile is, in any
    process: ezdxf's time stamps and ids are written fixed, its classes in
    a fixed order.

    Parameters
    ----------
    profile : Profile
    path : str or os.PathLike

    See Also
    --------
    profile_csv : the outline points of every half.
    slicelab.artefacts.drawing.parts : what is written.

    Examples
    --------
    >>> import os, tempfile, ezdxf
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> path = os.path.join(tempfile.mkdtemp(), "pot.dxf")
    >>> profile_dxf(profile(pot(20, 24), planes=2), path)
    >>> sorted({e.dxf.layer for e in ezdxf.readfile(path).modelspace()})
    ['AXIS', 'EXTERIOR', 'INTERIOR', 'NOTES', 'RIM', 'SECTION']
    """
    import ezdxf

    from ..artefacts.drawing import parts
    d = parts(profile)
    with _FIXED:
        before = ezdxf.options.write_fixed_meta_data_for_testing
        ezdxf.options.write_fixed_meta_data_for_testing = True
        try:
            doc = _document(ezdxf, profile, d)
            # ezdxf lists the classes of the entity types in use in the order of a set, which differs
            # from process to process (string hashing): registered here first, in a fixed order.
            from ezdxf.sections.classes import REQ_R2004, REQUIRED_CLASSES
            for name in [*REQUIRED_CLASSES.get(doc.dxfversion, REQ_R2004), *sorted(doc.entitydb.dxf_types_in_use())]:
                doc.classes.add_class(name)
            with atomic_path(path) as tmp:
                doc.saveas(tmp)
        finally:
            ezdxf.options.write_fixed_meta_data_for_testing = before


def _document(ezdxf, profile, d):
    """The DXF document of the profile's `parts` `d`."""
    h = d["half"]
    doc = ezdxf.new("R2010", setup=["linetypes"], units=4)  # 4: millimetres
    doc.header["$MEASUREMENT"] = 1  # metric
    for name, colour in DXF_LAYERS.items():
        layer = doc.layers.add(name, color=colour)
        if name == "AXIS":
            layer.dxf.linetype = "DASHDOT"
    msp = doc.modelspace()

    def poly(points, layer, close=False):
        msp.add_lwpolyline([(float(x), float(y)) for x, y in points], format="xy", close=close,
                           dxfattribs={"layer": layer})

    for ring in (h.polygon, *h.holes):
        poly(ring, "SECTION", close=True)
    for surface, points in d["runs"]:
        poly(points, _LAYER_OF[surface])
    z = np.concatenate([x.polygon[:, 1] for x in profile.halves])
    msp.add_line((0.0, float(z.min()) - 5.0), (0.0, float(z.max()) + 5.0), dxfattribs={"layer": "AXIS"})
    for points in d["break_symbols"]:
        poly(points, "BREAK_SYMBOLS")
    for points in d["appendages"]:
        poly(points, "APPENDAGE")
    for rings, cut in d["appendage_sections"]:
        for ring in rings:
            poly(ring, "APPENDAGE_SECTION", close=True)
        poly(cut, "APPENDAGE_SECTION")
    notes = [profile.name or ("sherd" if getattr(profile, "sherd", None) is not None else "vessel")]
    if d["uncertain"]:
        notes.append("orientation uncertain")
    for k, text in enumerate(notes):
        msp.add_text(text, height=3.0, dxfattribs={"layer": "NOTES", "insert": (0.0, float(z.min()) - 10.0 - 5 * k)})
    return doc


def profile_csv(profile, path) -> None:
    """Write the outline points of every half-section as CSV, atomically.

    One row per point: ``half`` (its index, in order of angle),
    ``angle_deg`` (its direction about the axis), ``drawn`` (``yes`` for
    the half the drawing shows), ``ring`` (0 for the wall's outline, 1, 2
    ... for voids inside it), ``point`` (index along the ring,
    counter-clockwise), ``r_mm`` and ``z_mm``, and ``surface``: what the
    outline is from this point to the next
    (`slicelab.artefacts.drawing.surfaces`: exterior, interior, rim, break,
    axis; ``void`` along the rings of voids). Numbers are written in full,
    so they read back exactly.

    See Also
    --------
    profile_dxf : the drawn half as CAD polylines.
    slicelab.artefacts.drawing.surfaces : how each point's surface is told.

    Examples
    --------
    >>> import csv, os, tempfile
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> path = os.path.join(tempfile.mkdtemp(), "pot.csv")
    >>> profile_csv(profile(pot(20, 24), planes=2), path)
    >>> rows = list(csv.DictReader(open(path, newline="")))
    >>> sorted({r["surface"] for r in rows}), {r["half"] for r in rows if r["drawn"] == "yes"}
    (['axis', 'exterior', 'interior', 'rim'], {'0'})
    """
    from ..artefacts.drawing import surfaces
    sherd = getattr(profile, "sherd", None)
    with atomic_open(path, "w", encoding="utf-8", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for k, h in enumerate(profile.halves):  # tens of halves
            angle = math.degrees(h.angle)
            drawn = "yes" if k == profile.representative else "no"
            labels = surfaces(h, sherd)
            for ring, (points, names) in enumerate([(h.polygon, labels),
                                                     *[(x, ["void"] * len(x)) for x in h.holes]]):
                w.writerows((k, angle, drawn, ring, i, float(r), float(z), name)
                            for i, ((r, z), name) in enumerate(zip(points, names)))
