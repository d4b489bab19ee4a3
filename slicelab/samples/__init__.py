"""Deterministic samples with known geometry, for tests, notebooks and benchmarks.

==========================  ==========================================================
``samples.solids``          boxes, solids of revolution, the pot, voxels, awkward solids
``samples.vessels``         vessel forms (pot, beaker, bowl, plate, jug) and their truth
``samples.fragments``       sherds broken as real ones break, low-poly fragments, reassembled vessels
``samples.scans``           simulated scans: noise, pose, holes, ovality, sherds, with the truth
==========================  ==========================================================
"""
from __future__ import annotations

from .fragments import BREAKS, SHERDS, assembled_vessel, broken_sherd, lowpoly_sherd, sherd_mesh
from .scans import scan
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
from .vessels import FLOOR_COSINE, FORMS, LIPS, handle_mesh, handle_truth, lip_parts, sealed_vessel, vessel_mesh, \
    vessel_outlines, vessel_profile, vessel_truth, wall_thickness_samples

__all__ = ["random_motion", "box", "revolve", "revolve_grid", "oriented", "torus", "sphere", "POT", "pot",
           "pot_profile", "pot_dimensions", "ring_prism", "cube_with_hole", "concat", "nested_shells",
           "overlapping_cubes", "figure_eight_prism", "voxels", "staircase",
           "FORMS", "vessel_outlines", "vessel_profile", "vessel_mesh", "vessel_truth", "handle_mesh",
           "handle_truth", "sealed_vessel", "wall_thickness_samples", "FLOOR_COSINE", "LIPS", "lip_parts", "SHERDS", "BREAKS", "scan",
           "sherd_mesh", "broken_sherd", "lowpoly_sherd", "assembled_vessel"]
