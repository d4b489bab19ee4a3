"""Reading meshes (STL, and through `slicelab.mesh.formats` PLY, OBJ and 3MF), writing STL, safe output.

Binary files are read and written as numpy record arrays (`STL_RECORD`);
numpy-stl parses and writes ASCII. This module decides which format a file is in, refuses
files that cannot be a mesh before anything is allocated, and turns every
failure into one `MeshFileError` that names the file and the reason: whatever
the format, a file either loads as the mesh it holds or is refused, with no
hang and no other exception. Coordinates that are NaN, infinite or beyond
single precision (what STL stores and the slicer computes in) are refused.
"""
from __future__ import annotations

import io
import re
import stat
from pathlib import Path

import numpy as np

from ..files.atomic import atomic_open, atomic_path
from .formats import is_scan_format, read_scan, unit_scale
from .core import Mesh

__all__ = ["MeshFileError", "load", "save", "write_binary_stl", "STL_RECORD"]

_HEADER = 80
_RECORD = 50  # 12 float32 + uint16 attribute
#: One facet of a binary STL file: normal, three corners (float32, little-endian), attribute word.
STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attr", "<u2")])
assert STL_RECORD.itemsize == _RECORD
#: Facets encoded at once when writing (a few MB: the record buffer stays small and in cache).
_WRITE_CHUNK = 1 << 16
#: The largest float32, beyond which a coordinate cannot be stored in STL or sliced.
_SINGLE_MAX = float(np.finfo(np.float32).max)
_MAGIC = {
    b"\x89PNG": "a PNG image", b"\xff\xd8\xff": "a JPEG image", b"PK\x03\x04": "a ZIP archive, not a 3MF",
    b"%PDF": "a PDF document", b"GIF8": "a GIF image", b"\x1f\x8b": "a gzip archive",
    b"ply": "a PLY mesh", b"o ": "an OBJ mesh", b"# ": "a text file",
}


class MeshFileError(ValueError):
    """An input file that is not a usable mesh.

    The message always names the file and the reason, on one line.
    """

    def __init__(self, path, reason: str):
        self.path = str(path)
        self.reason = reason
        super().__init__(f"{path}: {reason}")


def _describe_foreign(head: bytes) -> str | None:
    for magic, what in _MAGIC.items():
        if head.startswith(magic):
            return what
    return None


def load(path, *, units: str | None = None, scale: float | None = None) -> Mesh:
    """Read a mesh file: binary or ASCII STL, PLY (binary or ASCII), OBJ or 3MF.

    STL binary files are recognised by their size (84 bytes + 50 per
    triangle, as the header's count claims), so a binary file whose header
    starts with ``solid`` is still read as binary. ASCII files may hold
    several solids, odd spacing and CRLF line ends. PLY, OBJ and 3MF are
    recognised by their ending (a PLY also by its first line, a 3MF also as
    a ZIP archive holding a 3D model) and read by `slicelab.mesh.formats`:
    PLY through meshio after its header is checked; OBJ with relative
    (negative) indices and ``v/vt/vn`` corners; 3MF as all its build items
    with their transforms, in millimetres (`slicelab.mesh.threemf`). Faces of
    four or more corners become triangles (a fan from the first corner).

    Parameters
    ----------
    path : str or os.PathLike
    units : {"mm", "cm", "m", "in"}, optional
        The unit the file is written in; coordinates are scaled to mm. A 3MF
        file states its own unit, which is applied first: `units` and `scale`
        then multiply the millimetres.
    scale : float, optional
        A further factor applied to the coordinates.

    Returns
    -------
    Mesh

    Raises
    ------
    MeshFileError
        The file is missing, a directory or another non-regular file, empty, truncated, not a mesh
        file, malformed (a PLY header that ends early or claims more than the file holds, an OBJ face
        index that is 0 or names no vertex, a 3MF zip bomb, malformed XML or component cycle), holds
        coordinates that are NaN, infinite or beyond single precision, or no facets.

    Examples
    --------
    >>> import slicelab, pathlib, tempfile
    >>> m = slicelab.load(pathlib.Path(slicelab.__file__).parents[1] / "data" / "sphere.stl")
    >>> m.triangles.shape[1:]
    (3, 3)

    An OBJ whose face counts back from the last vertex (``-1`` is the third):

    >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.obj"
    >>> _ = f.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf -3 -2 -1\\n")
    >>> load(f, units="cm").triangles[0].tolist()
    [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]]
    >>> _ = f.write_text("v 1e39 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n")
    >>> try:
    ...     load(f)
    ... except MeshFileError as exc:
    ...     print(exc.reason)
    1 facets have coordinates beyond single precision (up to 1e+39, float32 ends at 3.4e+38)
    """
    factor = unit_scale(units, scale)
    p = Path(path)
    mesh = _read(p)
    if factor == 1.0:
        return mesh
    with np.errstate(over="ignore"):  # refused just below
        triangles = mesh.triangles * factor
    _refuse_beyond_single(p, triangles)
    return Mesh(triangles, mesh.file_normals)


def _read(p: Path) -> Mesh:
    """The mesh a file holds, in the file's own units."""
    if not p.exists():
        raise MeshFileError(p, "no such file")
    if p.is_dir():
        raise MeshFileError(p, "is a directory, not a mesh file")
    try:
        st = p.stat()
    except OSError as exc:
        raise MeshFileError(p, f"cannot be read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(st.st_mode):
        # A FIFO or a device would block the read or never end.
        raise MeshFileError(p, "is not a regular file (a pipe, socket or device)")
    try:
        size = st.st_size
        with open(p, "rb") as fh:
            head = fh.read(_HEADER + 4)
    except OSError as exc:
        raise MeshFileError(p, f"cannot be read ({exc.strerror or exc})") from None
    if size == 0:
        raise MeshFileError(p, "is empty")
    kind = is_scan_format(p, head)
    if kind is not None:
        triangles, normals = read_scan(p, kind, lambda reason: MeshFileError(p, reason))
        return _finish(p, triangles, normals)

    if size >= _HEADER + 4:
        count = int.from_bytes(head[_HEADER:_HEADER + 4], "little")
        if size == _HEADER + 4 + _RECORD * count:
            triangles, normals = _read_binary(p, count)
            return _finish(p, triangles, normals)
    else:
        count = None

    stripped = head.lstrip()
    if stripped[:5].lower() == b"solid":
        triangles, normals = _read_ascii(p)
        return _finish(p, triangles, normals)

    if head.startswith(b"PK\x03\x04"):  # a 3MF without its ending?
        from .threemf import is_3mf_package  # imported here: zipfile and ElementTree only for ZIP archives
        if is_3mf_package(p):
            triangles, normals = read_scan(p, "3mf", lambda reason: MeshFileError(p, reason))
            return _finish(p, triangles, normals)

    foreign = _describe_foreign(head)
    if foreign:
        raise MeshFileError(p, f"not an STL file (looks like {foreign})")
    if count is None:
        raise MeshFileError(p, f"not an STL file ({size} bytes, shorter than a binary STL header)")
    expected = _HEADER + 4 + _RECORD * count
    if expected > size:
        raise MeshFileError(
            p, f"truncated binary STL: header claims {count} triangles ({expected} bytes) "
               f"but the file has {size} bytes")
    raise MeshFileError(
        p, f"not an STL file: binary header claims {count} triangles ({expected} bytes) "
           f"but the file has {size} bytes")


def _read_binary(p: Path, count: int):
    """The facets and stored normals of a binary STL whose size matches its count (checked by the
    caller): its records read straight into `STL_RECORD`s. numpy-stl reads the same records, but
    importing it would add to every command's start-up (`scripts/bench_slice.py` prints by how much);
    it still reads ASCII STL."""
    try:
        records = np.fromfile(p, dtype=STL_RECORD, count=count, offset=_HEADER + 4)
    except (OSError, ValueError) as exc:
        raise MeshFileError(p, f"unreadable binary STL ({exc})") from None
    if len(records) != count:
        raise MeshFileError(p, f"binary STL holds {len(records)} of {count} triangles")
    return records["vertices"], records["normal"]


_WS = re.compile(rb"[ \t\r\f\v]+")


def _read_ascii(p: Path):
    from stl import mesh as stl_mesh
    from stl.stl import Mode
    raw = p.read_bytes()
    if b"\0" in raw:
        raise MeshFileError(p, "not an ASCII STL (binary bytes after a 'solid' header)")
    # numpy-stl matches keywords literally ("outer loop"), so fold runs of spaces,
    # tabs and CRs into one space before handing the text over.
    text = b"\n".join(line.strip() for line in _WS.sub(b" ", raw).split(b"\n") if line.strip())
    tail = text.rsplit(b"\n", 1)[-1].lower() if text else b""
    if not tail.startswith(b"endsolid") and not tail.startswith(b"end solid"):
        raise MeshFileError(p, "malformed ASCII STL (no closing 'endsolid': truncated?)")
    vectors, normals = [], []
    try:
        for part in stl_mesh.Mesh.from_multi_file(str(p), calculate_normals=False,
                                                  fh=io.BytesIO(text + b"\n"), mode=Mode.ASCII,
                                                  speedups=False):
            vectors.append(part.vectors)
            normals.append(part.normals)
    except Exception as exc:
        reason = str(exc.args[-1] if isinstance(exc, RuntimeError) and exc.args else exc)
        reason = reason.replace("\n", " ")[:200]
        raise MeshFileError(p, f"malformed ASCII STL ({reason})") from None
    n_facets = len(re.findall(rb"(?im)^facet\b", text))
    n_vertices = len(re.findall(rb"(?im)^vertex\b", text))
    got = sum(len(v) for v in vectors)
    if n_facets != got or n_vertices != 3 * n_facets:
        raise MeshFileError(
            p, f"malformed ASCII STL ({n_facets} facets with {n_vertices} vertices, {got} read)")
    if not vectors:
        return np.zeros((0, 3, 3)), np.zeros((0, 3))
    return np.concatenate(vectors), np.concatenate(normals)


def _finish(p: Path, triangles, normals) -> Mesh:
    if len(triangles) == 0:
        raise MeshFileError(p, "has no facets")
    if not np.isfinite(triangles).all():  # on the stored float32 values: half the memory traffic
        bad = int((~np.isfinite(triangles)).any(axis=(1, 2)).sum())
        raise MeshFileError(p, f"{bad} facets have NaN or infinite coordinates")
    t = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    if np.asarray(triangles).dtype != np.float32:  # what float32 holds is in range
        _refuse_beyond_single(p, t)
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if not np.isfinite(n).all():
        n = np.where(np.isfinite(n), n, 0.0)  # a bad stored normal is a defect to report, not a refusal
    return Mesh(t, n)


def _refuse_beyond_single(p: Path, t: np.ndarray) -> None:
    """Refuse coordinates no float32 holds: STL could not store them, and the slicer's float32 stages would
    turn them into infinities (a mesh checked watertight in float64 that then crashes `cut`)."""
    big = float(np.abs(t).max()) if t.size else 0.0
    if big > _SINGLE_MAX:
        bad = int((np.abs(t) > _SINGLE_MAX).any(axis=(1, 2)).sum())
        raise MeshFileError(p, f"{bad} facets have coordinates beyond single precision "
                               f"(up to {big:.3g}, float32 ends at {_SINGLE_MAX:.3g})")


def write_binary_stl(triangles, normals, path, name: str = "") -> None:
    """Write corners and normals as a binary STL file, atomically, without building a `Mesh`.

    The values are stored as float32 (corners already in float32 are
    stored bit for bit); the 80-byte header reads ``slicelab <name>``; each
    attribute word is 0.

    Parameters
    ----------
    triangles : (n, 3, 3) array_like
    normals : (n, 3) array_like
    path : str or os.PathLike
    name : str, optional
        Named in the header; the file's stem by default.

    Examples
    --------
    >>> import tempfile, os
    >>> t = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], np.float32)
    >>> f = os.path.join(tempfile.mkdtemp(), "t.stl")
    >>> write_binary_stl(t, [[0, 0, 1]], f)
    >>> os.path.getsize(f), load(f).triangles.tolist() == t.tolist()
    (134, True)
    """
    t = np.asarray(triangles).reshape(-1, 3, 3)
    n = np.asarray(normals).reshape(-1, 3)
    if len(n) != len(t):
        raise ValueError(f"{len(t)} triangles but {len(n)} normals")
    target = Path(path)
    header = f"slicelab {name or target.stem}".encode("ascii", "replace")[:_HEADER].ljust(_HEADER, b" ")
    records = np.zeros(min(len(t), _WRITE_CHUNK), STL_RECORD)
    with atomic_path(target) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(header)
            fh.write(np.array(len(t), "<u4").tobytes())
            for lo in range(0, len(t), _WRITE_CHUNK):  # over chunks of facets, one buffer reused
                part = records[:min(_WRITE_CHUNK, len(t) - lo)]
                part["normal"] = n[lo:lo + len(part)]
                part["vertices"] = t[lo:lo + len(part)]
                part.tofile(fh)


def save(mesh: Mesh, path, ascii: bool = False) -> None:
    """Write a mesh as binary (default) or ASCII STL, atomically.

    The stored normals are the winding normals.

    Parameters
    ----------
    mesh : Mesh
    path : str or os.PathLike
    ascii : bool, default False

    See Also
    --------
    write_binary_stl : the binary writer, for corners already rounded to float32.

    Examples
    --------
    >>> import tempfile, os
    >>> m = Mesh.from_triangles([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    >>> f = os.path.join(tempfile.mkdtemp(), "t.stl")
    >>> save(m, f, ascii=True); len(load(f))
    1
    """
    if not ascii:
        write_binary_stl(mesh.triangles, mesh.normals, path)
        return
    from stl import mesh as stl_mesh
    from stl.stl import Mode
    data = np.zeros(len(mesh), dtype=stl_mesh.Mesh.dtype)
    data["vectors"] = mesh.triangles
    data["normals"] = mesh.normals
    m = stl_mesh.Mesh(data, calculate_normals=False)
    target = Path(path)
    with atomic_open(target, "wb") as fh:
        m.save(target.stem or "slicelab", fh=fh, mode=Mode.ASCII, update_normals=False)
