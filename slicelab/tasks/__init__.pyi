"""The names ``slicelab.tasks`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .plates import write_plates as write_plates, arrange_files as arrange_files
from .spec import Job as Job, JobInput as JobInput, JobResult as JobResult, ParameterError as ParameterError
from .jobs import JOBS as JOBS, job_parameters as job_parameters, run_job as run_job, TASKS as TASKS
from .executors import run_jobs as run_jobs
from .batch import (
    BatchResult as BatchResult,
    task_parameters as task_parameters,
    find_mesh_files as find_mesh_files,
    process_file as process_file,
    run_batch as run_batch,
    write_summary as write_summary,
)
