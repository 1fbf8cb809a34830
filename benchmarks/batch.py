"""Batch jobs (issue 17): tasks per second in this process and with 1 and 2 warm worker processes,
against a fresh ``illusio`` process per task (what a shell loop would do), on one job of short
tasks (apparent ridges of the built-in shapes at 256×256, a τ sweep): the ratio shows why workers
are kept warm. The per-task time and the coordinator's per-task overhead feed the model of
RESULTS.md (throughput with N workers ≈ N / (task time + start-up / tasks per worker), capped by
the cores)."""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from illusio.batch import load_job, run_job
from illusio.core.context import Context

from .runner import Timing

JOB = """
tasks:
  - command: lines
    arguments: [torus-knot, gear, blob, superquadric]
    options: {{size: {size}}}
    sweep: {{tau: [-1.0, 0.0, 1.0], lambda: [0.5, 2.0]}}
    output: "{{input_stem}}-tau{{tau}}-lambda{{lambda}}.png"
"""


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="illusio-batch-bench-") as tmp:
        tmp = Path(tmp)
        (tmp / "job.yaml").write_text(JOB.format(size="128x128" if quick else "384x384"))
        job = load_job(tmp / "job.yaml")
        n = len(job.tasks)
        per_second = {}
        for label, workers in (("in this process", 0), ("1 worker", 1), ("2 workers", 2)):
            out = tmp / f"out-{workers}"
            start = time.perf_counter()
            report = run_job(job, out, workers=workers)
            seconds = time.perf_counter() - start
            assert report.ran == n and not report.failed
            per_second[workers] = n / seconds
            timings.append(
                Timing(
                    f"batch/{label}",
                    1,
                    seconds * 1000,
                    seconds * 1000,
                    seconds * 1000,
                    f"{n} tasks, pool start-up included",
                )
            )
            ratios[f"tasks per second, {label}"] = n / seconds
            shutil.rmtree(out)
        # a fresh process per task, as a shell loop over `illusio lines ...` would run them
        sample = job.tasks[: 3 if quick else 6]
        start = time.perf_counter()
        for task in sample:
            subprocess.run(
                [sys.executable, "-m", "illusio", *task.argv, "-o", str(tmp / "fresh.png")],
                check=True,
                capture_output=True,
            )
        fresh = (time.perf_counter() - start) / len(sample)
        timings.append(
            Timing(
                "batch/fresh process per task",
                1,
                fresh * 1000,
                fresh * 1000,
                fresh * 1000,
                f"mean over {len(sample)} tasks",
            )
        )
        ratios["tasks per second, a fresh process per task"] = 1 / fresh
        ratios["warm worker / fresh process per task, tasks per second (1 worker)"] = per_second[1] * fresh
        ratios["2 workers / 1 worker, tasks per second"] = per_second[2] / per_second[1]
        ratios["in this process / 1 worker, tasks per second"] = per_second[0] / per_second[1]
        task_s = 1 / per_second[0]
        startup = n / per_second[1] - n * task_s
        ratios["per-task seconds (in this process)"] = task_s
        ratios["worker start-up seconds (1-worker run less n tasks)"] = startup
        for workers in (2, 4, 8):
            # N workers each on its own device: n tasks take start-up + n·c/N
            ratios[f"model: {workers} / 1 workers, tasks per second, one device each"] = (startup + n * task_s) / (
                startup + n * task_s / workers
            )
    return timings, ratios
