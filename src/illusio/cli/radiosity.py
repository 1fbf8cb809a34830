"""illusio radiosity: a hierarchical radiosity solution of a scene, its element mesh or links, and
the Mitsuba ground truth of the same polygons for comparison."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import typer

from ..core.errors import InputError
from ..core.images import check_output_path, write_image
from ..radiosity.params import RadiosityParams
from .common import SCENE_HELP, on_turntable_option, parse_size, resolve_scene, scene_inputs
from .params_options import params_options


def parse_lamps(values: list[str], flag: str = "--set-lamp") -> tuple:
    """['lamp-0=0.5', ...] -> (('lamp-0', 0.5), ...); a scale must be finite and ≥ 0."""
    out = []
    for text in values or ():
        name, sep, value = text.partition("=")
        try:
            scale = float(value)
        except ValueError:
            scale = -1.0
        if not sep or not name or not 0 <= scale < float("inf"):
            raise InputError(f"{flag} takes NAME=SCALE with a finite SCALE ≥ 0, got {text!r}")
        out.append((name, scale))
    return tuple(out)


@params_options(params=RadiosityParams)
def radiosity(
    on_turntable: bool = on_turntable_option(),
    scene: str = typer.Argument(..., help=SCENE_HELP),
    output: Path = typer.Option(..., "-o", "--output", help="image to write (.png sRGB, .npy/.exr linear)"),
    set_lamp: list[str] = typer.Option(None, "--set-lamp", help="NAME=SCALE, the lamp's exitance × SCALE (repeatable)"),
    size: str = typer.Option("640x480", "--size", help="WIDTHxHEIGHT of both images"),
    camera: str = typer.Option(None, "--camera", help="named camera of the scene (default: main)"),
    reference: Path = typer.Option(
        None, "--reference", help="also path-trace the same polygons with Mitsuba to this image"
    ),
    spp: int = typer.Option(256, "--spp", help="--reference: paths per pixel"),
    supersample: int = typer.Option(
        0, "--supersample", help="samples per pixel side of the radiosity image (0: 4 with --reference, else 1)"
    ),
    stats: bool = typer.Option(
        False, "--stats/--no-stats", help="print elements, links, rays and the time of each phase"
    ),
    *,
    params: RadiosityParams,
) -> None:
    """Solve SCENE by hierarchical radiosity (Hanrahan et al. 1991, as in Loscos 1999, ch. 4) and
    draw it; with --reference, score it against a Mitsuba 3 path tracing of the same polygons."""
    import numpy as np

    from ..core.context import default_context
    from ..core.renderer import Frame
    from ..radiosity.renderer import RadiosityRenderer

    out = check_output_path(output, scene_inputs(scene))
    ref_out = check_output_path(reference, scene_inputs(scene) + [str(out)]) if reference is not None else None
    if not 1 <= spp <= 1 << 20:
        raise InputError(f"--spp must be in 1..{1 << 20}, got {spp}")
    if not 0 <= supersample <= 8:
        raise InputError(f"--supersample must be in 0..8, got {supersample}")
    k = supersample or (4 if reference is not None else 1)
    w, h = parse_size(size)
    parse_size(f"{w * k}x{h * k}")
    params = replace(params, lamp_scales=parse_lamps(set_lamp))
    seed, exposure, element = params.hierarchy.seed, params.exposure, params.element
    sc = resolve_scene(scene, on_turntable)
    view = sc.camera(camera)
    sc.check_in_view(view, (w, h))
    renderer = default_context().kept(RadiosityRenderer)
    renderer.prepare(sc)
    solution = renderer.solve(params)
    if element >= len(solution.hierarchy):
        raise InputError(f"--element {element}: the solution has {len(solution.hierarchy)} elements")
    image, emitter = renderer.radiance(Frame(view, (w, h)), params, k)
    ref = None
    if ref_out is not None:
        from ..radiosity.mitsuba import render_mitsuba, score

        scaled = renderer.polygons
        scales = dict(params.lamp_scales)
        if scales:
            import dataclasses

            factor = np.array([scales.get(n, 1.0) for n in scaled.names])[scaled.group]
            scaled = dataclasses.replace(scaled, exitance=scaled.exitance * factor[:, None])
        ref = render_mitsuba(scaled, view, (w, h), spp, seed) * exposure
    write_image(out, image)
    typer.echo(f"wrote {out} ({w}×{h})")
    if ref is not None:
        write_image(ref_out, ref)
        # Mitsuba draws the polygons at their mean reflectance: scored against the same, untextured
        flat = (
            renderer.radiance(Frame(view, (w, h)), replace(params, textures=False), k)[0] if params.textures else image
        )
        s = score(flat, ref, ~emitter)
        typer.echo(
            f"wrote {ref_out}: mean relative error {100 * s.mean_relative_error:.1f} % over {s.pixels} "
            f"non-emitter pixels, PSNR {s.psnr:.1f} dB"
        )
    if stats:
        for line in solution.stats.lines():
            typer.echo(line)
