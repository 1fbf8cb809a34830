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

One build per scene (a build is seconds to a minute; ``--repeat`` is not used). The scenes are read
from ../shared/data/scenes/mgf (ILLUSIO_MGF), never copied; missing scenes are skipped. ``--quick``:
the cube and office2 at 48×36 and 64 paths a pixel."""

from __future__ import annotations

import resource
import time
import warnings

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame

from .radiosity import MGF
from .runner import Timing

SCENES = ("cube", "office2", "office3", "graz")
QUICK_SCENES = ("cube", "office2")


def link_bytes(solution) -> tuple[float, float]:
    """Bytes a link takes in the store: the item sizes of the element links' arrays (receiver, source,
    form factor, visibility, tag, rays) and of the cluster links' (receiver, source, the two kernels,
    visibility)."""
    links, cluster = solution.links, solution.cluster_links
    element = sum(
        getattr(links, n).itemsize for n in ("receiver", "source", "form_factor", "visibility", "tag", "rays")
    )
    per_cluster = sum(a.itemsize * int(np.prod(a.shape[1:])) for a in (getattr(cluster, n) for n in cluster._FIELDS))
    return float(element), float(per_cluster)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    from illusio.passes.mitsuba import mitsuba_available
    from illusio.radiosity import RadiosityParams, RadiosityRenderer
    from illusio.radiosity.mitsuba import render_mitsuba, score
    from illusio.scene.mgf import load_mgf

    size, samples = ((48, 36), 64) if quick else ((96, 72), 1024)
    timings, ratios = [], {}
    for name in QUICK_SCENES if quick else SCENES:
        path = MGF / f"{name}.mgf"
        if not path.is_file():
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the files' unused entities and rd 1, said by the reader
            scene = load_mgf(path)
        view = scene.camera("main")
        renderer = RadiosityRenderer(ctx)
        try:
            renderer.prepare(scene)
            start = time.perf_counter()
            image, emitter = renderer.radiance(Frame(view, size), RadiosityParams(), 2)
            seconds = time.perf_counter() - start
            solution, polygons = renderer.result(), renderer.polygons
        finally:
            renderer.release()
        stats = solution.stats
        notes = (
            f"{len(polygons):,} polygons (twins included), {stats.elements:,} elements, {stats.links:,} links, "
            f"{stats.iterations} iterations"
        )
        timings.append(
            Timing(f"{name}: build and draw at the defaults", 1, seconds * 1000, seconds * 1000, seconds * 1000, notes)
        )
        ratios[f"{name}: elements"] = float(stats.elements)
        ratios[f"{name}: links"] = float(stats.links)
        element_bytes, cluster_bytes = link_bytes(solution)
        ratios[f"{name}: bytes per element link"] = element_bytes
        ratios[f"{name}: bytes per cluster link"] = cluster_bytes
        ratios[f"{name}: link store MB"] = (
            len(solution.links) * element_bytes + len(solution.cluster_links) * cluster_bytes
        ) / 1e6
        ratios[f"{name}: build microseconds per link"] = seconds * 1e6 / max(stats.links, 1)
        ratios[f"{name}: peak resident memory GB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
        if mitsuba_available():
            reference = render_mitsuba(polygons, view, size, samples, seed=1)
            lit = ~emitter
            ratios[f"{name}: error against Mitsuba, 4×4 blocks"] = score(
                image, reference, lit, block=4
            ).mean_relative_error
            ratios[f"{name}: mean radiance / Mitsuba's"] = float(image[lit].mean() / reference[lit].mean())
            if not quick:
                other = render_mitsuba(polygons, view, size, samples, seed=2)
                ratios[f"{name}: the reference's own noise, 4×4 blocks"] = (
                    score(other, reference, lit, block=4).mean_relative_error / 2**0.5
                )
    return timings, ratios
