"""The triangle mesh container shared by every stage.

`Mesh` is deliberately small: the triangles, their normals from the vertex
winding, the normals the file stored, and two things found on first use and
kept, since the corners cannot change: the bounding box and the exact weld
(which the mesh check and the slicer both read). Each stage keeps its
own logic in its own module and takes a `Mesh` as plain data.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..geometry.triangles import winding_normals

__all__ = ["Mesh"]

@dataclass(frozen=True, eq=False)
class Mesh:
    """An immutable triangle soup in millimetres.

    Parameters
    ----------
    triangles : (n, 3, 3) array_like
        Corners of each facet in winding order (counter-clockwise seen from
        outside for a well-oriented solid).
    file_normals : (n, 3) array_like, optional
        Normals as stored in the file; defaults to the winding normals.

    Attributes
    ----------
    triangles : (n, 3, 3) float64 ndarray
    normals : (n, 3) float64 ndarray
        Unit normals recomputed from the vertex order (right-hand rule).
    file_normals : (n, 3) float64 ndarray
        Normals as the file stored them (possibly zero or wrong).

    Examples
    --------
    >>> m = Mesh.from_triangles([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    >>> len(m), m.normals[0].tolist()
    (1, [0.0, 0.0, 1.0])
    """

    triangles: np.ndarray
    file_normals: np.ndarray | None = None
    normals: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        t = np.ascontiguousarray(self.triangles, dtype=np.float64)
        if t.ndim != 3 or t.shape[1:] != (3, 3):
            raise ValueError(f"triangles must have shape (n, 3, 3), got {t.shape}")
        t.setflags(write=False)
        normals = winding_normals(t)
        normals.setflags(write=False)
        if self.file_normals is None:
            fn = normals
        else:
            fn = np.ascontiguousarray(self.file_normals, dtype=np.float64)
            if fn.shape != (len(t), 3):
                raise ValueError(f"file_normals must have shape ({len(t)}, 3), got {fn.shape}")
            fn.setflags(write=False)
        object.__setattr__(self, "triangles", t)
        object.__setattr__(self, "normals", normals)
        object.__setattr__(self, "file_normals", fn)

    @classmethod
    def _with_normals(cls, triangles, normals, file_normals) -> "Mesh":
        """A mesh whose winding normals are already known, for stages that cut facets into pieces.

        A piece of a facet lies in the facet's plane and keeps its winding, so it
        keeps the facet's normal; taking it over saves recomputing millions of
        them. The caller vouches that `normals` match the winding.
        """
        mesh = object.__new__(cls)
        for name, value in (("triangles", triangles), ("normals", normals), ("file_normals", file_normals)):
            value = np.ascontiguousarray(value, dtype=np.float64)
            value.setflags(write=False)
            object.__setattr__(mesh, name, value)
        return mesh

    def __len__(self) -> int:
        return len(self.triangles)

    def __repr__(self) -> str:
        lo, hi = self.bounds if len(self) else (np.zeros(3), np.zeros(3))
        size = " x ".join(f"{s:.4g}" for s in hi - lo)
        return f"Mesh({len(self)} facets, {size} mm)"

    @cached_property
    def bounds(self) -> np.ndarray:
        """(2, 3) array: minimum and maximum corner of the bounding box (read-only, made once:
        the corners cannot change)."""
        flat = self.triangles.reshape(-1, 3)
        # Column by column: numpy reduces a strided column far faster than axis=0 of (n, 3).
        out = np.array([[flat[:, k].min() for k in range(3)], [flat[:, k].max() for k in range(3)]])
        out.setflags(write=False)
        return out

    @cached_property
    def welded(self) -> tuple[np.ndarray, np.ndarray]:
        """The exact weld (`slicelab.geometry.topology.exact_ids`), made once: the vertex id of
        every corner, (n, 3) int64, and the first corner (flat index) of each vertex, (v,) int64.

        Corners are the same vertex only when their coordinates are bit for bit
        equal (-0.0 and 0.0 alike). Both arrays are read-only.

        Examples
        --------
        >>> m = Mesh.from_vertices_faces([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]])
        >>> ids, first = m.welded
        >>> len(first), bool(ids[0, 1] == ids[1, 0]), bool(ids[0, 2] == ids[1, 2])
        (4, True, True)
        """
        from ..geometry.topology import exact_ids
        ids, first = exact_ids(self.triangles.reshape(-1, 3))
        ids = ids.reshape(-1, 3)
        for a in (ids, first):
            a.setflags(write=False)
        return ids, first

    @property
    def has_weld(self) -> bool:
        """Whether `welded` is made already (the mesh check makes it): reading it then costs nothing.

        Examples
        --------
        >>> m = Mesh.from_vertices_faces([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> m.has_weld, len(m.welded[1]), m.has_weld
        (False, 3, True)
        """
        return "welded" in self.__dict__

    @classmethod
    def from_triangles(cls, triangles, file_normals=None) -> "Mesh":
        """Build a mesh from an (n, 3, 3) array of corners.

        Accepts numpy arrays and anything array-like, such as numpy-stl's
        ``mesh.vectors`` or trimesh's ``mesh.triangles``.

        Examples
        --------
        >>> Mesh.from_triangles(np.zeros((0, 3, 3))).triangles.shape
        (0, 3, 3)
        """
        return cls(np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3), file_normals)

    @classmethod
    def from_vertices_faces(cls, vertices, faces) -> "Mesh":
        """Build a mesh from shared vertices and integer faces.

        Parameters
        ----------
        vertices : (v, 3) array_like
        faces : (n, 3) array_like of int
            Indices into `vertices`, in winding order.

        Examples
        --------
        >>> v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
        >>> f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
        >>> len(Mesh.from_vertices_faces(v, f))
        4
        """
        v = np.asarray(vertices, dtype=np.float64)
        f = np.asarray(faces, dtype=np.int64)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"vertices must have shape (v, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3:
            raise ValueError(f"faces must have shape (n, 3), got {f.shape}")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ValueError("faces index vertices that do not exist")
        return cls(v[f])

    def transformed(self, matrix) -> "Mesh":
        """Return the mesh moved by a 4x4 homogeneous matrix.

        A matrix with negative determinant mirrors the mesh; the winding is
        then reversed so that normals still point outwards.

        Examples
        --------
        >>> m = Mesh.from_triangles([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]])
        >>> shift = np.eye(4); shift[:3, 3] = [0, 0, 5]
        >>> m.transformed(shift).bounds[0].tolist()
        [0.0, 0.0, 5.0]
        """
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape != (4, 4):
            raise ValueError(f"matrix must be 4x4, got {m.shape}")
        # einsum, not matmul: a threaded BLAS on (n, 3) x (3, 3) is slow and fights for the cores.
        t = np.einsum("...j,ij->...i", self.triangles, m[:3, :3]) + m[:3, 3]
        fn = np.einsum("...j,ji->...i", self.file_normals, np.linalg.inv(m[:3, :3]))  # inverse transpose
        if np.linalg.det(m[:3, :3]) < 0:
            t = t[:, ::-1]
        lengths = np.linalg.norm(fn, axis=1, keepdims=True)
        fn = np.divide(fn, lengths, out=np.zeros_like(fn), where=lengths > 0)
        return Mesh(t, fn)
