"""3MF, the package slicers and CAD tools save (PrusaSlicer's projects): its build as one mesh, in mm.

A 3MF file is a ZIP archive whose ``_rels/.rels`` names the model part
(``3D/3dmodel.model``). Its ``<resources>`` hold objects, each a mesh
(``<vertex x y z>``, ``<triangle v1 v2 v3>`` counting from 0) or
``<components>`` placing other objects (of another part through the
production extension's ``p:path``); ``<build>`` items place objects. A
transform is 12 numbers ``m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32``
applied to row vectors, ``[x y z 1] @ M`` (M 4 x 3). `read_3mf` returns every
build item's triangles, transforms composed, in millimetres; a mirroring
transform also reverses the winding, so a mirrored solid still faces out.

The vertex and triangle lists, nearly all of a file, are cut out of the XML
and parsed by numpy at once (`_list_rows`); ElementTree parses the rest, so
malformed XML is refused with its line and column. A list holding anything
but elements written alike (a comment, an entity) sends its part through
ElementTree whole. Refused: a part inflating beyond a bound (zip bombs), a
DTD, component cycles, builds repeating components past what fits in memory.
"""
from __future__ import annotations

import io
import re
import secrets
import warnings
import xml.etree.ElementTree as ET
import zipfile
import zlib
from urllib.parse import unquote

import numpy as np

__all__ = ["read_3mf", "is_3mf_package", "UNITS_3MF"]

_CORE = "{http://schemas.microsoft.com/3dmanufacturing/core/2015/02}"
_PATH = "{http://schemas.microsoft.com/3dmanufacturing/production/2015/06}path"
_MODEL_REL = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"
_RELATIONSHIP = "{http://schemas.openxmlformats.org/package/2006/relationships}Relationship"
# Extensions a model may require that leave its geometry as read here (production, colours, triangle
# sets); one requiring another (beams, slices, booleans, displacement) is refused rather than misread.
_HARMLESS = {_CORE[1:-1], _PATH[1:-5], "http://schemas.microsoft.com/3dmanufacturing/material/2015/02",
             "http://schemas.microsoft.com/3dmanufacturing/trianglesets/2021/07"}
#: Size of each 3MF unit in millimetres.
UNITS_3MF = {"micron": 0.001, "millimeter": 1.0, "centimeter": 10.0, "inch": 25.4, "foot": 304.8,
             "meter": 1000.0}
_PART_CAP = 2 << 30   # bytes a package may inflate to, all parts together
_RATIO = 100          # a mesh's XML deflates a few fold, a zip bomb's zeros about a thousand fold
_FLOOR = 16 << 20     # a part up to this size is read whatever its ratio
_MAX_DEPTH = 64
_MAX_TRIANGLES = 50_000_000
_MAX_VISITS = 1_000_000
_LIST = re.compile(rb"<(vertices|triangles)(\s[^>]*)?>")


class _Slow(Exception):
    """A vertex or triangle list holding more than elements written alike: ElementTree is to read it."""


def is_3mf_package(path) -> bool:
    """Whether `path` is a ZIP archive holding a 3MF model part (for files without the ``.3mf`` ending)."""
    try:
        with zipfile.ZipFile(path) as z:
            names = [n.lower().lstrip("/") for n in z.namelist()]
    except (zipfile.BadZipFile, OSError, ValueError, EOFError):
        return False
    return any(n.startswith("3d/") and n.endswith(".model") for n in names)


def read_3mf(path, error) -> np.ndarray:
    """The triangles (n, 3, 3) of a 3MF file's build, in millimetres; `error(reason)` makes the exception.

    Examples
    --------
    >>> import tempfile, os, zipfile
    >>> f = os.path.join(tempfile.mkdtemp(), "t.3mf")
    >>> model = ('<model unit="centimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
    ...          '<resources><object id="1"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/>'
    ...          '<vertex x="0" y="1" z="0"/></vertices><triangles><triangle v1="0" v2="1" v3="2"/></triangles>'
    ...          '</mesh></object></resources><build><item objectid="1" transform="1 0 0 0 1 0 0 0 1 5 0 0"/>'
    ...          '</build></model>')
    >>> with zipfile.ZipFile(f, "w") as z: z.writestr("3D/3dmodel.model", model)
    >>> read_3mf(f, ValueError)[0].tolist()
    [[50.0, 0.0, 0.0], [60.0, 0.0, 0.0], [50.0, 10.0, 0.0]]
    """
    try:
        z = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        raise error(f"not a 3MF file (not a ZIP archive: {str(exc)[:100]})") from None
    with z:
        return _Package(z, error).triangles()


class _Package:
    """The parts of one 3MF package, each read and parsed once, on demand, and its build."""

    def __init__(self, z: zipfile.ZipFile, error):
        self.z, self.error, self.budget = z, error, _PART_CAP
        self.infos = {info.filename.lstrip("/").lower(): info for info in z.infolist()}
        self.models: dict[str, dict] = {}

    def read(self, name: str) -> bytes:
        info = self.infos.get(name.lstrip("/").lower())
        if info is None:
            raise self.error(f"3MF package has no part {name!r}")
        limit = min(self.budget, max(_FLOOR, _RATIO * info.compress_size))
        if info.file_size > limit:
            raise self.error(f"3MF part {info.filename!r} would inflate from {info.compress_size} to "
                             f"{info.file_size} bytes (a zip bomb?)")
        try:
            with self.z.open(info) as fh:
                data = fh.read(limit + 1)  # zipfile stops at the declared size; the bound holds regardless
        except (zipfile.BadZipFile, zlib.error, NotImplementedError, RuntimeError, EOFError, OSError,
                ValueError) as exc:
            raise self.error(f"3MF part {info.filename!r} cannot be unpacked ({str(exc)[:100]})") from None
        if len(data) > limit:
            raise self.error(f"3MF part {info.filename!r} inflates beyond {limit} bytes (a zip bomb?)")
        self.budget -= len(data)
        if re.search(rb"<!(?:DOCTYPE|ENTITY)", data):
            raise self.error(f"3MF part {info.filename!r} declares a DTD, which 3MF does not allow")
        return data

    def xml(self, text: bytes, name: str) -> ET.Element:
        try:
            return ET.fromstring(text)
        except (ET.ParseError, LookupError, ValueError) as exc:  # LookupError: an unknown declared encoding
            raise self.error(f"malformed XML in 3MF part {name!r} ({str(exc)[:100]})") from None

    def number(self, text, what: str):
        try:
            return int(text)
        except (TypeError, ValueError):
            raise self.error(f"malformed 3MF model ({what}: {str(text)[:40]!r} is not a number)") from None

    def transform(self, text, where: str) -> np.ndarray:
        """The 4 x 4 matrix of a transform attribute (row vectors: [x y z 1] @ A); identity when absent."""
        a = np.eye(4)
        if text is not None:
            try:
                values = np.array(text.split(), dtype=np.float64)
            except ValueError:
                values = np.zeros(0)
            if values.shape != (12,) or not np.isfinite(values).all():
                raise self.error(f"malformed 3MF model (transform {text[:60]!r} in {where}: not 12 finite numbers)")
            a[:, :3] = values.reshape(4, 3)
        return a

    def model(self, part: str) -> dict:
        """{object id: (type, vertices, triangles, [(part, id, matrix)])}, and the root element under None."""
        part = part.lstrip("/")
        if part.lower() not in self.models:
            data = self.read(part)
            try:
                self.models[part.lower()] = self.parse(data, part, fast=True)
            except _Slow:
                self.models[part.lower()] = self.parse(data, part, fast=False)
        return self.models[part.lower()]

    def parse(self, data: bytes, part: str, fast: bool) -> dict:
        lists, mark = [], f"#{secrets.token_hex(8)}-"  # a mark no file can hold by chance or design
        if fast:  # cut the lists out, leaving the mark (and their line breaks: errors keep their lines)
            pieces, at, m = [], 0, _LIST.search(data)
            while m is not None:  # over lists, a few per object
                end = data.find(b"</" + m.group(1) + b">", m.end())
                if (m.group(2) or b"").endswith(b"/") or end < 0:  # empty, or unclosed: ElementTree will say
                    m = _LIST.search(data, m.end())
                    continue
                pieces += [data[at:m.end()], f"{mark}{len(lists)}".encode(), b"\n" * data.count(b"\n", m.end(), end)]
                lists.append(data[m.end():end])
                at, m = end, _LIST.search(data, end)
            data = b"".join(pieces) + data[at:]
        root = self.xml(data, part)
        if root.tag != f"{_CORE}model":
            raise self.error(f"3MF part {part!r} is not a 3MF model (its root is <{root.tag}>)")
        self.refuse_extensions(root, data, part)
        objects = {None: root}
        for obj in root.iterfind(f"{_CORE}resources/{_CORE}object"):
            oid = self.number(obj.get("id"), f"object id in {part!r}")
            where = f"object {oid} in {part!r}"
            if oid in objects:
                raise self.error(f"malformed 3MF model (two objects with id {oid} in {part!r})")
            vertices, triangles = np.zeros((0, 3)), np.zeros((0, 3), np.int64)
            if (mesh := obj.find(f"{_CORE}mesh")) is not None:
                vertices = self.rows(mesh.find(f"{_CORE}vertices"), "vertex", ("x", "y", "z"), np.float64,
                                     lists, mark, f"vertices of {where}")
                triangles = self.rows(mesh.find(f"{_CORE}triangles"), "triangle", ("v1", "v2", "v3"), np.int64,
                                      lists, mark, f"triangles of {where}")
                if len(triangles) and (triangles.min() < 0 or triangles.max() >= len(vertices)):
                    bad = int(triangles.max() if triangles.max() >= len(vertices) else triangles.min())
                    raise self.error(f"malformed 3MF model ({where}: a triangle names vertex {bad} "
                                     f"of {len(vertices)}, counting from 0)")
            components = [((c.get(_PATH) or part).lstrip("/"), self.number(c.get("objectid"), f"component of {where}"),
                           self.transform(c.get("transform"), where))
                          for c in obj.iterfind(f"{_CORE}components/{_CORE}component")]
            objects[oid] = (obj.get("type", "model"), vertices, triangles, components)
        return objects

    def refuse_extensions(self, root: ET.Element, data: bytes, part: str) -> None:
        """Refuse a model that requires an extension which could change its geometry."""
        start = re.search(rb"<(?:[\w.-]+:)?model\b[^>]*>", data)
        spaces = dict(re.findall(r'xmlns:([\w.-]+)\s*=\s*["\']([^"\']*)',
                                 start.group().decode("utf-8", "replace") if start else ""))
        for prefix in (root.get("requiredextensions") or "").split():
            if spaces.get(prefix, prefix) not in _HARMLESS:
                raise self.error(f"3MF model {part!r} requires the extension {spaces.get(prefix, prefix)!r}, "
                                 "which slicelab does not read")

    def rows(self, element, tag: str, names, dtype, lists, mark, what) -> np.ndarray:
        """(n, 3) values of a vertex or triangle list: a cut-out list at once, else element by element."""
        if element is None:
            return np.zeros((0, 3), dtype)
        text = (element.text or "").strip()
        try:
            if text.startswith(mark):
                rows = _list_rows(lists[int(text[len(mark):])], tag.encode(), names, dtype)
                if rows is None:
                    raise _Slow
                return rows
            rows = [[child.get(name) for name in names] for child in element.iter(_CORE + tag)]
            if any(None in row for row in rows):
                raise ValueError(f"one lacks one of {', '.join(names)}")
            return np.array(rows, dtype=str).reshape(-1, 3).astype(dtype)
        except (ValueError, OverflowError) as exc:
            raise self.error(f"malformed 3MF model ({what}: {str(exc)[:80]})") from None

    def object(self, key):
        if key[1] is None or key[1] not in (objects := self.model(key[0])):
            raise self.error(f"malformed 3MF model (no object {key[1]} in {key[0]!r})")
        return objects[key[1]]

    def size(self, key, path: tuple, sizes: dict) -> None:
        """Triangles and objects visited an object expands to (memoised), refusing cycles and deep nesting."""
        if key in sizes:
            return
        if key in path:
            cycle = " -> ".join(str(k[1]) for k in path[path.index(key):] + (key,))
            raise self.error(f"3MF components form a cycle (objects {cycle})")
        if len(path) >= _MAX_DEPTH:
            raise self.error(f"3MF components nest deeper than {_MAX_DEPTH} levels")
        _, _, triangles, components = self.object(key)
        n_tri, n_visited = len(triangles), 1
        for child in ((child_part, oid) for child_part, oid, _ in components):
            self.size(child, path + (key,), sizes)
            n_tri, n_visited = n_tri + sizes[child][0], n_visited + sizes[child][1]
        sizes[key] = (n_tri, n_visited)

    def triangles(self) -> np.ndarray:
        root_part = "3D/3dmodel.model"
        if "_rels/.rels" in self.infos:
            for rel in self.xml(self.read("_rels/.rels"), "_rels/.rels").iter(_RELATIONSHIP):
                if rel.get("Type") == _MODEL_REL and rel.get("Target"):
                    root_part = unquote(rel.get("Target")).lstrip("/")
                    break
        root = self.model(root_part)[None]
        unit = root.get("unit", "millimeter")
        if unit not in UNITS_3MF:
            raise self.error(f"3MF model unit {unit!r} is not one of {', '.join(UNITS_3MF)}")
        items = [(((i.get(_PATH) or root_part).lstrip("/"), self.number(i.get("objectid"), "build item")),
                  self.transform(i.get("transform"), "build item"))
                 for i in root.iterfind(f"{_CORE}build/{_CORE}item")]
        if not items:
            raise self.error("3MF model has no build items (nothing to print)")
        sizes: dict = {}
        for key, _ in items:
            if self.object(key)[0] == "other":
                raise self.error(f"3MF build item names object {key[1]}, of type 'other' (not to be printed)")
            self.size(key, (), sizes)
        n_tri, n_visited = (sum(sizes[key][i] for key, _ in items) for i in (0, 1))
        if n_tri > _MAX_TRIANGLES or n_visited > _MAX_VISITS:
            raise self.error(f"3MF build repeats its components into {n_tri} triangles in {n_visited} objects, "
                             f"more than slicelab reads ({_MAX_TRIANGLES} triangles, {_MAX_VISITS} objects)")
        placed: dict = {}  # (part, id) -> the matrices placing its mesh
        stack = list(items)
        while stack:  # over objects visited (bounded above), not triangles
            key, a = stack.pop()
            _, _, triangles, components = self.object(key)
            if len(triangles):
                placed.setdefault(key, []).append(a)
            stack += [((p, oid), c @ a) for p, oid, c in components]
        with np.errstate(over="ignore", invalid="ignore"):  # what overflows is refused by `load` as not finite
            out = [_placed(*self.object(key)[1:3], np.stack(mats)) for key, mats in placed.items()]
            tri = np.concatenate(out) if out else np.zeros((0, 3, 3))
            return tri * UNITS_3MF[unit] if unit != "millimeter" else tri


def _placed(vertices: np.ndarray, triangles: np.ndarray, mats: np.ndarray) -> np.ndarray:
    """The mesh's triangles under each (4 x 4, row-vector) matrix; under a mirroring one, rewound."""
    moved = vertices @ mats[:, :3, :3] + mats[:, None, 3, :3]  # (k, n vertices, 3): vertices, not corners
    out = moved[:, triangles]
    flip = np.linalg.det(mats[:, :3, :3]) < 0
    if flip.any():
        out[flip] = out[flip][:, :, ::-1]
    return out.reshape(-1, 3, 3)


def _list_rows(block: bytes, tag: bytes, names, dtype) -> np.ndarray | None:
    """The first three values of each element of a list (``<vertex x=".." y=".." z=".."/>``), parsed at once.

    Outside the quotes, each distinct way the file writes an element is checked (more attributes may
    follow); the values, an element a line, go to numpy's C parser. None when the list holds anything
    else; ValueError for a value that is not a number.
    """
    if b"&" in block or b"'" in block:
        return None
    arr = np.frombuffer(block, np.uint8)
    quote = arr == 34
    inside = np.logical_xor.accumulate(quote) & ~quote  # the values' bytes
    pieces = arr[~inside].tobytes().split(b"/>")  # one an element, its values left out
    element = re.compile(rb"\s*<" + tag + b"".join(rb"\s+" + a.encode() + rb'\s*=\s*""' for a in names)
                         + rb'(?:\s+[\w:.-]+\s*=\s*"")*\s*')
    if pieces[-1].strip() or not all(element.fullmatch(piece) for piece in set(pieces[:-1])):
        return None
    n = len(pieces) - 1
    if n == 0:
        return np.zeros((0, 3), dtype)
    q = np.flatnonzero(quote)
    ends = np.flatnonzero((arr[:-1] == 47) & (arr[1:] == 62) & ~inside[:-1])  # each "/>" outside the values
    first = np.searchsorted(q, np.concatenate([[0], ends[:-1]]))  # each element's first quote
    opens, closes = q[first[:, None] + [0, 2, 4]], q[first[:, None] + [1, 3, 5]]
    marks = np.zeros(len(arr) + 1, np.int8)
    marks[opens + 1] += 1
    marks[closes] -= 1
    keep = np.cumsum(marks[:-1], dtype=np.int8).astype(bool)  # the first three values' bytes
    keep[opens] = keep[closes] = True
    text = arr.copy()
    text[opens] = text[closes] = 32
    text[opens[:, 0]] = 10  # a line an element
    text = text[keep].tobytes()
    if text.count(b"\n") != n:  # a line break inside a value: ElementTree normalises it
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = np.loadtxt(io.BytesIO(text), dtype=dtype, ndmin=2, comments=None, encoding="latin1")
    except ValueError as exc:
        raise ValueError(re.sub(r" at row .*", "", str(exc))) from None
    if rows.shape != (n, 3):
        raise ValueError("a value holds more than one number")
    return rows
