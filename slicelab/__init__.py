"""slicelab: exact slicing of triangle meshes (STL) and what labs make of each layer.

Each stage lives in its own module and passes plain data:

========================  ====================================================
``slicelab.io``           `load`, `save`, `MeshFileError`
``slicelab.mesh``         `Mesh`, the small immutable container
``slicelab.check``        `check` -> `MeshReport` (normals, open edges, shells)
``slicelab.sections``     `section`, `slice_layers` -> `Section`
``slicelab.loops``        chaining segments into loops, hole hierarchy
========================  ====================================================
"""
from __future__ import annotations

import importlib
import sys
import types

from .check import MeshReport, check
from .io import MeshFileError, load, save
from .mesh import Mesh

__version__ = "0.1.0"

# Heavier stages load on first use, so `import slicelab` and the CLI stay fast.
_LAZY = {
    "Section": "sections", "Frame": "sections", "section": "sections", "slice_layers": "sections",
    "Split": "split", "split": "split",
    "align": "artefacts", "Alignment": "artefacts", "profile": "artefacts", "Profile": "artefacts",
    "Measurements": "artefacts", "run_batch": "batch",
    "rasterize": "raster", "LayerRaster": "raster", "GridMask": "raster", "raster_hierarchy": "raster",
    "layer_perimeters": "perimeters", "Perimeters": "perimeters",
    "layer_paths": "paths", "LayerPaths": "paths",
    "PrintSettings": "plan", "PrintPlan": "plan", "plan": "plan",
    "cut": "cut", "Cut": "cut", "CutWarning": "cut",
    "partition": "partition", "Partition": "partition", "stair_cut": "partition", "StairCut": "partition",
}

__all__ = ["Mesh", "MeshFileError", "MeshReport", "check", "load", "save", "__version__", *_LAZY]


class _Package(types.ModuleType):
    """The package module: a stage's function keeps its name when its module has the same name.

    Importing a submodule makes the import system set ``slicelab.<name>`` to that module;
    for ``split``, ``plan``, ``cut`` and the like the function must stay under that name
    (the module itself is always in ``sys.modules``).
    """

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and _LAZY.get(name) == name:
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


def __getattr__(name):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'slicelab' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
