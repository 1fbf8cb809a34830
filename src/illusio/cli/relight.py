"""illusio relight: relight the built-in real scene (a photograph of the office) — first landing:
the baseline method of Loscos 4.2 (estimates from the photograph, display by eq. 4.3)."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.errors import InputError
from ..core.images import check_output_path, write_image
from ..radiosity.params import HierarchyParams
from ..relight.params import METHODS, RelightParams
from .common import parse_size
from .radiosity import parse_lamps

_P = RelightParams()


def relight(
    scene: str = typer.Argument("office", help="the built-in real scene (its photograph is path-traced: the photo extra)"),
    output: Path = typer.Option(..., "-o", "--output", help="the relit image (.png sRGB, .npy/.exr linear)"),
    set_lamp: list[str] = typer.Option(None, "--set", help="NAME=SCALE: a real lamp's estimated exitance × SCALE (repeatable)"),
    method: str = typer.Option(_P.method, "--method", help=f"one of {', '.join(METHODS)}"),
    size: str = typer.Option("320x240", "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(64, "--samples", help="paths per pixel of the photograph"),
    epsilon: float = typer.Option(HierarchyParams().epsilon, "--epsilon", help="radiosity refinement ε"),
    mean_reflectance: float = typer.Option(_P.mean_reflectance, "--mean-reflectance", help="ρ̂, the first guess of eq. (4.1)"),
    photograph: Path = typer.Option(None, "--photograph", help="also write the photograph used"),
) -> None:
    """Relight SCENE from one photograph (Loscos 1999, ch. 4): reflectances and lamp powers estimated
    from the photograph, then the lamps changed (--set)."""
    from ..relight import RelightSession, builtin_real_scene

    out = check_output_path(output)
    photo_out = check_output_path(photograph, [str(out)]) if photograph is not None else None
    if not 1 <= samples <= 1 << 16:
        raise InputError(f"--samples must be in 1..65536, got {samples}")
    params = RelightParams(method=method, mean_reflectance=mean_reflectance, hierarchy=HierarchyParams(epsilon=epsilon))
    scales = dict(parse_lamps(set_lamp))
    real = builtin_real_scene(scene, parse_size(size), samples)
    session = RelightSession(real, params)
    unknown = sorted(set(scales) - set(session.lamp_names))
    if unknown:
        raise InputError(f"no lamp named {unknown[0]!r}; lamps: {', '.join(session.lamp_names)}")
    image = session.image(scales)
    write_image(out, image)
    if photo_out is not None:
        write_image(photo_out, real.photograph)
    typer.echo(f"wrote {out}: prepared in {session.times['prepare']:.1f} s, the edit in {session.times['edit']:.2f} s")
