"""Writing build plates: each plate as one STL with its pieces in place, a JSON of placements, a top view.

Shared by ``slicelab arrange`` (pieces from files) and ``slicelab partition
--plates`` (the pieces a partition just made).
"""
from __future__ import annotations

import json
from pathlib import Path

from ..files.atomic import atomic_open
from .spec import reason

__all__ = ["write_plates", "arrange_files"]


def write_plates(pieces, names, build_volume, folder, *, spacing: float = 5.0, rotate: bool = True,
                 preview: bool = True) -> tuple[dict, list]:
    """Arrange `pieces` onto plates and write ``plate_NN.stl``, ``plates.json`` and ``plate_NN.png``.

    Returns the results (plain JSON) and the reasons (a plate whose file is
    not watertight as written).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from slicelab.samples import box
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> res, why = write_plates([box((0, 0, 0), (90, 90, 10))] * 5, ["a", "b", "c", "d", "e"],
    ...                         (200, 200, 100), d, preview=False)
    >>> res["plates_used"], res["lower_bound"], sorted(p.name for p in d.iterdir())
    (2, 2, ['plate_01.stl', 'plate_02.stl', 'plates.json'])
    """
    from ..mesh.written import write_mesh
    from ..slicing.plates import arrange
    folder = Path(folder)
    plates = arrange(pieces, build_volume, spacing=spacing, rotate=rotate)
    width = max(2, len(str(len(plates))))
    info, reasons = plates.to_dict(), []
    for k, plate in enumerate(info["plates"]):  # over plates
        name = f"plate_{k + 1:0{width}d}"
        written = write_mesh(plates.plate_mesh(k, pieces), folder / f"{name}.stl")
        plate["file"] = f"{name}.stl"
        plate["piece_files"] = [names[i] for i in plate["pieces"]]
        plate["bodies"] = written.report.n_shells
        plate["watertight"] = bool(written.report.watertight)
        if not written.report.watertight:
            reasons.append(reason("not_watertight", f"{name}.stl as written is not watertight"))
        if preview:
            from ..viz.plates import save_plate_png
            save_plate_png(plates, k, pieces, folder / f"{name}.png", names=names)
    results = {"pieces": len(pieces), "plates_used": len(plates), "one_per_plate": len(pieces),
               "lower_bound": plates.lower_bound, "fill": plates.fill}
    with atomic_open(folder / "plates.json", "w", encoding="utf-8") as fh:
        json.dump({**results, **info}, fh, indent=1)
    return results, reasons


def arrange_files(paths, build_volume, folder, *, spacing: float = 5.0, rotate: bool = True, preview: bool = True,
                  units=None, scale=None) -> tuple[dict, list]:
    """`write_plates` for pieces read from mesh files (each file one piece)."""
    from ..mesh import load
    pieces = [load(p, units=units, scale=scale) for p in paths]
    return write_plates(pieces, [Path(p).name for p in paths], build_volume, folder, spacing=spacing,
                        rotate=rotate, preview=preview)
