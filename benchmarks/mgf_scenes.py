"""RenderPark's MGF scenes (issue 45): each solved by radiosity at the default parameters (clusters,
ε = 6·10⁻⁵, two-sided surfaces as MGF has them) and scored against Mitsuba 3 path-tracing the same
polygons from the same camera — the mean relative error over 4×4 blocks (the radiosity goal: 5 %)
and the ratio of the mean radiances — beside the build's time, elements and links. The reference
takes 1,024 paths a pixel; a second one with another seed gives its own noise (the error of one
against the other, over √2), the floor under which a score says nothing.

The link store in numbers beside the counts: bytes per element link and per cluster link (the
arrays' item sizes), the store's megabytes, the build's microseconds per link, and the process's
peak resident memory after the scene (the scenes run in growing order, so each peak is that scene's
or below).

At RenderPark's element count (issue 45: its figures from a build of its sources on a 2-core
machine, with the command line in RESULTS — the Graz office 309k elements, 3.2M links, 67–85 s,
0.91 GB): the Graz office again with ``MATCHED`` (ε 10⁻⁵, minimum element area 6·10⁻⁴ m², 277k
elements), its build alone in a fresh process (time after the file's parsing; peak resident memory
of that process, as RenderPark's is of its own), then drawn here and scored as the others; and
built alone once more with ``FULL`` (ε 8·10⁻⁶, 5·10⁻⁴ m², 307k elements: its full count). office2's
build alone at the defaults the same way, against RenderPark's 3.5–4.3 s (12.7k elements, 170k
links). Neither with ``--quick``.

One build per scene (a build is seconds to a minute; ``--repeat`` is not used). The scenes are read
from ../shared/data/scenes/mgf (ILLUSIO_MGF), never copied; missing scenes are skipped. ``--quick``:
the cube and office2 at 48×36 and 64 paths a pixel."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
import warnings

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame

from .radiosity import MGF
from .runner import Timing

SCENES = ("cube", "office2", "office3", "graz")
QUICK_SCENES = ("cube", "office2")
#: the Graz office at RenderPark's element count: HierarchyParams' fields, and RenderPark's figures
MATCHED = {"epsilon": 1e-5, "min_area": 6e-4}
#: the Graz office at RenderPark's full element count (307k against its 309k): built alone only
FULL = {"epsilon": 8e-6, "min_area": 5e-4}
RENDERPARK_GRAZ = {"elements": 309_000, "links": 3.2e6, "seconds": (67.0, 85.0), "peak GB": 0.91}
#: RenderPark's office2 at its defaults (the issue's table; its memory was not recorded)
RENDERPARK_OFFICE2 = {"elements": 12_700, "links": 170e3, "seconds": (3.5, 4.3)}

# the build alone in its own process: prints its counts, seconds and peak resident memory as JSON —
# the high-water mark of its own memory since it started (VmHWM; ru_maxrss keeps the parent's from
# before the exec, the benchmark's own gigabytes once it has drawn the Graz office)
_BUILD_ALONE = """
import json, sys, time, warnings
from illusio.radiosity import HierarchyParams, Radiosity, scene_polygons
from illusio.scene.mgf import load_mgf
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    polygons = scene_polygons(load_mgf(sys.argv[1]))
    start = time.perf_counter()
    solution = Radiosity(polygons, HierarchyParams(**json.loads(sys.argv[2]))).build()
    seconds = time.perf_counter() - start
def peak_kb():
    try:
        with open("/proc/self/status") as status:
            return next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    except OSError:  # no /proc: the process's own peak as the system counts it
        import resource
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
stats = solution.stats
print(json.dumps({"elements": stats.elements, "links": stats.links, "cluster links": stats.cluster_links,
                  "seconds": seconds, "converged": bool(solution.result.converged),
                  "peak GB": peak_kb() / 1e6}))
"""


def link_bytes(solution) -> tuple[float, float]:
    """Bytes a link takes in the store: the item sizes of the element links' arrays (receiver, source,
    form factor, visibility; tag and rays once an edit stores them) and of the cluster links'
    (receiver, source, the two kernels, visibility)."""
    links, cluster = solution.links, solution.cluster_links
    element = links.item_bytes()
    per_cluster = sum(a.itemsize * int(np.prod(a.shape[1:])) for a in (getattr(cluster, n) for n in cluster._FIELDS))
    return float(element), float(per_cluster)


def build_alone(path, label: str, ratios: dict, hierarchy: dict, peer: dict) -> None:
    """The build with ``hierarchy`` (HierarchyParams' fields) in a fresh process (its own peak
    memory): its counts, seconds and peak, and their ratios to RenderPark's figures ``peer`` (its
    fastest time; its memory where recorded)."""
    out = subprocess.run(
        [sys.executable, "-c", _BUILD_ALONE, str(path), json.dumps(hierarchy)],
        capture_output=True,
        text=True,
        check=True,
    )
    got = json.loads(out.stdout.strip().splitlines()[-1])
    for key in ("elements", "links", "cluster links", "seconds", "peak GB"):
        ratios[f"{label}, the build alone in its own process: {key}"] = float(got[key])
    ratios[f"{label}, the build alone: converged (1 yes)"] = float(got["converged"])
    ratios[f"{label}, the build alone: elements / RenderPark's"] = got["elements"] / peer["elements"]
    ratios[f"{label}, the build alone: time / RenderPark's fastest (goal <= 1)"] = got["seconds"] / peer["seconds"][0]
    if "peak GB" in peer:
        ratios[f"{label}, the build alone: peak memory / RenderPark's (goal <= 1)"] = got["peak GB"] / peer["peak GB"]


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    from illusio.passes.mitsuba import mitsuba_available
    from illusio.radiosity import HierarchyParams, RadiosityParams, RadiosityRenderer
    from illusio.radiosity.mitsuba import render_mitsuba, score
    from illusio.scene.mgf import load_mgf

    size, samples = ((48, 36), 64) if quick else ((96, 72), 1024)
    timings, ratios = [], {}
    cases = [(name, name, RadiosityParams()) for name in (QUICK_SCENES if quick else SCENES)]
    if not quick:
        cases.append(("graz at RenderPark's elements", "graz", RadiosityParams(hierarchy=HierarchyParams(**MATCHED))))
    references = {}  # per scene: Mitsuba's two renders, the same polygons whatever the refinement
    for label, name, params in cases:
        path = MGF / f"{name}.mgf"
        if not path.is_file():
            continue
        if params.hierarchy != HierarchyParams():
            build_alone(path, label, ratios, MATCHED, RENDERPARK_GRAZ)
            build_alone(path, "graz at RenderPark's full element count", ratios, FULL, RENDERPARK_GRAZ)
        elif name == "office2" and not quick:
            build_alone(path, label, ratios, {}, RENDERPARK_OFFICE2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the files' unused entities and rd 1, said by the reader
            scene = load_mgf(path)
        view = scene.camera("main")
        renderer = RadiosityRenderer(ctx)
        try:
            renderer.prepare(scene)
            start = time.perf_counter()
            image, emitter = renderer.radiance(Frame(view, size), params, 2)
            seconds = time.perf_counter() - start
            solution, polygons = renderer.result(), renderer.polygons
        finally:
            renderer.release()
        stats = solution.stats
        notes = (
            f"{len(polygons):,} polygons (twins included), {stats.elements:,} elements, {stats.links:,} links, "
            f"{stats.iterations} iterations"
        )
        what = (
            "at the defaults"
            if label == name
            else f"(ε {MATCHED['epsilon']:g}, minimum area {MATCHED['min_area']:g} m²)"
        )
        timings.append(
            Timing(f"{label}: build and draw {what}", 1, seconds * 1000, seconds * 1000, seconds * 1000, notes)
        )
        ratios[f"{label}: elements"] = float(stats.elements)
        ratios[f"{label}: links"] = float(stats.links)
        element_bytes, cluster_bytes = link_bytes(solution)
        ratios[f"{label}: bytes per element link"] = element_bytes
        ratios[f"{label}: bytes per cluster link"] = cluster_bytes
        ratios[f"{label}: link store MB"] = (
            len(solution.links) * element_bytes + len(solution.cluster_links) * cluster_bytes
        ) / 1e6
        ratios[f"{label}: build microseconds per link"] = seconds * 1e6 / max(stats.links, 1)
        ratios[f"{label}: peak resident memory GB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
        del solution
        if mitsuba_available():
            if name not in references:
                references[name] = [render_mitsuba(polygons, view, size, samples, seed=1)]
                if not quick:
                    references[name].append(render_mitsuba(polygons, view, size, samples, seed=2))
            reference = references[name][0]
            lit = ~emitter
            ratios[f"{label}: error against Mitsuba, 4×4 blocks"] = score(
                image, reference, lit, block=4
            ).mean_relative_error
            ratios[f"{label}: mean radiance / Mitsuba's"] = float(image[lit].mean() / reference[lit].mean())
            if len(references[name]) > 1:
                ratios[f"{label}: the reference's own noise, 4×4 blocks"] = (
                    score(references[name][1], reference, lit, block=4).mean_relative_error / 2**0.5
                )
    return timings, ratios
