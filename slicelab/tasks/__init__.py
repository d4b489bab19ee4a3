"""Jobs run on files, shared by the command line and `run_batch`.

==========================  =====================================================
``tasks.batch``             `run_batch` over a folder, on processes or Dask
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"TASKS": "batch", "BatchResult": "batch", "task_parameters": "batch", "find_stl_files": "batch", "process_file": "batch", "run_batch": "batch", "write_summary": "batch"}


__all__ = ["TASKS", "BatchResult", "task_parameters", "find_stl_files", "process_file", "run_batch", "write_summary"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
