"""Deterministic samples with known geometry, for tests, notebooks and benchmarks.

==========================  ==========================================================
``samples.solids``          boxes, solids of revolution, the pot, voxels, awkward solids
``samples.vessels``         vessel forms (pot, beaker, bowl, plate, jug) and their truth
``samples.scans``           simulated scans: noise, pose, holes, ovality, sherds, with the truth
==========================  ==========================================================
"""
from __future__ import annotations

from .scans import SHERDS, scan, sherd_mesh
from .solids import (
    POT,
    box,
    concat,
    cube_with_hole,
    figure_eight_prism,
    nested_shells,
    oriented,
    overlapping_cubes,
    pot,
    pot_dimensions,
    pot_profile,
    random_motion,
    revolve,
    revolve_grid,
    ring_prism,
    sphere,
    staircase,
    torus,
    voxels,
)
from .vessels import FLOOR_COSINE, FORMS, handle_mesh, handle_truth, sealed_vessel, vessel_mesh, vessel_outlines, \
    vessel_profile, vessel_truth, wall_thickness_samples

__all__ = ["random_motion", "box", "revolve", "revolve_grid", "oriented", "torus", "sphere", "POT", "pot",
           "pot_profile", "pot_dimensions", "ring_prism", "cube_with_hole", "concat", "nested_shells",
           "overlapping_cubes", "figure_eight_prism", "voxels", "staircase",
           "FORMS", "vessel_outlines", "vessel_profile", "vessel_mesh", "vessel_truth", "handle_mesh",
           "handle_truth", "sealed_vessel", "wall_thickness_samples", "FLOOR_COSINE", "SHERDS", "scan", "sherd_mesh"]
