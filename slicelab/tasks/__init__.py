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

from .._lazy import attach_stub

# The public names and their submodules are listed once, in __init__.pyi; each submodule loads
# the first time one of its names is used.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
