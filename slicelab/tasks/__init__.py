"""Jobs run on files, shared by the command line and `run_batch`.

==========================  =====================================================
``tasks.spec``              what a job is: `Job`, checked parameters, `JobResult`
``tasks.jobs``              the jobs (`JOBS`), `job_parameters`, `run_job`
``tasks.fabrication``       the cut, partition and slice jobs
``tasks.limits``            work estimated from the part and refused up front when impossible
``tasks.plates``            build plates written: one STL each, placements, top views
``tasks.executors``         `run_jobs`: in this process, local processes or Dask
``tasks.outputs``           each batch input's own output folder and report name
``tasks.threads``           BLAS and OpenMP held to one thread: the same numbers on any machine
``tasks.summary``           a batch's summary.csv (units in every column) and rim-diameter chart
``tasks.batch``             `run_batch` over a folder: reports, summary, resuming
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"write_plates": "plates", "arrange_files": "plates", "Job": "spec", "JobInput": "spec", "JobResult": "spec", "ParameterError": "spec", "JOBS": "jobs",
          "job_parameters": "jobs", "run_job": "jobs", "run_jobs": "executors", "TASKS": "jobs",
          "BatchResult": "batch", "task_parameters": "batch", "find_mesh_files": "batch",
          "process_file": "batch", "run_batch": "batch", "write_summary": "batch"}


__all__ = ["write_plates", "arrange_files", "Job", "JobInput", "JobResult", "ParameterError", "JOBS", "job_parameters", "run_job", "run_jobs",
           "TASKS", "BatchResult", "task_parameters", "find_mesh_files", "process_file", "run_batch",
           "write_summary"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
