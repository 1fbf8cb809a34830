"""illusio relight: relight the built-in real scene (a photograph of the office) by Loscos' chapter 4
(estimates from the photograph, then baseline, loscos or per-pixel display of the edits)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer

from ..core.errors import InputError, did_you_mean
from ..core.images import check_output_path, write_image
from ..relight.params import DEFAULT_PATHS, DEFAULT_SIZE, SHOW, VIRTUAL_LAMP_SIZE, RelightParams
from .common import parse_size
from .params_options import params_options
from .radiosity import parse_lamps

#: --size's default, as the option shows it
DEFAULT_SIZE_TEXT = f"{DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]}"


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


RESPONSE_HELP = (
    "how a folder's photograph becomes linear: auto (PNG, JPEG, TIFF from sRGB; EXR, HDR, .npy as "
    "stored), srgb, linear or gamma:G"
)


CAMERA_GUESS_HELP = "a folder without camera.json: relight from the model's own camera (unchecked)"


def _real_scene(scene: str, size: str, samples: int, response: str = "auto", camera_guess: bool = False):
    """A folder (scene.yaml, photograph, camera.json) or a built-in scene photographed by Mitsuba."""
    from ..relight import builtin_real_scene, load_real_scene

    if Path(scene).is_dir():
        return load_real_scene(scene, response, camera_guess)
    if not 1 <= samples <= 1 << 16:
        raise InputError(f"--samples must be in 1..65536, got {samples}")
    return builtin_real_scene(scene, parse_size(size), samples)


@params_options(params=RelightParams)
def relight_prepare(
    scene: str = typer.Argument(
        "office",
        help="a folder (scene.yaml, photograph, camera.json) or the built-in real "
        "scene (its photograph is path-traced: the photo extra)",
    ),
    output: Path = typer.Option(..., "-o", "--output", help="the prepared session (.npz)"),
    size: str = typer.Option(DEFAULT_SIZE_TEXT, "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(DEFAULT_PATHS, "--samples", help="paths per pixel of the photograph"),
    response: str = typer.Option("auto", "--response", help=RESPONSE_HELP),
    camera_guess: bool = typer.Option(False, "--camera-guess/--no-camera-guess", help=CAMERA_GUESS_HELP),
    *,
    params: RelightParams,
) -> None:
    """Prepare SCENE once (estimates, refinement, textures, the lamps' basis) and save it, so that
    `illusio relight FILE.npz --set ...` starts at once."""
    from ..relight import RelightSession

    out = check_output_path(output, [str(p) for p in Path(scene).iterdir()] if Path(scene).is_dir() else [])
    if out.suffix.lower() != ".npz":
        raise InputError(f"-o: a prepared session is saved as .npz, got {out.name}")
    session = RelightSession(_real_scene(scene, size, samples, response, camera_guess), params)
    session.save(out)
    typer.echo(f"wrote {out}: {session.solution.stats.leaves} leaves, prepared in {session.times['prepare']:.1f} s")
    _report_registration(session)


@params_options(params=RelightParams)
def relight(
    scene: str = typer.Argument(
        "office",
        help="a folder (scene.yaml, photograph, camera.json; see "
        "relight.load_real_scene), the built-in real scene (its photograph is "
        "path-traced: the photo extra), or a session saved by `illusio relight "
        "prepare` (.npz)",
    ),
    output: Path = typer.Option(..., "-o", "--output", help="the relit image (.png sRGB, .npy/.exr linear)"),
    set_lamp: list[str] = typer.Option(
        None, "--set", help="NAME=SCALE: a real lamp's estimated exitance × SCALE (repeatable)"
    ),
    size: str = typer.Option(DEFAULT_SIZE_TEXT, "--size", help="WIDTHxHEIGHT of the photograph (its main camera)"),
    samples: int = typer.Option(DEFAULT_PATHS, "--samples", help="paths per pixel of the photograph"),
    add_lamp: list[str] = typer.Option(
        None,
        "--add-lamp",
        help=(
            f"X,Y,Z:EXITANCE — a virtual {VIRTUAL_LAMP_SIZE * 100:g} cm lamp facing down at X,Y,Z (m), W/m² "
            "(repeatable)"
        ),
    ),
    add_object: list[str] = typer.Option(
        None,
        "--add-object",
        help="MESH@X,Y,Z — a virtual object (mesh file or built-in shape) standing at X,Y,Z (repeatable)",
    ),
    photograph: Path = typer.Option(None, "--photograph", help="also write the photograph used"),
    show: str = typer.Option(
        "image",
        "--show",
        help="image, textures (what the method displays), mesh (leaf outlines), display-factor "
        "or registration (the model's edges over the photograph's)",
    ),
    response: str = typer.Option("auto", "--response", help=RESPONSE_HELP),
    camera_guess: bool = typer.Option(False, "--camera-guess/--no-camera-guess", help=CAMERA_GUESS_HELP),
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
    lamps = [_parse_lamp(t) for t in add_lamp or ()]  # every option checked before the photograph
    objects = [_parse_object(t) for t in add_object or ()]
    if saved:
        session = RelightSession.load(scene)
    else:
        session = RelightSession(_real_scene(scene, size, samples, response, camera_guess), params)
    real = session.real
    unknown = sorted(set(scales) - set(session.lamp_names))
    if unknown:
        raise InputError(
            f"no lamp named {unknown[0]!r}{did_you_mean(unknown[0], session.lamp_names)}; "
            f"lamps: {', '.join(session.lamp_names)}"
        )
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
    _report_registration(session)


def _report_registration(session) -> None:
    """Print how well the model lines up with the photograph; warn when poorly."""
    import warnings

    result = session.registration()
    typer.echo(result.line())
    if result.poor:
        warnings.warn(
            f"{result.line()}: the model and the photograph do not line up well; check camera.json "
            "(illusio relight calibrate) or the model (--show registration draws both)",
            stacklevel=2,
        )


def relight_calibrate(
    photo: Path = typer.Argument(..., help="the photograph (its size is the camera's)"),
    points: Path = typer.Option(
        ...,
        "--points",
        help="u v x y z per line: a pixel and the model point it shows "
        "(see illusio.relight.calibrate; at least 6, not on one plane)",
    ),
    output: Path = typer.Option(
        ..., "-o", "--output", help="camera.json to write (beside scene.yaml and the photograph)"
    ),
    max_error: float = typer.Option(
        2.0, "--max-error", help="refuse a fit whose RMS reprojection error is above this many pixels"
    ),
) -> None:
    """The photograph's camera (intrinsics f_x, f_y, c_x, c_y, k1, k2 and pose) from points picked on it
    and on the model (OpenCV's calibrateCamera), written as camera.json; the reprojection error printed."""
    from ..core.images import read_image
    from ..relight.calibrate import calibrate, read_points, write_camera

    if not max_error > 0:
        raise InputError(f"--max-error must be positive, got {max_error:g}")
    check_output_path(output, (photo, points))
    if output.suffix.lower() != ".json":
        raise InputError(f"{output}: the camera is written as .json (camera.json beside the photograph)")
    image = read_image(photo)
    uv, xyz = read_points(points)
    size = (image.shape[1], image.shape[0])
    outside = ~((uv >= -0.5) & (uv <= np.array(size) - 0.5)).all(axis=1)
    if outside.any():
        k = int(np.flatnonzero(outside)[0])
        raise InputError(
            f"{points}: point {k + 1} (u, v = {uv[k, 0]:g}, {uv[k, 1]:g}) is outside the {size[0]}×{size[1]} photograph"
        )
    result = calibrate(uv, xyz, size)
    worst = int(np.argmax(result.errors))
    i = result.intrinsics
    summary = (
        f"reprojection error {result.rms:.2f} px RMS over {len(uv)} points (worst: point {worst + 1}, "
        f"{result.errors[worst]:.2f} px)"
    )
    if result.rms > max_error:
        raise InputError(
            f"{summary}: above --max-error {max_error:g} px; check that each u, v is paired with its x, y, z"
        )
    write_camera(output, result)
    typer.echo(
        f"wrote {output}: fx {i.fx:.1f}, fy {i.fy:.1f}, cx {i.cx:.1f}, cy {i.cy:.1f} px, k1 {i.distortion[0]:.4f}, "
        f"k2 {i.distortion[1]:.4f}; {summary}"
    )


def relight_example(
    folder: Path = typer.Argument(
        ..., help="the folder to write (scene.yaml, photograph.png, points.txt, true-camera.json)"
    ),
    size: str = typer.Option(DEFAULT_SIZE_TEXT, "--size", help="WIDTHxHEIGHT of the photograph"),
    samples: int = typer.Option(
        DEFAULT_PATHS, "--samples", help="paths per pixel of the photograph (denoised when pyoidn is installed)"
    ),
    seed: int = typer.Option(0, "--seed", help="the path tracer's and the picked points' randomness"),
) -> None:
    """The worked example of relighting your own photograph: a room's model, a photograph of it
    path-traced through a camera with its own intrinsics and lens distortion, and points picked on
    both. Then: `illusio relight calibrate`, `illusio relight prepare`, `illusio relight` (docs/own-data.md)."""
    from ..relight.example import make_example

    if not 1 <= samples <= 4096:
        raise InputError(f"--samples must be in [1, 4096], got {samples}")
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder}: exists and is not a folder")
    w, h = parse_size(size)
    paths = make_example(folder, (w, h), samples, seed)
    typer.echo(f"wrote {folder}: {', '.join(p.name for p in paths.values())} ({w}×{h}, {samples} paths a pixel)")
