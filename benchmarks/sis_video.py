"""Stereogram videos (issue 46): the mean frame-to-frame change where the depth stays the same, with
the colours held (illusio.sis.video) against every frame regenerated with the same pattern, and the
time a frame takes each way (the CPU reference: the held frames add the chain roots and the tree
vote). Two depth videos: the torus knot turning (the CLI's turntable) and a sphere crossing a far
background; 24 frames each at 640×360."""

from __future__ import annotations

import time

import numpy as np

from illusio.core.context import Context
from illusio.scene.builtin import shape
from illusio.sis.params import StereogramParams
from illusio.sis.video import StereogramSequence, turntable_depths, unchanged_change

from .runner import Timing


def crossing_sphere(size, frames):
    w, h = size
    yy, xx = np.mgrid[0:h, 0:w]
    out = []
    for k in range(frames):
        r2 = ((xx - 0.35 * w - 4 * k) ** 2 + (yy - h / 2) ** 2) / (0.15 * w) ** 2
        out.append(np.where(r2 < 1, 0.9 - 0.7 * np.sqrt(np.clip(1 - r2, 0, 1)), 0.9).astype(np.float32))
    return out


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size, frames = ((320, 180), 8) if quick else ((640, 360), 24)
    videos = {
        "torus-knot turning": list(turntable_depths(ctx, shape("torus-knot"), size, 48))[:frames],
        "sphere crossing": crossing_sphere(size, frames),
    }
    timings, ratios = [], {}
    for name, depths in videos.items():
        same = float(np.mean([np.mean(depths[k] == depths[k - 1]) for k in range(1, len(depths))]))
        ratios[f"{name}: share of pixels whose depth stays"] = same
        change = {}
        for hold in (True, False):
            label = "held" if hold else "regenerated"
            samples = []
            for _ in range(max(1, repeat)):
                sequence = StereogramSequence(StereogramParams(), hold)
                t0 = time.perf_counter()
                images = [sequence.frame(d) for d in depths]
                samples.append((time.perf_counter() - t0) * 1000 / len(depths))
            change[hold] = unchanged_change(images, depths)
            ratios[f"{name}: mean change where the depth stays, {label}"] = change[hold]
            timings.append(
                Timing(
                    f"sis-video/{name}: {label}, a frame",
                    len(samples),
                    float(np.median(samples)),
                    min(samples),
                    max(samples),
                    f"{size[0]}×{size[1]}",
                )
            )
        ratios[f"{name}: change held / regenerated"] = change[True] / max(change[False], 1e-12)
    by = {t.name: t for t in timings}
    for name in videos:
        ratios[f"{name}: time held / regenerated"] = (
            by[f"sis-video/{name}: held, a frame"].min_ms / by[f"sis-video/{name}: regenerated, a frame"].min_ms
        )
    return timings, ratios
