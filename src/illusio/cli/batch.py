"""illusio batch: run a job file (many frames, many runs) here, in local workers or on Ray.

``--ray`` takes an optional value: :func:`optional_values` gives a bare ``--ray`` the value
``local`` before the command line is parsed (click's optional values swallow the next option)."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.errors import InputError

#: options whose value may be left out, and the value they then take
OPTIONAL_VALUES = {"--ray": "local"}


def optional_values(argv: list[str]) -> list[str]:
    """``[..., "--ray", "--workers", "2"]`` → ``[..., "--ray", "local", "--workers", "2"]``."""
    out = []
    for k, word in enumerate(argv):
        out.append(word)
        if word in OPTIONAL_VALUES and (k + 1 == len(argv) or argv[k + 1].startswith("-")):
            out.append(OPTIONAL_VALUES[word])
    return out


def batch(
    job: Path = typer.Argument(
        ..., help="the job file (YAML: tasks with command, inputs, options, sweep, frames, output, video)"
    ),
    out: Path = typer.Option(..., "--out", help="folder for the outputs and the manifest (manifest.jsonl)"),
    workers: int = typer.Option(
        0, "--workers", help="local worker processes (0: run in this process); with --ray, actors"
    ),
    ray: str = typer.Option(
        None,
        "--ray",
        metavar="[ADDRESS]",
        help="run on Ray (pip install 'illusio[cluster]'): --ray alone starts a local cluster; "
        "--ray auto or --ray HOST:PORT joins one",
    ),
    retries: int = typer.Option(1, "--retries", help="tries again after a task fails, before reporting it"),
) -> None:
    """Run JOB: every task through the illusio command it names, in workers that stay warm; a rerun
    skips what the manifest lists as done and redoes what is missing or changed."""
    import sys

    from ..batch import Interrupted, load_job, run_job
    from .common import progress

    if workers < 0 or retries < 0:
        raise InputError("--workers and --retries must be ≥ 0")
    spec = load_job(job)
    if out.resolve() == job.resolve().parent and any((out / t.output).resolve() == job.resolve() for t in spec.tasks):
        raise InputError("an output of the job would replace the job file")
    with progress(len(spec.tasks), "batch: tasks") as advance:
        try:
            report = run_job(
                spec, out, workers, retries, ray is not None, None if ray in (None, "local") else ray, advance
            )
        except Interrupted as stop:
            r = stop.report
            typer.echo(
                f"illusio: interrupted: {r.ran} tasks finished, the manifest lists them; run again to resume", err=True
            )
            raise typer.Exit(130) from None
    typer.echo(
        f"{report.ran} ran, {report.skipped} already done, {len(report.failed)} failed"
        f"{f', {report.retried} retried' if report.retried else ''}"
        f"{f', {report.restarted} given to another worker' if report.restarted else ''}"
        f"{', videos: ' + ', '.join(report.videos) if report.videos else ''}"
    )
    for output, message in report.failed.items():
        print(f"illusio: failed: {output}: {message}", file=sys.stderr)
    if report.failed:
        raise typer.Exit(1)
