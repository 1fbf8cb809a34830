"""Batch jobs: one YAML job file, run in this process, in local worker processes or on a Ray cluster,
resumable through a manifest (``illusio batch``)."""

from .job import Job, Task, load_job
from .runner import Interrupted, Report, run_job

__all__ = ["Job", "Task", "load_job", "run_job", "Report", "Interrupted"]
