"""illusio relight: relight the built-in real scene (a photograph of the office) by Loscos' chapter 4
(estimates from the photograph, then baseline, loscos or per-pixel display of the edits)."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.errors import InputError, did_you_mean
from ..core.images import check_output_path, write_image
from ..relight.params import SHOW, VIRTUAL_LAMP_SIZE, RelightParams
from .common import parse_size
from .params_options import params_options
from .radiosity import parse_lamps



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


def _real_scene(scene: str, size: str, samples: int):
    """A folder (scene.yaml, photograph, camera.json) or a built-in scene photographed by Mitsuba."""
    from ..relight import builtin_real_scene, load_real_scene

    if Path(scene).is_dir():
        return load_real_scene(scene)
    if not 1 <= samples <= 1 << 16:
        raise InputError(f"--samples must be in 1..65536, got {samples}")
    return builtin_real_scene(scene, parse_size(size), samples)


@params_options(params=RelightParams)
def relight_prepare(
    scene: str = typer.Argument("office", help="a folder (scene.yaml, photograph, camera.json) or the built-in real "
                                               "scene (its photograph is path-traced: the photo extra)"),
    output: Path = typer.Option(..., "-o", "--output", help="the prepared session (.npz)"),
    size: str = typer.Option("320x240", "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(64, "--samples", help="paths per pixel of the photograph"),
    *,
    params: RelightParams,
) -> None:
    """Prepare SCENE once (estimates, refinement, textures, the lamps' basis) and save it, so that
    `illusio relight FILE.npz --set ...` starts at once."""
    from ..relight import RelightSession

    out = check_output_path(output, [str(p) for p in Path(scene).iterdir()] if Path(scene).is_dir() else [])
    if out.suffix.lower() != ".npz":
        raise InputError(f"-o: a prepared session is saved as .npz, got {out.name}")
    session = RelightSession(_real_scene(scene, size, samples), params)
    session.save(out)
    typer.echo(f"wrote {out}: {session.solution.stats.leaves} leaves, prepared in {session.times['prepare']:.1f} s")


@params_options(params=RelightParams)
def relight(
    scene: str = typer.Argument("office", help="a folder (scene.yaml, photograph, camera.json; see "
                                               "relight.load_real_scene), the built-in real scene (its photograph is "
                                               "path-traced: the photo extra), or a session saved by `illusio relight "
                                               "prepare` (.npz)"),
    output: Path = typer.Option(..., "-o", "--output", help="the relit image (.png sRGB, .npy/.exr linear)"),
    set_lamp: list[str] = typer.Option(None, "--set", help="NAME=SCALE: a real lamp's estimated exitance × SCALE (repeatable)"),
    size: str = typer.Option("320x240", "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(64, "--samples", help="paths per pixel of the photograph"),
    add_lamp: list[str] = typer.Option(None, "--add-lamp", help=f"X,Y,Z:EXITANCE — a virtual {VIRTUAL_LAMP_SIZE * 100:g} cm lamp facing down at X,Y,Z (m), W/m² (repeatable)"),
    add_object: list[str] = typer.Option(None, "--add-object", help="MESH@X,Y,Z — a virtual object (mesh file or built-in shape) standing at X,Y,Z (repeatable)"),
    photograph: Path = typer.Option(None, "--photograph", help="also write the photograph used"),
    show: str = typer.Option("image", "--show", help="image, textures (what the method displays), mesh (leaf outlines) or display-factor"),
    *,
    params: RelightParams,
) -> None:
    """Relight SCENE from one photograph (Loscos 1999, ch. 4): reflectances and lamp powers estimated
    from the photograph, then the lamps changed (--set). `illusio relight prepare SCENE -o S.npz`
    saves the preparation; `illusio relight S.npz ...` starts from it (its own method and size)."""
    from ..relight import RelightSession

    saved = scene.lower().endswith(".npz")
    out = check_output_path(output, [scene] if saved else [])
    if Path(scene).is_dir():
        out = check_output_path(output, [str(p) for p in Path(scene).iterdir()])
    photo_out = check_output_path(photograph, [str(out)]) if photograph is not None else None
    if not 1 <= samples <= 1 << 16:
        raise InputError(f"--samples must be in 1..65536, got {samples}")
    if show not in SHOW:
        raise InputError(f"--show must be one of {', '.join(SHOW)}, got {show!r}{did_you_mean(show, SHOW)}")
    scales = dict(parse_lamps(set_lamp, "--set"))
    lamps = [_parse_lamp(t) for t in add_lamp or ()]           # every option checked before the photograph
    objects = [_parse_object(t) for t in add_object or ()]
    if saved:
        session = RelightSession.load(scene)
    else:
        session = RelightSession(_real_scene(scene, size, samples), params)
    real = session.real
    unknown = sorted(set(scales) - set(session.lamp_names))
    if unknown:
        raise InputError(f"no lamp named {unknown[0]!r}{did_you_mean(unknown[0], session.lamp_names)}; "
                         f"lamps: {', '.join(session.lamp_names)}")
    for k, (centre, power) in enumerate(lamps):
        session.add_lamp(centre, VIRTUAL_LAMP_SIZE, (power, power, power), f"virtual-lamp-{k}")
    for k, (mesh, at) in enumerate(objects):
        session.add_object(mesh, f"virtual-object-{k}", at)
    image = session.image(scales)
    if show != "image":
        image = session.show(show)
    write_image(out, image)
    if photo_out is not None:
        write_image(photo_out, real.photograph)
    start = f"loaded in {session.times['load']:.2f} s" if saved else f"prepared in {session.times['prepare']:.1f} s"
    typer.echo(f"wrote {out}: {start}, the edit in {session.times['edit']:.2f} s")
