"""The formats scanners write (PLY, binary or ASCII, and Wavefront OBJ), read through meshio, and units.

Scanners and GigaMesh write PLY and OBJ; meshio parses them. Faces with more
than three corners (quads of a scan's grid, polygons of a CAD export) are
split into triangles by a fan from their first corner. Every failure is one
`MeshFileError` naming the file and the reason, as for STL.

Units: slicelab works in millimetres. `UNITS` maps a unit name to its size
in mm; `load(..., units="m")` scales a file written in metres.

See Also
--------
slicelab.mesh.load : which reads STL itself and these formats through here.
"""
from __future__ import annotations

import contextlib
import io
import math
from pathlib import Path

import numpy as np

__all__ = ["SCAN_FORMATS", "UNITS", "read_scan", "unit_scale", "is_scan_format"]

#: File endings read through meshio.
SCAN_FORMATS = {".ply": "ply", ".obj": "obj"}

#: Size of each unit in millimetres.
UNITS = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}


def unit_scale(units: str | None = None, scale: float | None = None) -> float:
    """The factor that turns a file's coordinates into millimetres.

    Examples
    --------
    >>> unit_scale("m"), unit_scale("in", 2), unit_scale()
    (1000.0, 50.8, 1.0)
    """
    factor = 1.0
    if units is not None:
        if units not in UNITS:
            raise ValueError(f"units must be one of {', '.join(UNITS)}, got {units!r}")
        factor = UNITS[units]
    if scale is not None:
        s = float(scale)
        if not (math.isfinite(s) and s > 0):
            raise ValueError(f"scale must be a positive number, got {scale!r}")
        factor *= s
    return factor


def is_scan_format(path, head: bytes) -> str | None:
    """'ply' or 'obj' when the file's ending or first bytes say so, else None."""
    kind = SCAN_FORMATS.get(Path(path).suffix.lower())
    if kind:
        return kind
    if head.startswith(b"ply\n") or head.startswith(b"ply\r\n"):
        return "ply"
    return None


def read_scan(path, kind: str, error) -> tuple[np.ndarray, np.ndarray]:
    """Triangles (n, 3, 3) and zero stored normals of a PLY or OBJ file; `error(reason)` makes the exception.

    Examples
    --------
    >>> import tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "quad.obj")
    >>> _ = open(f, "w").write("v 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nf 1 2 3 4\\n")
    >>> t, n = read_scan(f, "obj", ValueError)
    >>> t.shape, float(t[:, :, 2].sum())
    ((2, 3, 3), 0.0)
    """
    import meshio
    try:
        # meshio prints warnings about what it skips (normals, colours): not the user's concern here.
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            m = meshio.read(str(path), file_format=kind)
    except (Exception, SystemExit) as exc:  # meshio raises assorted types, and exits on some headers
        text = str(exc).replace("\n", " ").strip()[:200] or type(exc).__name__
        raise error(f"malformed {kind.upper()} file ({text})") from None
    points = np.asarray(m.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] < 3:
        raise error(f"malformed {kind.upper()} file (vertices need 3 coordinates)")
    points = points[:, :3]
    tris = []
    for block in m.cells:  # over cell blocks (one per face size), not faces
        faces = np.asarray(block.data)
        if block.type in ("triangle", "quad", "polygon") and faces.ndim == 2 and faces.shape[1] >= 3:
            k = faces.shape[1]
            # A fan from the first corner: (0, j, j + 1) for j = 1 .. k - 2.
            j = np.arange(1, k - 1)
            tris.append(np.stack([np.repeat(faces[:, :1], k - 2, axis=1), faces[:, j], faces[:, j + 1]],
                                 axis=2).reshape(-1, 3))
    if not tris:
        raise error(f"has no faces ({kind.upper()} file with {len(points)} vertices and no triangles)")
    faces = np.concatenate(tris).astype(np.int64)
    if faces.min() < 0 or faces.max() >= len(points):
        raise error(f"malformed {kind.upper()} file (a face names a vertex that does not exist)")
    return points[faces], np.zeros((len(faces), 3))
