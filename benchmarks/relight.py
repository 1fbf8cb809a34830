"""Relighting (issue 16, as far as it has landed): the office photographed by Mitsuba, relit by each
method under the edits of Loscos' Figure 4.17, scored against Mitsuba's render of the same edit.

Edits: the back lamps off (lamp-0, lamp-1); the left lamps off and the right doubled; the right off
and the left doubled. Per method and edit: mean relative error and PSNR over the non-lamp pixels, and
the mean relative error inside the original shadow regions (leaves with a lamp link that is not
VISIBLE in the loscos preparation). The truth's own noise is half the mean relative difference of
two renders of it with different seeds. Times: preparation and one edit with its display."""

from __future__ import annotations

import dataclasses

import numpy as np

from illusio.core.context import Context
from illusio.radiosity.mitsuba import render_mitsuba, score
from illusio.relight import METHODS, RelightParams, RelightSession, builtin_real_scene

from .runner import Timing

EDITS = {"back lamps off": {"lamp-0": 0.0, "lamp-1": 0.0},
         "left off, right doubled": {"lamp-0": 0.0, "lamp-2": 0.0, "lamp-1": 2.0, "lamp-3": 2.0},
         "right off, left doubled": {"lamp-1": 0.0, "lamp-3": 0.0, "lamp-0": 2.0, "lamp-2": 2.0}}


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size, spp = ((80, 60), 32) if quick else ((160, 120), 512)
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    real = builtin_real_scene("office", size, spp)
    p = real.polygons
    truths, noise = {}, {}
    for name, edit in EDITS.items():
        factor = np.array([edit.get(n, 1.0) for n in p.names])[p.group]
        edited = dataclasses.replace(p, exitance=p.exitance * factor[:, None])
        halves = [render_mitsuba(edited, real.view, size, spp // 2, seed=s) for s in (11, 12)]
        truths[name] = (halves[0] + halves[1]) / 2
        noise[name] = halves
    sessions = {m: RelightSession(real, RelightParams(method=m), ctx) for m in METHODS}
    loscos = sessions["loscos"]
    leaves, _ = loscos.references
    shadowed = np.zeros(len(loscos.solution.hierarchy), bool)
    shadowed[leaves[loscos.shadowed]] = True
    ids = loscos.pixel_polygon
    lamp = np.isin(p.group, p.lamps)
    geometry = (ids >= 0) & ~lamp[np.maximum(ids, 0)]
    shadow = geometry & shadowed[np.maximum(loscos.pixel_element, 0)] & (loscos.pixel_element >= 0)
    ratios["pixels scored / in the original shadows"] = float(geometry.sum()) / max(float(shadow.sum()), 1)
    for name in EDITS:
        ratios[f"{name}: the truth's own noise, mean relative"] = score(noise[name][0], noise[name][1], geometry).mean_relative_error / 2
    for method, session in sessions.items():
        t = session.times["prepare"]
        timings.append(Timing(f"relight/{method}/prepare", 1, t * 1000, t * 1000, t * 1000,
                              f"{session.solution.stats.leaves} leaves, {size[0]}x{size[1]} photograph"))
        for name, edit in EDITS.items():
            image = session.image(edit)
            whole = score(image, truths[name], geometry)
            ratios[f"{method}, {name}: mean relative error"] = whole.mean_relative_error
            ratios[f"{method}, {name}: PSNR dB"] = whole.psnr
            ratios[f"{method}, {name}: mean relative error in the original shadows"] = score(image, truths[name], shadow).mean_relative_error
        t = session.times["edit"]
        timings.append(Timing(f"relight/{method}/lamp change with display", 1, t * 1000, t * 1000, t * 1000))
        ratios[f"{method}: lamp change / preparation time (goal <= 1/20)"] = session.times["edit"] / session.times["prepare"]
        session.release()
    return timings, ratios
