"""illusio render: one image of a scene, a YAML scene, a mesh or a shape."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.errors import InputError
from ..core.images import check_output_path, write_image
from ..core.renderer import DEFAULT_SIZE
from ..passes.scene_renderer import RenderSettings

_DEFAULT = RenderSettings()
from .common import parse_size, resolve_scene, scene_inputs


def render(
    scene: str = typer.Argument(..., help="built-in scene (cornell-box, living-room, office, museum, turntable), a .yaml scene, a mesh file or a built-in shape"),
    output: Path = typer.Option(..., "-o", "--output", help="image to write: .png (8-bit sRGB; 16-bit with --bit-depth 16), .jpg, .npy or .exr (linear float)"),
    camera: str = typer.Option(None, "--camera", help="named camera of the scene (default: main)"),
    size: str = typer.Option("x".join(map(str, DEFAULT_SIZE)), "--size", help="WIDTHxHEIGHT in pixels"),
    shadows: bool = typer.Option(_DEFAULT.shadows, "--shadows/--no-shadows", help="cube shadow maps"),
    exposure: float = typer.Option(_DEFAULT.exposure, "--exposure", help="scale on linear radiance before writing"),
    bit_depth: int = typer.Option(8, "--bit-depth", help="8 or 16 for PNG"),
) -> None:
    """Render SCENE to an image."""
    from ..core.context import default_context
    from ..passes.scene_renderer import render_scene

    out = check_output_path(output, scene_inputs(scene))
    w, h = parse_size(size)
    if not exposure > 0:
        raise InputError(f"--exposure must be positive, got {exposure}")
    sc = resolve_scene(scene)
    view = sc.camera(camera)
    img = render_scene(sc, view, (w, h), default_context(), RenderSettings(shadows=shadows, exposure=exposure))
    write_image(out, img, bit_depth=bit_depth)
    typer.echo(f"wrote {out} ({w}×{h})")
