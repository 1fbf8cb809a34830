"""Hierarchical radiosity (issue 15): accuracy against Mitsuba, build scale and the interactive updates.

Accuracy: the Cornell box and the office, the radiosity render (4×4 supersampled, as the path
tracer's box-filtered pixels) against Mitsuba 3 path tracing of the same polygons — mean relative
error over non-emitter pixels, PSNR — at the default parameters and a finer ε. The reference is the
mean of two renders with different seeds; half their mean relative difference is its own noise,
reported beside (an error below it cannot be measured).

Scale, in one run on the office: the build at the default parameters (elements, links, seconds; the
ratio to RenderPark's 5.4k elements / 42k links in 0.34 s), a lamp-intensity change re-solved with the
links kept, the chair moved by the dynamic update and the moved office rebuilt from scratch; then the
build time over ε from ~2k to ~50k elements, with the exponent of time against elements."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.radiosity import HierarchyParams, Radiosity, RadiosityParams, RadiosityRenderer, scene_polygons
from illusio.radiosity.mitsuba import render_mitsuba, score
from illusio.scene import load_scene

from .runner import Timing

RENDERPARK = {"elements": 5400, "links": 42000, "seconds": 0.34}


def _seconds(fn) -> tuple[float, object]:
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def accuracy(ctx: Context, quick: bool, ratios: dict) -> None:
    cases = {"cornell-box": ((48, 48), 128) if quick else ((128, 128), 4096),
             "office": ((64, 48), 64) if quick else ((160, 120), 4096)}
    renderer = RadiosityRenderer(ctx)
    for name, (size, spp) in cases.items():
        scene = load_scene(name)
        renderer.prepare(scene)
        view = scene.camera("main")
        halves = [render_mitsuba(renderer.polygons, view, size, spp // 2, seed=s) for s in (1, 2)]
        reference = (halves[0] + halves[1]) / 2
        variants = {"default": HierarchyParams()} if quick else {
            "default": HierarchyParams(), "ε = 1e-5": HierarchyParams(epsilon=1e-5)}
        mask = None
        for label, hierarchy in variants.items():
            image, emitter = renderer.radiance(Frame(view, size), RadiosityParams(hierarchy), 4)
            mask = ~emitter
            s = score(image, reference, mask)
            st = renderer.result().stats
            ratios[f"{name}, {label} ({st.elements} elements, {st.links} links): mean relative error vs Mitsuba (goal <= 0.05)"] = s.mean_relative_error
            ratios[f"{name}, {label}: PSNR dB vs Mitsuba"] = s.psnr
        noise = score(halves[0], halves[1], mask).mean_relative_error / 2
        ratios[f"{name}: the reference's own noise, mean relative ({spp} paths per pixel, {size[0]}x{size[1]})"] = noise
    renderer.release()


def scale(quick: bool, timings: list, ratios: dict) -> None:
    polygons = scene_polygons(load_scene("office"))
    params = HierarchyParams(epsilon=3e-4) if quick else HierarchyParams()
    Radiosity(polygons, HierarchyParams(epsilon=1e-2)).build()          # numba compiles once
    build_s, sol = _seconds(lambda: Radiosity(polygons, params).build())
    st = sol.stats
    timings.append(Timing("office/build", 1, build_s * 1000, build_s * 1000, build_s * 1000,
                          f"{st.elements} elements, {st.links} links, {st.rays} rays"))
    ratios["office build: elements (goal >= 5000)"] = st.elements
    ratios["office build: links (goal >= 40000)"] = st.links
    ratios["office build: seconds (goal <= 3 on 2 cores)"] = build_s
    per_link = build_s / st.links / (RENDERPARK["seconds"] / RENDERPARK["links"])
    ratios["office build / RenderPark (0.34 s for 5.4k elements, 42k links): time ratio"] = build_s / RENDERPARK["seconds"]
    ratios["office build / RenderPark: time per link ratio"] = per_link

    resolve_s, result = _seconds(lambda: sol.set_lamps({"lamp-0": 0.25, "lamp-3": 2.0}))
    timings.append(Timing("office/lamp change", 1, resolve_s * 1000, resolve_s * 1000, resolve_s * 1000,
                          f"links kept, {result.iterations} iterations of gather + push-pull"))
    ratios["lamp change / build time (goal <= 1/50 = 0.02)"] = resolve_s / build_s

    move = np.eye(4)
    move[:3, 3] = (0.3, 0.0, 0.2)
    move_s, _ = _seconds(lambda: sol.move_object("chair-seat", move))
    moved = polygons.corners.copy()
    rows = polygons.group == polygons.names.index("chair-seat")
    moved[rows] += move[:3, 3]
    rebuild_s, fresh = _seconds(lambda: Radiosity(dataclasses.replace(polygons, corners=moved), params).build())
    timings.append(Timing("office/move chair seat", 1, move_s * 1000, move_s * 1000, move_s * 1000, "dynamic update"))
    timings.append(Timing("office/rebuild with the seat moved", 1, rebuild_s * 1000, rebuild_s * 1000, rebuild_s * 1000))
    ratios["moved object update / full rebuild time (goal <= 1/10 = 0.1)"] = move_s / rebuild_s

    growth = [3e-4, 1e-4, 4e-5] if quick else [6e-4, 1e-4, 4e-5, 1.5e-5, 5e-6, 2e-6]
    counts, seconds = [], []
    for eps in growth:
        s, sol = _seconds(lambda: Radiosity(polygons, HierarchyParams(epsilon=eps, min_area=2e-4)).build())
        counts.append(sol.stats.elements)
        seconds.append(s)
        timings.append(Timing(f"office/build ε={eps:g}", 1, s * 1000, s * 1000, s * 1000,
                              f"{sol.stats.elements} elements, {sol.stats.links} links"))
        ratios[f"growth: ε={eps:g}: elements"] = sol.stats.elements
        ratios[f"growth: ε={eps:g}: links"] = sol.stats.links
        ratios[f"growth: ε={eps:g}: seconds"] = s
        ratios[f"growth: ε={eps:g}: seconds / (n log2 n) × 1e6"] = s / (sol.stats.elements * np.log2(sol.stats.elements)) * 1e6
    slope = np.polyfit(np.log(counts), np.log(seconds), 1)[0]
    ratios["growth: exponent of build time against elements"] = float(slope)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    scale(quick, timings, ratios)
    accuracy(ctx, quick, ratios)
    return timings, ratios
