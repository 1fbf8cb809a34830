"""Running a job: in this process, in N local worker processes, or on a Ray cluster (one actor per
worker). The coordinator (this process) keeps the queue, the retries and the manifest; workers only
run tasks (:func:`worker.run_task`). A task that fails is retried ``retries`` times, then reported;
a worker that dies takes no finished output with it, and its task is given to another worker without
counting as a try. Ctrl-C stops the workers; outputs are written atomically by the commands, so none
is partial, and the manifest lists exactly what finished."""

from __future__ import annotations

import contextlib
import multiprocessing
import os
from collections import Counter
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InputError
from .job import Job, Task
from .manifest import Manifest
from .worker import TaskFailed, run_task

__all__ = ["Report", "run_job", "Interrupted"]


@dataclass
class Report:
    ran: int = 0
    skipped: int = 0
    failed: dict = field(default_factory=dict)  # output → error line
    retried: int = 0
    restarted: int = 0  # tasks given again after a worker died
    videos: list = field(default_factory=list)
    workers: set = field(default_factory=set)


class Interrupted(Exception):
    """Ctrl-C: ``report`` says what finished."""

    def __init__(self, report: Report):
        super().__init__("interrupted")
        self.report = report


class _Books:
    """The coordinator's bookkeeping, shared by every backend."""

    def __init__(self, job: Job, out: Path, retries: int, advance: Callable[[int], None], task_fn=run_task):
        self.out, self.retries, self.advance, self.task_fn = out, retries, advance, task_fn
        self.manifest = Manifest(out)
        self.report = Report()
        self.queue: list[Task] = []
        for task in job.tasks:
            if self.manifest.done(task.key, out / task.output):
                self.report.skipped += 1
                advance(1)
            else:
                self.queue.append(task)
        self.queue.reverse()  # pop() takes them in the job's order
        self.tries: Counter = Counter()

    def finished(self, task: Task, result) -> None:
        path, seconds, worker = result
        self.manifest.record(task.key, Path(path), task.output, seconds, worker)
        self.report.ran += 1
        self.report.workers.add(worker)
        self.advance(1)

    def failed(self, task: Task, message: str) -> None:
        self.tries[task] += 1
        if self.tries[task] <= self.retries:
            self.report.retried += 1
            self.queue.insert(0, task)  # again, after the others
        else:
            self.report.failed[task.output] = message
            self.advance(1)

    def lost(self, task: Task) -> None:
        """``task``'s worker died: run it again, without the half-written file it may have left."""
        from ..core.images import remove_partial_outputs

        remove_partial_outputs(self.out / task.output)
        self.report.restarted += 1
        self.queue.append(task)


def _in_process(books: _Books) -> None:
    while books.queue:
        task = books.queue.pop()
        try:
            books.finished(task, books.task_fn(task, str(books.out)))
        except TaskFailed as exc:
            books.failed(task, str(exc))


def _pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))


def _processes(books: _Books, workers: int) -> None:
    pool = _pool(workers)
    running: dict = {}
    try:
        while books.queue or running:
            broken = False
            while books.queue and len(running) < workers:
                task = books.queue.pop()
                try:
                    running[pool.submit(books.task_fn, task, str(books.out))] = task
                except BrokenProcessPool:  # a worker died before its future said so: the pool is gone
                    books.queue.append(task)
                    broken = True
                    break
            # the finished are kept even when the pool broke on a submit; the unfinished run again below
            done = {f for f in running if f.done()} if broken else wait(running, return_when=FIRST_COMPLETED)[0]
            for future in done:
                task = running.pop(future)
                try:
                    books.finished(task, future.result())
                except TaskFailed as exc:
                    books.failed(task, str(exc))
                except BrokenProcessPool:
                    books.lost(task)
                    broken = True
            if broken:  # a worker died: the others' tasks are lost with the pool, run them again
                for task in running.values():
                    books.lost(task)
                running.clear()
                pool.shutdown(wait=False, cancel_futures=True)
                pool = _pool(workers)
    finally:
        for process in list(getattr(pool, "_processes", {}).values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)


class _Actor:
    """A Ray worker: one process holding a GL context on the GPU Ray gave it (if any)."""

    def __init__(self):
        import ray

        gpus = ray.get_gpu_ids()
        if gpus:  # render on the EGL device of the GPU Ray assigned (EGL lists devices as CUDA does)
            os.environ["ILLUSIO_EGL_DEVICE"] = str(int(gpus[0]))

    def run(self, task: Task, out: str, task_fn=run_task):
        try:
            return task_fn(task, out)
        except TaskFailed as exc:
            return ("failed", str(exc))

    def pid(self) -> int:
        return os.getpid()


def _ray(books: _Books, workers: int, address: str | None, on_start: Callable | None = None) -> None:
    try:
        import ray
    except ImportError:
        raise InputError("--ray needs Ray: pip install 'illusio[cluster]'") from None
    if not ray.is_initialized():
        import logging

        quiet = {"log_to_driver": False, "logging_level": logging.ERROR}
        try:
            if address:
                ray.init(address=address, **quiet)
            else:
                ray.init(num_cpus=max(workers, 1), include_dashboard=False, **quiet)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            where = f"the Ray cluster at {address}" if address else "a local Ray cluster"
            raise InputError(f"cannot start or join {where}: {' '.join(str(exc).split())[:200]}") from None
    gpus = ray.cluster_resources().get("GPU", 0)
    actor_class = ray.remote(num_cpus=1, num_gpus=1 if gpus >= 1 else 0, max_restarts=0)(_Actor)
    count = workers or max(1, int(gpus) if gpus >= 1 else int(ray.cluster_resources().get("CPU", 1)))
    actors = [actor_class.remote() for _ in range(count)]
    idle = list(actors)
    running: dict = {}
    if on_start is not None:
        on_start(actors)
    try:
        while books.queue or running:
            while books.queue and idle:
                actor = idle.pop()
                task = books.queue.pop()
                running[actor.run.remote(task, str(books.out), books.task_fn)] = (actor, task)
            ready, _ = ray.wait(list(running), num_returns=1)
            for ref in ready:
                actor, task = running.pop(ref)
                try:
                    result = ray.get(ref)
                except ray.exceptions.RayActorError:  # the worker died: a new one, the task again
                    books.lost(task)
                    idle.append(actor_class.remote())
                    continue
                idle.append(actor)
                if result[0] == "failed":
                    books.failed(task, result[1])
                else:
                    books.finished(task, result)
    finally:
        for actor in actors + idle:
            with contextlib.suppress(Exception):
                ray.kill(actor)


def run_job(
    job: Job,
    out: Path,
    workers: int = 0,
    retries: int = 1,
    use_ray: bool = False,
    address: str | None = None,
    advance: Callable[[int], None] = lambda n=1: None,
    on_start: Callable | None = None,
    task_fn=run_task,
) -> Report:
    """Run what ``job`` still lacks in ``out``; assemble its videos. ``workers``: 0 runs in this
    process, N > 0 in N local processes (or N Ray actors with ``use_ray``). ``on_start(actors)`` is
    called with the Ray actors once made; ``task_fn(task, out)`` runs a task (tests wrap it)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    books = _Books(job, out, retries, advance, task_fn)
    try:
        if use_ray:
            _ray(books, workers, address, on_start)
        elif workers > 0:
            _processes(books, workers)
        else:
            _in_process(books)
    except KeyboardInterrupt:
        raise Interrupted(books.report) from None
    _videos(job, out, books)
    return books.report


def _videos(job: Job, out: Path, books: _Books) -> None:
    from ..core.images import read_image, write_video

    for entry, video, fps, frames in job.videos:
        if any(f in books.report.failed for f in frames):
            books.report.failed[video] = f"task {entry}: not assembled, some frames failed"
            continue
        target = out / video
        if target.exists() and books.report.ran == 0:
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        write_video(target, [read_image(out / f) for f in frames], fps)
        books.report.videos.append(video)
