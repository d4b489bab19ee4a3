"""The formats besides STL: PLY (binary or ASCII), Wavefront OBJ and 3MF; and units.

Scanners and GigaMesh write PLY and OBJ, slicers and CAD tools save 3MF
(`slicelab.mesh.threemf`). A PLY header is read and checked here, within
64 KiB, before meshio parses the body: meshio's own header reader loops
forever on a header that ends early (``ply`` and nothing else), reads some
types with the wrong sign and walks element counts no file of its size could
hold. meshio gets the header rewritten in the forms it reads right, and what
it returns is checked against the header's counts. OBJ is read here, its
numbers by numpy's C parser: meshio turns relative (negative) face indices
into wrong ones and fails unless texture coordinates are one per vertex.
Faces with more than three corners (quads of a scan's grid, polygons of a
CAD export) are split into triangles by a fan from their first corner.
Every failure is one `MeshFileError` naming the file and the reason, as for
STL.

Units: slicelab works in millimetres. `UNITS` maps a unit name to its size
in mm; `load(..., units="m")` scales a file written in metres.

See Also
--------
slicelab.mesh.load : which reads STL itself and these formats through here.
"""
from __future__ import annotations

import contextlib
import io
import itertools
import math
import re
import warnings
from pathlib import Path

import numpy as np

__all__ = ["SCAN_FORMATS", "UNITS", "read_scan", "unit_scale", "is_scan_format"]

#: File endings read here rather than as STL.
SCAN_FORMATS = {".ply": "ply", ".obj": "obj", ".3mf": "3mf"}

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
    """'ply', 'obj' or '3mf' when the file's ending or first bytes say so, else None.

    A ZIP archive without the ending is recognised as 3MF by `load`, after the
    STL layouts have been ruled out.
    """
    kind = SCAN_FORMATS.get(Path(path).suffix.lower())
    if kind:
        return kind
    if head.startswith(b"ply\n") or head.startswith(b"ply\r\n"):
        return "ply"
    return None


def read_scan(path, kind: str, error) -> tuple[np.ndarray, np.ndarray]:
    """Triangles (n, 3, 3) and zero stored normals of a PLY, OBJ or 3MF file; `error(reason)` makes the exception.

    Examples
    --------
    >>> import tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "quad.obj")
    >>> _ = open(f, "w").write("v 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nf 1 2 3 4\\n")
    >>> t, n = read_scan(f, "obj", ValueError)
    >>> t.shape, float(t[:, :, 2].sum())
    ((2, 3, 3), 0.0)
    """
    if kind == "3mf":
        from .threemf import read_3mf
        triangles = read_3mf(path, error)
    else:
        points, faces = (_read_obj if kind == "obj" else _read_ply)(Path(path), error)
        triangles = points[faces]
    return triangles, np.zeros((len(triangles), 3))


def _fan(flat: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Triangles (m, 3) of index rows (0, j, j + 1) over faces given as one flat index list and corner counts."""
    if (counts == 3).all():
        return flat.reshape(-1, 3)
    n_tri = counts - 2
    first = np.repeat(np.cumsum(counts) - counts, n_tri)  # where each triangle's face starts in `flat`
    j = np.arange(len(first)) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri) + 1
    return np.stack([flat[first], flat[first + j], flat[first + j + 1]], axis=1)


# --- PLY ------------------------------------------------------------------------------------------------

_PLY_HEADER_MAX = 64 * 1024
_PLY_FORMATS = ("ascii", "binary_little_endian", "binary_big_endian")
_PLY_SIZES = {"char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2, "int16": 2, "uint16": 2,
              "int": 4, "uint": 4, "int32": 4, "uint32": 4, "float": 4, "float32": 4,
              "double": 8, "float64": 8, "int64": 8, "uint64": 8}
# The names meshio's tables read correctly, for each PLY type: in binary bodies it reads
# "uchar" as signed and lacks "char", "ushort", "float64", "short" and "int16" (None: refused).
_MESHIO_BINARY = {"char": "int8", "uchar": "uint8", "ushort": "uint16", "float64": "double",
                  "short": None, "int16": None}
_MESHIO_ASCII = {"int16": "short"}
_FLOAT_TYPES = {"float", "float32", "double", "float64"}


def _ply_header(p: Path, error):
    """(format, header length in bytes, [(element, count, [(property, type, list count type or None)])])."""
    with open(p, "rb") as fh:
        head = fh.read(_PLY_HEADER_MAX)
    if head.split(b"\n", 1)[0].strip() != b"ply":
        raise error("malformed PLY file (it does not start with 'ply')")
    end = re.search(rb"(?m)^[ \t]*end_header[ \t\r]*(?:\n|\Z)", head)
    if end is None:
        if len(head) < _PLY_HEADER_MAX:
            raise error("malformed PLY file (the header ends early: no 'end_header' line)")
        raise error(f"malformed PLY file (no 'end_header' in the first {_PLY_HEADER_MAX // 1024} KiB)")
    try:
        text = head[:end.start()].decode("ascii")
    except UnicodeDecodeError:
        raise error("malformed PLY file (the header is not ASCII text)") from None
    lines = [line.strip() for line in text.split("\n")]
    # As meshio skips them: blank lines, comments and obj_info.
    lines = [line.split() for line in lines[1:] if line and not line.startswith(("comment", "obj_info"))]
    if not lines or len(lines[0]) != 3 or lines[0][0] != "format" or lines[0][1] not in _PLY_FORMATS:
        raise error("malformed PLY file (no 'format ascii|binary_little_endian|binary_big_endian 1.0' line "
                    "after 'ply')")
    fmt = lines[0][1]
    elements = []
    for words in lines[1:]:
        if words[0] == "element":
            if len(words) != 3 or not re.fullmatch(r"\d{1,18}", words[2]):
                raise error(f"malformed PLY file (bad element line {' '.join(words)[:60]!r})")
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if len(words) == 5 and words[1] == "list" and words[2] in _PLY_SIZES and words[3] in _PLY_SIZES:
                elements[-1][2].append((words[4], words[3], words[2]))
            elif len(words) == 3 and words[1] in _PLY_SIZES:
                elements[-1][2].append((words[2], words[1], None))
            else:
                raise error(f"malformed PLY file (bad property line {' '.join(words)[:60]!r})")
        else:
            raise error(f"malformed PLY file (unexpected header line {' '.join(words)[:60]!r})")
    return fmt, end.end(), elements


def _ply_layout(fmt: str, elements, error):
    """The vertex and face elements meshio is to read, refusing layouts it would misread."""
    names = [e[0] for e in elements]
    if not names or names[0] != "vertex":
        raise error(f"malformed PLY file (the first element is {names[0] if names else 'missing'!r}, "
                    f"not 'vertex')")
    vertex = elements[0]
    face = elements[1] if len(elements) > 1 else None
    if face is not None and face[0] != "face":
        raise error(f"PLY element {face[0]!r} between vertices and faces is not supported")
    props = [prop[0] for prop in vertex[2]]
    if any(prop[2] for prop in vertex[2]):
        raise error("PLY vertices with list properties are not supported")
    for axis in "xyz":
        if axis not in props:
            raise error(f"malformed PLY file (vertices have no {axis!r} property)")
        if vertex[2][props.index(axis)][1] not in _FLOAT_TYPES:
            raise error(f"PLY coordinates of type {vertex[2][props.index(axis)][1]!r} are not supported "
                        "(float or double)")
    if fmt == "ascii" and props[:3] != ["x", "y", "z"]:
        raise error("PLY ASCII vertices must begin with x, y, z")  # meshio takes the first three columns
    if face is not None:
        fprops = face[2]
        if not fprops or fprops[0][0] not in ("vertex_indices", "vertex_index") or fprops[0][2] is None:
            raise error("malformed PLY file (faces do not begin with a 'vertex_indices' list)")
        if any(prop[2] for prop in fprops[1:]) or (fmt != "ascii" and len(fprops) > 1):
            raise error("PLY faces with properties besides their vertex list are not supported in binary files "
                        "(or lists in ASCII ones)")
        if fprops[0][1] in _FLOAT_TYPES or fprops[0][2] in _FLOAT_TYPES:
            raise error("malformed PLY file (face indices are not integers)")
    return vertex, face


def _read_ply(p: Path, error):
    fmt, start, elements = _ply_header(p, error)
    vertex, face = _ply_layout(fmt, elements, error)
    size = p.stat().st_size - start
    n_vertices, n_faces = vertex[1], face[1] if face else 0
    binary = fmt != "ascii"
    # The least a body can hold: every property, and at least three indices to a face. Checked before
    # meshio allocates or walks 10^12 faces.
    if binary:
        least = (n_vertices * sum(_PLY_SIZES[t] for _, t, _ in vertex[2])
                 + (n_faces * (_PLY_SIZES[face[2][0][2]] + 3 * _PLY_SIZES[face[2][0][1]]) if face else 0))
    else:  # a digit and a separator a number
        least = 2 * (n_vertices * len(vertex[2]) + (n_faces * (len(face[2]) + 3) if face else 0)) - 1
    if least > size:
        raise error(f"malformed PLY file (the header claims {n_vertices} vertices and {n_faces} faces, "
                    f"at least {least} bytes, but {size} bytes follow it)")
    rename = _MESHIO_BINARY if binary else _MESHIO_ASCII
    header = [f"ply\nformat {fmt} 1.0"]
    for name, count, props in (vertex, face) if face else (vertex,):
        header.append(f"element {name} {count}")
        for prop, kind, count_kind in props:
            kinds = [kind] if count_kind is None else [count_kind, kind]
            if any(k in rename and rename[k] is None for k in kinds):
                raise error(f"PLY properties of type {kind!r} in binary files are not supported")
            kinds = [rename.get(k, k) for k in kinds]
            prop = "vertex_indices" if count_kind and prop == "vertex_index" else prop
            header.append(f"property {'list ' if count_kind else ''}{' '.join(kinds)} {prop}")
    header.append("end_header\n")
    with open(p, "rb") as fh:
        fh.seek(start)
        body = fh.read()
    import meshio
    try:
        # meshio prints warnings about what it skips (normals, colours): not the user's concern here.
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = meshio.read(io.BytesIO("\n".join(header).encode() + body), file_format="ply")
    except (Exception, SystemExit) as exc:  # meshio raises assorted types, and exits on some headers
        text = re.sub(r"\s+", " ", str(exc)).strip() or type(exc).__name__
        text = re.sub(r"(Line #\d+ \([^)]*\)).*", r"\1 ...", text)[:160]  # numpy lists every bad line
        raise error(f"malformed PLY file (its body does not match its header: {text})") from None
    with np.errstate(all="ignore"):  # garbage read as coordinates: refused below or by `load`
        points = np.asarray(m.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] < 3 or len(points) != n_vertices:
        raise error(f"malformed PLY file ({len(points)} of the {n_vertices} vertices read: truncated?)")
    blocks = [np.asarray(block.data) for block in m.cells]  # over cell blocks (one per face size), not faces
    if any(b.ndim != 2 or b.shape[1] < 3 for b in blocks if b.size):
        raise error("malformed PLY file (a face with fewer than three corners: truncated or garbage?)")
    blocks = [b for b in blocks if b.size]
    if sum(len(b) for b in blocks) != n_faces:
        raise error(f"malformed PLY file ({sum(len(b) for b in blocks)} of the {n_faces} faces read)")
    if not blocks:
        raise error(f"has no faces (PLY file with {n_vertices} vertices and no faces)")
    faces = np.concatenate([_fan(b.astype(np.int64).ravel(), np.full(len(b), b.shape[1])) for b in blocks])
    if faces.min() < 0 or faces.max() >= len(points):
        raise error("malformed PLY file (a face names a vertex that does not exist)")
    return points[:, :3], faces


# --- OBJ ------------------------------------------------------------------------------------------------

def _keyword_cut(lines, keyword: bytes) -> bytes:
    """The lines joined, each without its leading keyword and space (kept: the newline before each line)."""
    return (b"\n" + b"\n".join(lines)).replace(b"\n" + keyword + b" ", b"\n")


def _loadtxt(text: bytes, n_lines: int, what: str, error, **kw) -> np.ndarray | None:
    """Rows of numbers, one a line, parsed by numpy's C reader; None when lines hold different counts."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            rows = np.loadtxt(io.BytesIO(text), ndmin=2, encoding="latin1", **kw)
    except UserWarning:  # no data at all: only comments after the keywords
        raise error(f"malformed OBJ file (a {what} line holds no numbers)") from None
    except ValueError as exc:
        reason = str(exc)
        if "number of columns changed" in reason:
            return None
        bad = re.search(r"could not convert string '(.*)' to (\w+)", reason)
        if bad and re.fullmatch(r"[+-]?\d+", bad.group(1)):  # digits only: beyond 64-bit integers
            reason = f"index {bad.group(1)[:40]} is out of range"
        elif bad:
            reason = f"{bad.group(1)[:40]!r} is not a number"
        elif "invalid column index" in reason:
            reason = "fewer than three coordinates"
        raise error(f"malformed OBJ file ({what}: {reason[:120]})") from None
    if len(rows) != n_lines:  # a line with only a comment after its keyword: numpy skips it
        raise error(f"malformed OBJ file (a {what} line holds no numbers)")
    return rows


def _ragged_faces(text: bytes, n_lines: int, error):
    """Indices and corner counts of faces of different sizes: the lines grouped by their count of numbers."""
    if b"#" in text:
        text = re.sub(rb"#[^\n]*", b"", text)
    arr = np.frombuffer(text, np.uint8)
    space = np.isin(arr, np.frombuffer(b" \t\r\n\v\f", np.uint8))
    starts = np.flatnonzero(~space & np.concatenate([[True], space[:-1]]))
    # `text` starts with a newline: the k-th line's numbers follow the (k + 1)-th newline.
    counts = np.bincount(np.searchsorted(np.flatnonzero(arr == 10), starts) - 1, minlength=n_lines)
    if counts.min() < 3:
        raise error("malformed OBJ file (a face with fewer than three corners)")
    lines, at = text.split(b"\n")[1:], np.cumsum(counts) - counts
    flat = np.empty(int(counts.sum()), np.int64)
    for k in np.unique(counts):  # over face sizes, a few
        group = counts == k
        rows = _loadtxt(b"\n" + b"\n".join(itertools.compress(lines, group)), int(group.sum()), "face", error,
                        dtype=np.int64)
        if rows is None or rows.shape[1] != k:  # numpy splits at more than ASCII spaces (a no-break space)
            raise error("malformed OBJ file (face: numbers separated by characters other than spaces)")
        flat[at[group][:, None] + np.arange(k)] = rows
    return flat, counts


def _read_obj(p: Path, error):
    """Vertices (n, 3) and triangles (m, 3) of an OBJ file: ``v`` and ``f`` lines, the rest ignored.

    Lines are sorted by keyword in one Python pass; the numbers of all
    ``v`` lines, then of all ``f`` lines, are parsed by numpy's loadtxt.
    Indices count from 1; a negative one counts back from the last vertex
    defined before its face (-1 is that vertex); ``v/vt/vn`` and ``v//vn`` keep ``v``.
    """
    data = p.read_bytes()
    if b"\\" in data:  # a backslash at the end of a line continues it
        data = re.sub(rb"\\[ \t]*\r?\n", b" ", data)
    if b"\t" in data:
        data = data.replace(b"\t", b" ")
    lines = data.splitlines()
    if data.startswith(b" ") or b"\n " in data or b"\r " in data:
        lines = [line.lstrip() for line in lines]
    keys = np.array([line[:2] for line in lines], dtype="S2")
    is_v, is_f = keys == b"v ", keys == b"f "
    if ((keys == b"v") | (keys == b"f")).any():
        raise error("malformed OBJ file (a 'v' or 'f' line holds no numbers)")
    if not is_f.any():
        raise error(f"has no faces (OBJ file with {int(is_v.sum())} vertices and no faces)")
    if not is_v.any():
        raise error("malformed OBJ file (faces but no vertices)")
    n_v, n_f = int(is_v.sum()), int(is_f.sum())
    points = _loadtxt(_keyword_cut(itertools.compress(lines, is_v), b"v"), n_v, "vertex", error,
                      usecols=(0, 1, 2))
    text = _keyword_cut(itertools.compress(lines, is_f), b"f")
    if b"/" in text:  # v/vt/vn, v//vn, v/vt: the vertex is the number before the first slash
        if b" /" in text or b"\n/" in text:
            raise error("malformed OBJ file (a face corner without its vertex number)")
        text = re.sub(rb"/\S*", b"", text)
    rows = _loadtxt(text, n_f, "face", error, dtype=np.int64)
    if rows is not None:
        flat, counts = rows.ravel(), np.full(len(rows), rows.shape[1])
    else:  # triangles and quads, say
        flat, counts = _ragged_faces(text, n_f, error)
    if counts.min() < 3:
        raise error("malformed OBJ file (a face with fewer than three corners)")
    if (flat == 0).any():
        raise error("malformed OBJ file (face index 0: OBJ counts vertices from 1)")
    if (flat < 0).any():  # relative: -1 is the last vertex defined before the face's line
        base = np.repeat(np.cumsum(is_v)[is_f], counts)
        flat = np.where(flat < 0, flat + base, flat - 1)
        if flat.min() < 0:
            raise error("malformed OBJ file (a relative face index reaches before the first vertex)")
    else:
        flat = flat - 1
    if flat.max() >= n_v:
        raise error(f"malformed OBJ file (a face names vertex {int(flat.max()) + 1} of {n_v})")
    return points, _fan(flat, counts)
