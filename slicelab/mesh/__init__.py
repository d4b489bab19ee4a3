"""Meshes: the `Mesh` container, reading (STL, PLY, OBJ, 3MF) and writing STL, checking and repairing.

==========================  =====================================================
``mesh.core``               `Mesh`, the small immutable container
``mesh.io``                 `load`, `save`, `MeshFileError`
``mesh.formats``            PLY (header checked, body through meshio), OBJ, units (`UNITS`, `unit_scale`)
``mesh.threemf``            3MF packages: objects, components, build transforms, units
``mesh.validation``         `check` -> `MeshReport` (normals, open edges, shells, volume)
``mesh.repairs``            `repair`: CAD float noise, collapsed and duplicate facets, windings
``mesh.holes``              `fill_holes`, `hole_loops`: loops of open edges closed by fans
``mesh.written``            `write_mesh`: STL whose report is the check of the file read back
==========================  =====================================================
"""
from __future__ import annotations

from .core import Mesh
from .formats import UNITS, unit_scale
from .io import MeshFileError, load, save
from .validation import MeshReport, check, signed_volume
from .repairs import RepairReport, Repaired, repair, near_vertex_pairs, default_tolerance
from .holes import fill_holes, hole_loops
from .written import WrittenMesh, as_float32, write_mesh

__all__ = ["Mesh", "MeshFileError", "load", "save", "UNITS", "unit_scale", "MeshReport", "check", "signed_volume", "RepairReport", "Repaired", "repair", "near_vertex_pairs", "default_tolerance", "fill_holes", "hole_loops", "WrittenMesh", "write_mesh", "as_float32"]
