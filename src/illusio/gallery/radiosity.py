"""The radiosity showcase: the Cornell box and the office solved by hierarchical radiosity, each as
the solution, its element mesh and Mitsuba's path tracing of the same polygons (when the photo
extra is installed), scored; and the office relit with two lamps off, re-solved with the links kept."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..core.renderer import Frame
from ..passes.denoise import denoiser_available
from ..passes.mitsuba import mitsuba_available
from ..radiosity import RadiosityParams, RadiosityRenderer
from ..scene.builtin import builtin_scene
from .html import Item, Section, Table
from .traced import DEMO_SAMPLES, path_traced

__all__ = ["radiosity_showcase"]


def radiosity_showcase(ctx: Context, out_dir: Path, size: tuple[int, int], spp: int = DEMO_SAMPLES) -> Section:
    section = Section(
        "Hierarchical radiosity (Hanrahan et al. 1991; Loscos 1999, ch. 4)",
        "Quadtrees over the scene's polygons, links with form factors and ray-cast visibility, BFV "
        "refinement, gather and push-pull; left the solution (each pixel's light gathered at its own "
        "point from it: the final gather), middle the element mesh, right Mitsuba 3 path tracing the "
        "same polygons.",
    )
    renderer = RadiosityRenderer(ctx)
    table = Table(
        f"Each solution: its size and build time on {ctx.info()['renderer']}, and against Mitsuba at {spp} paths "
        "a pixel" + (", denoised" if denoiser_available() else " (its own noise included)"),
        ["scene", "elements", "links", "build + solve", "mean relative error", "PSNR"],
        [],
    )
    section.tables.append(table)
    for name, shape in (("cornell-box", (size[1] // 2, size[1] // 2)), ("office", (size[0] // 2, size[1] // 2))):
        scene = builtin_scene(name)
        renderer.prepare(scene)
        view = scene.camera("main")
        t0 = time.perf_counter()
        solution = renderer.solve(RadiosityParams())
        build = time.perf_counter() - t0
        flat = RadiosityParams(textures=False)  # as Mitsuba of the polygons sees the surfaces: their means
        image, emitter = renderer.radiance(Frame(view, shape), flat, 2)
        mesh = renderer.render(Frame(view, shape), RadiosityParams(show="mesh"))
        panels = [np.clip(image, 0, 1), mesh]
        note = "sizes, times and scores in the table above"
        row = [name, f"{solution.stats.elements:,}", f"{solution.stats.links:,}", f"{build:.1f} s", "—", "—"]
        table.rows.append(row)
        if mitsuba_available():
            from ..radiosity.mitsuba import score

            reference = path_traced(renderer.polygons, view, shape, spp)
            s = score(image, reference, ~emitter)
            panels.append(np.clip(reference, 0, 1))
            row[4:] = [f"{100 * s.mean_relative_error:.1f} %", f"{s.psnr:.1f} dB"]
        else:
            note += "; Mitsuba not installed (pip install 'illusio[photo]'), no reference"
        rel = f"radiosity/{name}.png"
        write_image(out_dir / rel, np.concatenate(panels, axis=1))
        section.items.append(
            Item(
                rel,
                f"{name}: radiosity, element mesh, path tracing",
                note,
                figure="Hanrahan et al. 1991; Loscos 1999, Figure 4.6",
                command=f"illusio radiosity {name} -o {name}.png --reference {name}-mitsuba.png --spp {spp} --stats",
                params=flat,
            )
        )
        if name == "office":
            off = RadiosityParams(lamp_scales=(("lamp-0", 0.0), ("lamp-2", 0.0), ("lamp-3", 2.0)))
            t0 = time.perf_counter()
            relit = renderer.render(Frame(view, shape), off)
            ms = (time.perf_counter() - t0) * 1000
            rel = "radiosity/office-relit.png"
            write_image(out_dir / rel, np.concatenate([np.clip(image, 0, 1), relit], axis=1))
            section.items.append(
                Item(
                    rel,
                    "the office relit: lamps 0 and 2 off, lamp 3 doubled",
                    f"re-solved with the links kept and drawn in {ms:.0f} ms "
                    f"({renderer.result().result.iterations} iterations of gather + push-pull)",
                    figure="Loscos 1999, section 4.4.2",
                    command=(
                        "illusio radiosity office -o relit.png --set-lamp lamp-0=0 --set-lamp lamp-2=0 "
                        "--set-lamp lamp-3=2"
                    ),
                    params=off,
                    derived=("lamp_scales",),  # the --set-lamp options
                )
            )
    renderer.release()
    return section
