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


def _numbers(text: str, count: int, what: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != count:
        raise InputError(f"{what}: expected {count} numbers separated by commas, got {text!r}")
    return values


def _parse_lamp(text: str):
    where, sep, power = text.partition(":")
    if not sep:
        raise InputError(f"--add-lamp takes X,Y,Z:EXITANCE, got {text!r}")
    (value,) = _numbers(power, 1, "--add-lamp exitance")
    if not value > 0:
        raise InputError(f"--add-lamp exitance must be positive, got {value}")
    return _numbers(where, 3, "--add-lamp position"), value


def _parse_object(text: str):
    from .common import resolve_mesh

    source, sep, where = text.rpartition("@")
    if not sep or not source:
        raise InputError(f"--add-object takes MESH@X,Y,Z, got {text!r}")
    mesh = resolve_mesh(source)
    at = _numbers(where, 3, "--add-object position")
    lo, _ = mesh.bounds
    # stand it on the point given: its lowest point at Y
    return mesh, (at[0], at[1] - float(lo[1]), at[2])


def relight(
    scene: str = typer.Argument("office", help="the built-in real scene (its photograph is path-traced: the photo extra)"),
    output: Path = typer.Option(..., "-o", "--output", help="the relit image (.png sRGB, .npy/.exr linear)"),
    set_lamp: list[str] = typer.Option(None, "--set", help="NAME=SCALE: a real lamp's estimated exitance × SCALE (repeatable)"),
    method: str = typer.Option(_P.method, "--method", help=f"one of {', '.join(METHODS)}"),
    size: str = typer.Option("320x240", "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(64, "--samples", help="paths per pixel of the photograph"),
    epsilon: float = typer.Option(HierarchyParams().epsilon, "--epsilon", help="radiosity refinement ε"),
    mean_reflectance: float = typer.Option(_P.mean_reflectance, "--mean-reflectance", help="ρ̂, the first guess of eq. (4.1)"),
    add_lamp: list[str] = typer.Option(None, "--add-lamp", help="X,Y,Z:EXITANCE — a virtual 40 cm lamp facing down at X,Y,Z (m), W/m² (repeatable)"),
    add_object: list[str] = typer.Option(None, "--add-object", help="MESH@X,Y,Z — a virtual object (mesh file or built-in shape) standing at X,Y,Z (repeatable)"),
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
    lamps = [_parse_lamp(t) for t in add_lamp or ()]           # every option checked before the photograph
    objects = [_parse_object(t) for t in add_object or ()]
    real = builtin_real_scene(scene, parse_size(size), samples)
    session = RelightSession(real, params)
    unknown = sorted(set(scales) - set(session.lamp_names))
    if unknown:
        raise InputError(f"no lamp named {unknown[0]!r}; lamps: {', '.join(session.lamp_names)}")
    for k, (centre, power) in enumerate(lamps):
        session.add_lamp(centre, 0.4, (power, power, power), f"virtual-lamp-{k}")
    for k, (mesh, at) in enumerate(objects):
        session.add_object(mesh, f"virtual-object-{k}", at)
    image = session.image(scales)
    write_image(out, image)
    if photo_out is not None:
        write_image(photo_out, real.photograph)
    typer.echo(f"wrote {out}: prepared in {session.times['prepare']:.1f} s, the edit in {session.times['edit']:.2f} s")
