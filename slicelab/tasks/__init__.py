"""Jobs run on files, shared by the command line and `run_batch`.

==========================  =====================================================
``tasks.spec``              what a job is: `Job`, checked parameters, `JobResult`
``tasks.jobs``              the jobs (`JOBS`), `job_parameters`, `run_job`
``tasks.fabrication``       the cut, partition and slice jobs
``tasks.executors``         `run_jobs`: in this process, local processes or Dask
``tasks.batch``             `run_batch` over a folder: reports, summary, resuming
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"Job": "spec", "JobInput": "spec", "JobResult": "spec", "ParameterError": "spec", "JOBS": "jobs",
          "job_parameters": "jobs", "run_job": "jobs", "run_jobs": "executors", "TASKS": "batch",
          "BatchResult": "batch", "task_parameters": "batch", "find_stl_files": "batch",
          "process_file": "batch", "run_batch": "batch", "write_summary": "batch"}


__all__ = ["Job", "JobInput", "JobResult", "ParameterError", "JOBS", "job_parameters", "run_job", "run_jobs",
           "TASKS", "BatchResult", "task_parameters", "find_stl_files", "process_file", "run_batch",
           "write_summary"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
