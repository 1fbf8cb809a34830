"""``illusio lines`` and ``illusio curvature``: line drawings of a mesh and its curvature."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import typer

from ..core.errors import InputError, did_you_mean
from ..core.images import check_output_path, read_image, write_image
from ..lines.params import CurvatureParams, LineParams
from ..lines.style import LineStyle
from .common import parse_size, resolve_mesh
from .params_options import params_options


def _floats(text: str, count: tuple[int, ...], name: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError(f"{name} must be comma-separated numbers, got {text!r}") from None
    if len(values) not in count or not np.isfinite(values).all():
        raise InputError(f"{name} takes {' or '.join(map(str, count))} finite numbers, got {text!r}")
    return values


@params_options(params=LineParams, style=LineStyle)
def lines(
    mesh: str = typer.Argument(..., help="mesh file (.obj .ply .off .stl .gltf .glb) or built-in shape"),
    output: Path = typer.Option(
        ..., "-o", "--output", help="drawing to write: .png, or .svg (a layer of paths per line type)"
    ),
    view: str = typer.Option("30,15", "--view", help="AZIMUTH,ELEVATION in degrees around the mesh"),
    camera: str = typer.Option(
        None, "--camera", help="EYE_X,EYE_Y,EYE_Z[,TARGET_X,TARGET_Y,TARGET_Z] instead of --view"
    ),
    size: str = typer.Option("1024x1024", "--size", help="WIDTHxHEIGHT"),
    grid: bool = typer.Option(False, "--grid/--no-grid", help="write the τ × λ grid of hybrid apparent ridges instead"),
    compare: str = typer.Option(
        None,
        "--compare",
        help=(
            "sobel, laplace, canny (of the shaded mesh), photo (Canny of a path-traced photograph, scored "
            "with registration; needs mitsuba) or an edge IMAGE: print scores, write OUT-compare.png"
        ),
    ),
    auto: bool = typer.Option(
        False,
        "--auto/--no-auto",
        help="choose τ, λ and --threshold that best match the edges of --compare (default: canny of the shaded mesh)",
    ),
    debug: str = typer.Option(None, "--debug", help="write a debug view instead: q1, t1 or curvature"),
    colour: str = typer.Option(
        None, "--colour", help="one ink for every line: #rrggbb or R,G,B in [0, 1] (default: each type's)"
    ),
    antialias: int = typer.Option(2, "--antialias", help="draw at N× the size and reduce (1: no antialiasing)"),
    *,
    params: LineParams,
    style: LineStyle,
) -> None:
    """Draw MESH with apparent ridges and the classic line types."""
    from ..core.context import default_context
    from ..core.renderer import Frame
    from ..lines import compare as cmp
    from ..lines.debug import DEBUG_VIEWS, debug_view
    from ..lines.drawing import LineRenderer, framing_view
    from ..lines.svg import write_drawing_svg
    from ..scene.camera import Pose, View
    from ..scene.scene import Node, Scene

    targets = cmp.EDGE_METHODS + ("photo",)
    inputs = [mesh] + ([compare] if compare and compare not in targets else [])
    out = check_output_path(output, [i for i in inputs if Path(i).exists()])
    if out.suffix.lower() not in (".png", ".svg"):
        raise InputError(f"{out.name}: the drawing must be a .png or an .svg")
    if debug is not None and debug not in DEBUG_VIEWS:
        raise InputError(f"--debug must be one of {', '.join(DEBUG_VIEWS)}{did_you_mean(debug, DEBUG_VIEWS)}")
    if compare and compare not in targets and not Path(compare).is_file():
        # checked before anything is drawn: a mistyped method must not leave a drawing behind
        raise InputError(
            f"--compare {compare}: not an edge method or photo ({', '.join(targets)}) nor an image file"
            f"{did_you_mean(compare, targets)}"
        )
    if compare == "photo":
        from ..passes.mitsuba import load_mitsuba

        load_mitsuba()  # the install hint before anything is drawn
    from ..lines.style import parse_colour, ridge_strength, stylise

    if not 1 <= antialias <= 4:
        raise InputError(f"--antialias takes 1..4, got {antialias}")
    style = replace(style, colour=parse_colour(colour) if colour else None, supersample=antialias)
    fade = style.fade
    w, h = parse_size(size)
    parse_size(f"{w * antialias}x{h * antialias}")  # the supersampled drawing must fit too
    m = resolve_mesh(mesh)
    if camera:
        c = _floats(camera, (3, 6), "--camera")
        lo, hi = m.bounds
        target = tuple(c[3:]) if len(c) == 6 else tuple((np.asarray(lo, float) + hi) / 2)
        base = framing_view(m)
        v = View(
            Pose(tuple(c[:3]), target), replace(base.camera, near=1e-3 * base.camera.near, far=base.camera.far * 10)
        )
        Scene(m.name, nodes=[Node(m.name, m)]).check_in_view(v, (w, h))
    else:
        az_el = _floats(view, (2,), "--view")
        v = framing_view(m, az_el[0], az_el[1])
    renderer = default_context().kept(LineRenderer)
    renderer.prepare(m)

    made: dict = {}

    def target_edges():
        if "target" not in made:  # once: --auto and --compare share it
            made["target"] = edges_of_target()
        return made["target"]

    def edges_of_target():
        if not compare or compare in cmp.EDGE_METHODS:
            from ..lines.tuning import edge_target

            return edge_target(renderer, m, v, (w, h), compare or "canny")
        if compare == "photo":
            from ..lines.photograph import exposed, photograph

            photo = exposed(photograph(m, v, (w, h)))
            shot = out.with_name(out.stem + "-photo.png")
            write_image(shot, photo)
            typer.echo(f"wrote {shot} (the path-traced photograph)")
            return cmp.image_edges(photo, "canny")
        edges = read_image(compare, srgb=False)
        if edges.shape[:2] != (h, w):
            raise InputError(f"{compare}: edge image is {edges.shape[1]}×{edges.shape[0]}, the drawing {w}×{h}")
        return cmp.line_mask(edges)

    if auto:
        from ..lines.tuning import auto_parameters

        chosen = auto_parameters(renderer, v, (w, h), target_edges(), params)
        params = chosen.params
        typer.echo(f"auto against {compare or 'canny'}: {chosen}")
    if grid:
        from ..lines.tuning import parameter_grid

        tile = (max(64, w // 4), max(64, h // 4))
        write_image(out, parameter_grid(renderer, v, tile, params=params))
        typer.echo(f"wrote {out} (τ × λ grid, tiles {tile[0]}×{tile[1]})")
        return
    # the drawing at the output size: what --debug and --compare read (a PNG or SVG page alone is
    # drawn at antialias × the size only)
    needed = debug or compare or antialias == 1
    drawing = renderer.drawing(Frame(v, (w, h)), params) if needed else None
    if debug:
        write_image(out, debug_view(debug, drawing, m, renderer.curvature(params.curvature)))
        typer.echo(f"wrote {out} ({debug} view)")
        return
    # the page: drawn again at antialias × the size (a PNG's lines then widened and reduced; an SVG's
    # traced there and scaled to the size, so both hold the same lines)
    page = renderer.drawing(Frame(v, (w * antialias, h * antialias)), params) if antialias > 1 else drawing
    if out.suffix.lower() == ".svg":
        count = write_drawing_svg(out, page, params, style)
        typer.echo(f"wrote {out} ({count} paths)")
    else:
        strength = ridge_strength(page.q_t1, page.ridge_mask) if fade else None
        write_image(out, stylise(page.image, style, strength))
        typer.echo(f"wrote {out} ({w}×{h})")
    if compare:
        ours = cmp.line_mask(drawing.image)
        target = target_edges()
        typer.echo(f"against {compare}: {cmp.score(ours, target)}")
        if compare == "photo":  # a photograph's edges sit off the lines by a few pixels
            registered, (dx, dy) = cmp.registered_score(ours, target)
            typer.echo(f"registered (shifted {dx:+d}, {dy:+d} px): {registered}")
            ours = cmp.shift_mask(ours, dx, dy)
        side = out.with_name(out.stem + "-compare.png")
        write_image(side, cmp.overlay(ours, target))
        typer.echo(f"wrote {side} (red: ours only, blue: {compare} only, black: both)")


@params_options(settings=CurvatureParams)
def curvature(
    mesh: str = typer.Argument(..., help="mesh file or built-in shape"),
    output: Path = typer.Option(
        ...,
        "-o",
        "--output",
        help="arrays to write (.npz): k_min, k_max, e_min, e_max, normals, dcurv, "
        "valid, and vertices, faces, source_index (each row's vertex in the file)",
    ),
    no_cache: bool = typer.Option(False, "--no-cache", help="recompute even if a cached result exists"),
    *,
    settings: CurvatureParams,
) -> None:
    """Estimate per-vertex principal curvatures and directions of MESH."""
    from ..lines.curvature import estimate_curvature

    out = check_output_path(output, [mesh] if Path(mesh).exists() else [])
    if out.suffix.lower() != ".npz":
        raise InputError(f"{out.name}: curvature is written as .npz")
    m = resolve_mesh(mesh)
    c = estimate_curvature(
        m,
        settings.rings,
        settings.degree,
        cache=not no_cache,
        adaptive=settings.adaptive,
        extra_rings=settings.extra_rings,
        confidence=settings.confidence,
        smoothing=settings.smoothing,
    )
    source = m.source_index if m.source_index is not None else np.arange(len(m.vertices))
    c.save(out, vertices=m.vertices, faces=m.faces, source_index=source)
    typer.echo(
        f"wrote {out} ({len(c.k_min)} vertices, {int((~c.valid).sum())} without a fit; "
        f"curvature scale {c.scale():.4g} per unit)"
    )
