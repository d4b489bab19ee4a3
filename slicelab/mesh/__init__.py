"""Meshes: the `Mesh` container, STL reading and writing, and checking.

==========================  =====================================================
``mesh.core``               `Mesh`, the small immutable container
``mesh.io``                 `load`, `save`, `MeshFileError`
``mesh.formats``            PLY and OBJ through meshio, units (`UNITS`, `unit_scale`)
``mesh.validation``         `check` -> `MeshReport` (normals, open edges, shells, volume)
``mesh.repairs``            `repair`: CAD float noise, collapsed and duplicate facets, windings
``mesh.holes``              `fill_holes`, `hole_loops`: loops of open edges closed by fans
==========================  =====================================================
"""
from __future__ import annotations

from .core import Mesh
from .formats import UNITS, unit_scale
from .io import MeshFileError, load, save
from .validation import MeshReport, check, signed_volume
from .repairs import RepairReport, Repaired, repair, near_vertex_pairs, default_tolerance
from .holes import fill_holes, hole_loops

__all__ = ["Mesh", "MeshFileError", "load", "save", "UNITS", "unit_scale", "MeshReport", "check", "signed_volume", "RepairReport", "Repaired", "repair", "near_vertex_pairs", "default_tolerance", "fill_holes", "hole_loops"]
