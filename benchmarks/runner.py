"""Time named cases over repeated runs (warm-up, then median/min/max) and write JSON.

A case is a callable that does one complete unit of work and waits for the GPU to finish
(``ctx.finish()`` or a readback), so wall time measures the work itself.
"""

from __future__ import annotations

import json
import platform
import statistics
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from datetime import datetime, timezone
from pathlib import Path


@dataclass
class Timing:
    name: str
    runs: int
    median_ms: float
    min_ms: float
    max_ms: float
    notes: str = ""


def time_case(name: str, fn: Callable[[], object], repeat: int = 10, warmup: int = 2, notes: str = "") -> Timing:
    for _ in range(warmup):
        fn()
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        samples.append((time.perf_counter() - t0) * 1000)
    return Timing(name, repeat, statistics.median(samples), min(samples), max(samples), notes)


def time_interleaved(
    cases: dict[str, tuple[Callable[[], object], str]],
    repeat: int = 10,
    warmup: int = 2,
    samples: dict[str, list[float]] | None = None,
) -> list[Timing]:
    """Time ``cases`` ({name: (fn, notes)}) one run of each in turn, ``repeat`` rounds: cases whose
    ratio is a goal, on a machine whose speed drifts between cases run one after another.
    ``samples``, given: filled with each case's times (ms), a round each, for :func:`paired_ratio`."""
    for _ in range(warmup):
        for fn, _ in cases.values():
            fn()
    got: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(repeat):
        for name, (fn, _) in cases.items():
            t0 = time.perf_counter()
            fn()
            got[name].append((time.perf_counter() - t0) * 1000)
    if samples is not None:
        samples.update(got)
    return [
        Timing(name, repeat, statistics.median(got[name]), min(got[name]), max(got[name]), notes)
        for name, (_, notes) in cases.items()
    ]


def paired_ratio(samples: dict[str, list[float]], numerator: str, denominator: str) -> float:
    """The median over rounds of ``numerator``'s time over ``denominator``'s in the same round
    (time_interleaved's ``samples``): each pair ran seconds apart, so a slowdown of the machine that
    lasts a few frames moves one round's ratio, not the medians of the two cases apart."""
    return float(statistics.median(a / b for a, b in zip(samples[numerator], samples[denominator])))


def machine(ctx) -> dict:
    import os

    info = ctx.info()
    return {
        "renderer": info["renderer"],
        "gl_version": info["version"],
        "cpu_count": os.cpu_count(),
        "platform": platform.platform(),
        "python": platform.python_version(),
    }


def write_results(path: Path, suite: str, ctx, timings: list[Timing], ratios: dict[str, float]) -> dict:
    data = {
        "suite": suite,
        "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "machine": machine(ctx),
        "timings": [asdict(t) for t in timings],
        "ratios": ratios,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=2))
    tmp.replace(path)
    return data


def print_table(timings: list[Timing], ratios: dict[str, float]) -> None:
    if timings:  # a quality suite (sis_quality) has measurements only
        width = max(len(t.name) for t in timings)
        print(f"{'case':<{width}}  {'median ms':>10}  {'min':>8}  {'max':>8}  runs")
    for t in timings:
        print(f"{t.name:<{width}}  {t.median_ms:>10.2f}  {t.min_ms:>8.2f}  {t.max_ms:>8.2f}  {t.runs}")
    for k, v in ratios.items():
        print(f"ratio {k}: {v:.2f}" if timings else f"{k}: {v:g}")
