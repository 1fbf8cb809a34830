"""Hierarchical radiosity (issue 15): accuracy against Mitsuba, build scale and the interactive updates.

Accuracy: the Cornell box and the office, the radiosity render (4×4 supersampled, as the path
tracer's box-filtered pixels) against Mitsuba 3 path tracing of the same polygons — mean relative
error over non-emitter pixels, PSNR — at the default parameters and a finer ε. The reference is the
mean of two renders with different seeds; half their mean relative difference is its own noise,
reported beside (an error below it cannot be measured).

Scale, in one run on the office: the build at the default parameters (elements, links, seconds; the
ratio to RenderPark's 5.4k elements / 42k links in 0.34 s), a lamp-intensity change re-solved with the
links kept, the chair moved by the dynamic update and the moved office rebuilt from scratch; then the
build time over ε from ~2k to ~50k elements, with the exponent of time against elements.

Polygon growth (issue 31, clusters): the Cornell box (no blocks) with a scanned mesh from
../shared/data/models on its floor, from the cow (5.8k triangles) to the Stanford dragon (202k),
plus the office, the living room, the museum and office3 (MGF): build seconds, peak memory,
elements and links against the input polygons, at the default ε, each build in a fresh process;
the exponent of time against polygons, and the scan rooms against n log n. Accuracy against
Mitsuba adds the living room and a scan room."""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.radiosity import HierarchyParams, Radiosity, RadiosityParams, RadiosityRenderer, scene_polygons
from illusio.radiosity.mitsuba import render_mitsuba, score
from illusio.scene import load_scene

from .runner import Timing

RENDERPARK = {"elements": 5400, "links": 42000, "seconds": 0.34}
_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
MODELS = Path(os.environ.get("ILLUSIO_MODELS", _DATA / "models"))
MGF = Path(os.environ.get("ILLUSIO_MGF", _DATA / "scenes" / "mgf"))
#: scanned meshes for the growth table, by triangle count
SCANS = (
    "cow.obj",
    "bunny.off",
    "rocker-arm.obj",
    "dragon_vrip_res3.ply",
    "stanford-bunny.obj",
    "armadillo.obj",
    "dragon_vrip_res2.ply",
)


def scan_room(model: str):
    """The Cornell box without its blocks, ``model`` (a file of MODELS) 0.3 m tall on its floor."""
    import warnings

    from illusio.scene.mesh import load_mesh
    from illusio.scene.scene import Node
    from illusio.scene.transforms import translate

    scene = load_scene("cornell-box")
    material = scene.nodes[0].material
    scene.nodes[:] = [n for n in scene.nodes if "block" not in n.name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the scans' own repairs (unreferenced vertices)
        mesh = load_mesh(MODELS / model).normalised(0.3)
    scene.nodes.append(Node("scan", mesh, translate((0.278, 0.0, 0.28)), material))
    return scene


def _seconds(fn) -> tuple[float, object]:
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def accuracy(ctx: Context, quick: bool, ratios: dict) -> None:
    cases = {
        "cornell-box": ((48, 48), 128) if quick else ((128, 128), 4096),
        "office": ((64, 48), 64) if quick else ((160, 120), 4096),
        "living-room": ((64, 36), 64)
        if quick
        else ((160, 90), 16384),  # its lamps light it unevenly: 2048 paths left 1.9 % noise over blocks
        "scan room, stanford-bunny (69k triangles)": ((48, 48), 64) if quick else ((128, 128), 2048),
    }
    renderer = RadiosityRenderer(ctx)
    for name, (size, spp) in cases.items():
        scene = scan_room("stanford-bunny.obj") if name.startswith("scan room") else load_scene(name)
        renderer.prepare(scene)
        view = scene.camera("main")
        # untextured on both sides: Mitsuba of the polygons at their mean reflectances, as the solve
        # below (textures=False) sees them (the reference of a textured scene carries its images)
        untextured = renderer.polygons.without_textures()
        halves = [render_mitsuba(untextured, view, size, spp // 2, seed=s) for s in (1, 2)]
        reference = (halves[0] + halves[1]) / 2
        # the defaults (the final gather at each pixel), the corners' display alone, and a finer mesh
        variants = (
            {"default": RadiosityParams(textures=False)}
            if quick
            else {
                "default": RadiosityParams(textures=False),
                "corner gather (gather_rays 0)": RadiosityParams(textures=False, gather_rays=0),
                "ε = 1e-5": RadiosityParams(HierarchyParams(epsilon=1e-5), textures=False),
            }
        )
        mask = None
        for label, params in variants.items():
            image, emitter = renderer.radiance(Frame(view, size), params, 4)
            mask = ~emitter
            s = score(image, reference, mask)
            st = renderer.result().stats
            ratios[f"{name}, {label} ({st.elements} elements, {st.links} links): mean relative error vs Mitsuba"] = (
                s.mean_relative_error
            )
            ratios[f"{name}, {label}: mean relative error vs Mitsuba over 4x4 blocks (goal <= 0.05)"] = score(
                image, reference, mask, block=4
            ).mean_relative_error
            ratios[f"{name}, {label}: PSNR dB vs Mitsuba, linear radiance (peak: its 99th percentile)"] = s.psnr
        noise = score(halves[0], halves[1], mask).mean_relative_error / 2
        ratios[f"{name}: the reference's own noise, mean relative ({spp} paths per pixel, {size[0]}x{size[1]})"] = noise
        ratios[f"{name}: the reference's own noise over 4x4 blocks"] = (
            score(halves[0], halves[1], mask, block=4).mean_relative_error / 2
        )
    renderer.release()


def scale(quick: bool, timings: list, ratios: dict) -> None:
    polygons = scene_polygons(load_scene("office"))
    params = HierarchyParams(epsilon=3e-4) if quick else HierarchyParams()
    warm = Radiosity(polygons, HierarchyParams(epsilon=1e-2)).build()  # numba compiles once
    nudge = np.eye(4)
    nudge[:3, 3] = (0.01, 0.0, 0.0)
    warm.move_object("chair-seat", nudge)  # and the edits' kernels, where the cache is cold
    build_s, sol = _seconds(lambda: Radiosity(polygons, params).build())
    st = sol.stats
    timings.append(
        Timing(
            "office/build",
            1,
            build_s * 1000,
            build_s * 1000,
            build_s * 1000,
            f"{st.elements} elements, {st.links} links, {st.rays} rays",
        )
    )
    ratios["office build: elements (goal >= 5000)"] = st.elements
    ratios["office build: links (goal >= 40000)"] = st.links
    ratios["office build: seconds (goal <= 3 on 2 cores)"] = build_s
    per_link = build_s / st.links / (RENDERPARK["seconds"] / RENDERPARK["links"])
    ratios["office build / RenderPark (0.34 s for 5.4k elements, 42k links): time ratio"] = (
        build_s / RENDERPARK["seconds"]
    )
    ratios["office build / RenderPark: time per link ratio"] = per_link

    # a slider dragged: five changes, the median (one change alone read 0.016-0.021 of a build)
    changes = [
        _seconds(lambda scale=scale: sol.set_lamps({"lamp-0": scale, "lamp-3": 2.0}))
        for scale in (0.25, 0.5, 0.75, 0.25, 1.5)
    ]
    seconds = [c[0] for c in changes]
    resolve_s, result = float(np.median(seconds)), changes[0][1]
    timings.append(
        Timing(
            "office/lamp change",
            len(seconds),
            resolve_s * 1000,
            min(seconds) * 1000,
            max(seconds) * 1000,
            f"links kept, {result.iterations} iterations of gather + push-pull (the first change)",
        )
    )
    ratios["lamp change / build time (goal <= 1/50 = 0.02)"] = resolve_s / build_s

    move = np.eye(4)
    move[:3, 3] = (0.3, 0.0, 0.2)
    move_s, _ = _seconds(lambda: sol.move_object("chair-seat", move))
    moved = polygons.corners.copy()
    rows = polygons.group == polygons.names.index("chair-seat")
    moved[rows] += move[:3, 3]
    rebuild_s, fresh = _seconds(lambda: Radiosity(dataclasses.replace(polygons, corners=moved), params).build())
    timings.append(Timing("office/move chair seat", 1, move_s * 1000, move_s * 1000, move_s * 1000, "dynamic update"))
    timings.append(
        Timing("office/rebuild with the seat moved", 1, rebuild_s * 1000, rebuild_s * 1000, rebuild_s * 1000)
    )
    ratios["moved object update / full rebuild time (goal <= 1/10 = 0.1)"] = move_s / rebuild_s

    growth = [3e-4, 1e-4, 4e-5] if quick else [6e-4, 1e-4, 4e-5, 1.5e-5, 5e-6, 2e-6]
    counts, seconds = [], []
    for eps in growth:
        s, sol = _seconds(lambda: Radiosity(polygons, HierarchyParams(epsilon=eps, min_area=2e-4)).build())
        counts.append(sol.stats.elements)
        seconds.append(s)
        timings.append(
            Timing(
                f"office/build ε={eps:g}",
                1,
                s * 1000,
                s * 1000,
                s * 1000,
                f"{sol.stats.elements} elements, {sol.stats.links} links",
            )
        )
        ratios[f"growth: ε={eps:g}: elements"] = sol.stats.elements
        ratios[f"growth: ε={eps:g}: links"] = sol.stats.links
        ratios[f"growth: ε={eps:g}: seconds"] = s
        ratios[f"growth: ε={eps:g}: seconds / (n log2 n) × 1e6"] = (
            s / (sol.stats.elements * np.log2(sol.stats.elements)) * 1e6
        )
    slope = np.polyfit(np.log(counts), np.log(seconds), 1)[0]
    ratios["growth: exponent of build time against elements"] = float(slope)


_BUILD_ONE = """
import json, resource, sys, time
sys.path.insert(0, {root!r})
from benchmarks.radiosity import scan_room
from illusio.radiosity import Radiosity, scene_polygons
from illusio.scene import load_scene
label, what = {label!r}, {what!r}
p = scene_polygons(scan_room(what) if label.startswith("scan") else load_scene(what or label))
Radiosity(scene_polygons(load_scene("cornell-box"))).build()      # numba's kernels loaded before the clock starts
t = time.perf_counter()
sol = Radiosity(p).build()
s = time.perf_counter() - t
print(json.dumps(dict(polygons=len(p), seconds=s, elements=sol.stats.elements, links=sol.stats.links,
                      cluster_links=sol.stats.cluster_links,
                      gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6)))
"""


def polygon_growth(quick: bool, timings: list, ratios: dict) -> None:
    """Each build in a fresh process, so each peak memory is its own (numba compiles from its cache)."""
    cases = [("office", None), ("office3 (MGF)", str(MGF / "office3.mgf")), ("living-room", None), ("museum", None)]
    cases += [(f"scan {m}", m) for m in (SCANS[:2] if quick else SCANS)]
    rows = []
    root = str(Path(__file__).resolve().parents[1])
    for label, what in cases:
        out = subprocess.run(
            [sys.executable, "-c", _BUILD_ONE.format(root=root, label=label, what=what)],
            capture_output=True,
            text=True,
            check=True,
        )
        row = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append((label, row))
        timings.append(
            Timing(
                f"radiosity growth/{label}",
                1,
                row["seconds"] * 1000,
                row["seconds"] * 1000,
                row["seconds"] * 1000,
                f"{row['polygons']} polygons, {row['elements']} elements, "
                f"{row['links']} links ({row['cluster_links']} through clusters), {row['gb']:.2f} GB peak",
            )
        )
        for key in ("polygons", "seconds", "elements", "links", "gb"):
            ratios[f"polygon growth: {label}: {key}"] = row[key]
    scans = [r for label, r in rows if label.startswith("scan")]
    n = np.array([r["polygons"] for r in scans], float)
    t = np.array([r["seconds"] for r in scans])
    ratios["polygon growth: exponent of build time against polygons (scan rooms)"] = float(
        np.polyfit(np.log(n), np.log(t), 1)[0]
    )
    for label, r in rows:
        if label.startswith("scan"):
            ratios[f"polygon growth: {label}: seconds / (n log2 n) x 1e6"] = (
                r["seconds"] / (r["polygons"] * np.log2(r["polygons"])) * 1e6
            )
    biggest = max(scans, key=lambda r: r["polygons"])
    ratios[f"polygon growth: largest scan room ({biggest['polygons']} polygons): seconds (goal <= 120 on 2 cores)"] = (
        biggest["seconds"]
    )
    ratios["polygon growth: largest scan room: peak GB (goal <= 8)"] = biggest["gb"]


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    polygon_growth(quick, timings, ratios)
    scale(quick, timings, ratios)
    accuracy(ctx, quick, ratios)
    return timings, ratios
