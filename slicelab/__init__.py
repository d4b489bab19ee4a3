"""slicelab: exact slicing of triangle meshes and what labs make of each layer.

The package is laid out by concept; each subpackage re-exports its public
names (``__all__``) and keeps one job per module:

=======================  ==========================================================
``slicelab.geometry``    plain-array kernels: plane frames, topology, chains, polygons
``slicelab.mesh``        `Mesh`, STL input/output, `check`, `repair`
``slicelab.slicing``     sections, splits, watertight cuts, partitions into pieces
``slicelab.printing``    layer rasters, perimeters, infill, paths, the print plan
``slicelab.artefacts``   vessel axis, profiles, measurements, drawings
``slicelab.files``       safe file output, numbers as text, the SVG writer
``slicelab.gcode``       G-code of a print plan, its time estimate, layer drawings
``slicelab.viz``         matplotlib figures and previews (imported on first use)
``slicelab.tasks``       jobs on files for the command line and batches
``slicelab.samples``     analytic sample meshes (boxes, tori, pots, staircases)
=======================  ==========================================================

The most used names are available here; everything but the mesh basics
loads on first use, so ``import slicelab`` and the command line stay fast.

Examples
--------
>>> import slicelab
>>> from slicelab.samples import box
>>> slicelab.section(box(), (0, 0, 0.5), (0, 0, 1)).area
1.0
"""
from __future__ import annotations

from ._lazy import attach

from .mesh import Mesh, MeshFileError, MeshReport, check, load, repair, save

__version__ = "0.1.0"

# Public name -> the module that defines it, loaded on first use.
_LAZY = {
    "Section": "slicing.sections", "section": "slicing.sections", "slice_layers": "slicing.sections",
    "Frame": "geometry.planes",
    "Split": "slicing.split", "split": "slicing.split",
    "cut": "slicing.cut", "Cut": "slicing.cut", "CutWarning": "slicing.cut",
    "partition": "slicing.partition", "Partition": "slicing.partition",
    "arrange": "slicing.plates", "Plates": "slicing.plates",
    "stair_cut": "slicing.stair", "StairCut": "slicing.stair", "StairCutError": "slicing.stair",
    "align": "artefacts.axis", "Alignment": "artefacts.axis", "profile": "artefacts.profiles",
    "Profile": "artefacts.profiles", "Measurements": "artefacts.measure",
    "run_batch": "tasks",
    "rasterize": "printing.grid.raster", "LayerRaster": "printing.grid.raster", "GridMask": "printing.grid.raster",
    "raster_hierarchy": "printing.grid.hierarchy",
    "layer_perimeters": "printing.steps.perimeters", "Perimeters": "printing.steps.perimeters",
    "layer_paths": "printing.pipeline", "LayerPaths": "printing.table",
    "PrintSettings": "printing.config.settings", "PrintPlan": "printing.planner", "plan": "printing.planner",
}

__all__ = ["Mesh", "MeshFileError", "MeshReport", "check", "load", "repair", "save", "__version__", *_LAZY]


__getattr__, __dir__ = attach(__name__, _LAZY, globals(),
                              submodules=("geometry", "mesh", "slicing", "printing", "gcode", "artefacts", "files", "viz",
                                          "tasks", "samples"))
