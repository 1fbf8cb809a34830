"""``illusio ibr capture`` and ``illusio ibr render``: reference views of a scene, and new views made
from them."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import typer

from ..core.errors import InputError, did_you_mean
from ..core.images import check_output_path, write_image, write_video
from ..ibr.params import IbrParams
from .common import SCENE_HELP, on_turntable_option, parse_eye_target, parse_size, resolve_scene, scene_inputs
from .params_options import params_options

app = typer.Typer(add_completion=False, no_args_is_help=True, help="Image-based rendering from reference views.")


@app.command("capture")
def capture_command(
    scene: str = typer.Argument(..., help=SCENE_HELP),
    on_turntable: bool = on_turntable_option(),
    output: Path = typer.Option(..., "-o", "--output", help="folder to write the references to"),
    views: int = typer.Option(3, "--views", help="reference cameras along the main camera's right"),
    cameras: Path = typer.Option(
        None,
        "--cameras",
        help="JSON list of cameras {eye, target, fov, near, far} "
        "(or a references.json) to capture from, instead of --views",
    ),
    baseline: float = typer.Option(1.2, "--baseline", help="metres the reference eyes span"),
    size: str = typer.Option("512x384", "--size", help="WIDTHxHEIGHT of each reference"),
    renderer: str = typer.Option(
        "raster", "--renderer", help="raster (our G-buffer) or mitsuba (path-traced photographs)"
    ),
    samples: int = typer.Option(64, "--samples", help="paths a pixel with --renderer mitsuba"),
) -> None:
    """Capture reference views of SCENE (albedo, normal, emission, depth, the recorded colour, camera)."""
    from ..core.context import Context
    from ..ibr.reference_views import capture, load_cameras, orbit_views, save_references

    if not 1 <= views <= 16:
        raise InputError(f"--views must be in 1..16, got {views}")
    if renderer not in ("raster", "mitsuba"):
        raise InputError(f"--renderer must be raster or mitsuba, got {renderer!r}")
    if not 1 <= samples <= 65536:
        raise InputError(f"--samples must be in 1..65536, got {samples}")
    chosen = load_cameras(cameras) if cameras is not None else None
    sc = resolve_scene(scene, on_turntable)
    chosen = chosen or orbit_views(sc, views, baseline)
    if renderer == "mitsuba":
        from ..ibr.mitsuba import capture_mitsuba

        refs = capture_mitsuba(sc, chosen, parse_size(size), samples)
    else:
        refs = capture(sc, chosen, parse_size(size), Context())
    save_references(refs, output)
    typer.echo(f"wrote {output} ({len(chosen)} reference views)")


@app.command("import")
def import_command(
    kind: str = typer.Argument(
        ...,
        help="rgbd (color/ + depth/ + intrinsic.json + trajectory.log), tum (rgb.txt, "
        "depth.txt, groundtruth.txt) or colmap (sparse/ text model, images/, "
        "stereo/depth_maps/)",
    ),
    source: Path = typer.Argument(..., help="the capture's folder"),
    output: Path = typer.Option(..., "-o", "--output", help="references folder to write"),
    frames: str = typer.Option(
        None, "--frames", help="comma-separated frame indices to use as references (e.g. 0,10,20)"
    ),
    every: int = typer.Option(
        None, "--every", help="every N-th frame as a reference (default: 8 spread evenly, or all if fewer)"
    ),
    max_depth: float = typer.Option(None, "--max-depth", help="metres: farther depth becomes a hole"),
    intrinsics: Path = typer.Option(
        None,
        "--intrinsics",
        help="intrinsics JSON (width, height, fx, fy, cx, cy, or "
        "Open3D's intrinsic_matrix) instead of the folder's intrinsic.json",
    ),
    poses: Path = typer.Option(None, "--poses", help="rgbd: a trajectory .log instead of the folder's trajectory.log"),
    depth_scale: float = typer.Option(None, "--depth-scale", help="depth PNG units per metre (rgbd 1000, tum 5000)"),
) -> None:
    """Import a real capture (colour + depth + poses) as reference views: the photos as recorded colour
    and albedo, normals from the depth, the full intrinsics; every frame's camera and photo kept
    for --camera frame:K and --compare-photo K."""
    from ..ibr import captures
    from ..ibr.reference_views import save_references
    from ..ibr.select import MAX_REFERENCES

    if kind not in captures.KINDS:
        raise InputError(
            f"capture kind must be one of {', '.join(captures.KINDS)}, got {kind!r}{did_you_mean(kind, captures.KINDS)}"
        )
    if not source.is_dir():
        raise InputError(f"{source}: no such folder")
    if output.resolve() == source.resolve() or source.resolve().is_relative_to(output.resolve()):
        raise InputError(f"{output}: the references would be written over the capture; choose another folder")
    if frames is not None and every is not None:
        raise InputError("give --frames or --every, not both")
    read = captures.read_capture(kind, source, intrinsics, poses, depth_scale)
    count = len(read)
    if frames is not None:
        try:
            chosen = [int(v) for v in frames.split(",")]
        except ValueError:
            raise InputError(f"--frames takes comma-separated frame indices, got {frames!r}") from None
        bad = [k for k in chosen if not 0 <= k < count]
        if bad:
            raise InputError(f"--frames: frame {bad[0]} does not exist; the capture has {count} (0 to {count - 1})")
    elif every is not None:
        if every < 1:
            raise InputError(f"--every must be at least 1, got {every}")
        chosen = list(range(0, count, every))
    else:
        chosen = sorted({int(round(v)) for v in np.linspace(0, count - 1, min(count, 8))})
    if not 1 <= len(chosen) <= MAX_REFERENCES:
        raise InputError(f"{len(chosen)} references chosen; image-based rendering takes 1..{MAX_REFERENCES}")
    refs = captures.frames_to_references(read, chosen, max_depth)
    save_references(refs, output)
    w, h = refs.views[0].size
    typer.echo(
        f"wrote {output} ({len(chosen)} references of {count} frames, {w}×{h}: frames {','.join(map(str, chosen))})"
    )


def parse_camera(text: str, refs, extrapolate: bool = False):
    """``ref:K``, ``frame:K``, ``between:I,J[,T]`` or ``x,y,z:x,y,z`` → a View (the lens of the first
    reference). T is in [0, 1] unless ``extrapolate`` (beyond the pair, on the line through it)."""
    from ..scene.camera import Pose, View

    lens = refs.views[0].view.camera
    count = len(refs.views)

    def index(word: str) -> int:
        k = int(word)
        if not 0 <= k < count:  # Python's -1 would silently take the last reference
            raise InputError(f"--camera {text}: reference {k} does not exist; there are {count} (0 to {count - 1})")
        return k

    try:
        kind, _, rest = text.partition(":")
        if kind == "ref":
            return refs.views[index(rest)].view
        if kind == "frame":
            k = int(rest)
            if not 0 <= k < len(refs.frames):
                raise InputError(
                    f"--camera {text}: frame {k} does not exist; the capture has {len(refs.frames)} frames"
                    + ("" if refs.frames else " (frames come with an imported capture: illusio ibr import)")
                )
            return refs.frames[k][0]
        if kind == "between":
            parts = rest.split(",")
            if len(parts) not in (2, 3):
                raise ValueError
            i, j, t = index(parts[0]), index(parts[1]), (float(parts[2]) if len(parts) > 2 else 0.5)
            if not (0.0 <= t <= 1.0 or extrapolate and math.isfinite(t)):  # beyond the pair is extrapolation
                raise InputError(
                    f"--camera {text}: T must be in [0, 1] (0 at reference {i}, 1 at {j}), got {t:g}; "
                    "--extrapolate allows a T outside"
                )
            a, b = refs.views[i].view.pose, refs.views[j].view.pose
            mix = lambda p, q: tuple((1 - t) * np.asarray(p) + t * np.asarray(q))  # noqa: E731
            return View(Pose(mix(a.position, b.position), mix(a.target, b.target), a.up), refs.views[i].view.camera)
        pair = parse_eye_target(text)
        if pair is None:
            raise ValueError
        return View(Pose(*pair), lens)
    except InputError:
        raise
    except (ValueError, IndexError):
        raise InputError(
            f"--camera must be ref:K, frame:K, between:I,J[,T] or x,y,z:x,y,z (with {len(refs.views)} "
            f"references), got {text!r}"
        ) from None


@app.command("render")
@params_options(params=IbrParams)
def render_command(
    references: Path = typer.Argument(..., help="a references folder (illusio ibr capture, or your own)"),
    output: Path = typer.Option(
        ..., "-o", "--output", help="image to write (.png, .exr, .npy), or .mp4/.gif with --path"
    ),
    camera: str = typer.Option(
        "between:0,1", "--camera", help="ref:K, frame:K (an imported capture's frame), between:I,J[,T] or x,y,z:x,y,z"
    ),
    compare_photo: int = typer.Option(
        None,
        "--compare-photo",
        help="render frame K of an imported capture and print "
        "PSNR and SSIM against its photo over the pixels with depth",
    ),
    score_space: str = typer.Option(
        "srgb",
        "--score-space",
        help="srgb: scores of the displayed image, as papers give them; linear: of the linear radiance",
    ),
    path: Path = typer.Option(
        None,
        "--path",
        help="camera path JSON [{t, eye, target}, ...] (as illusio view "
        "--path) played into a video, instead of --camera",
    ),
    fps: float = typer.Option(12.0, "--fps", help="frames a second along --path"),
    size: str = typer.Option(None, "--size", help="WIDTHxHEIGHT (default: the references')"),
    ground_truth: str = typer.Option(None, "--ground-truth", help="render this scene from the same camera instead"),
    extrapolate: bool = typer.Option(
        False,
        "--extrapolate/--no-extrapolate",
        help="between:I,J,T may take T outside [0, 1] (a "
        "camera beyond the pair: what the references did not see is left black)",
    ),
    *,
    params: IbrParams,
) -> None:
    """Render a new view from REFERENCES."""
    from ..core.context import Context
    from ..core.renderer import Frame
    from ..ibr.reference_views import load_references
    from ..ibr.renderer import IbrRenderer
    from ..passes.scene_renderer import RenderSettings, render_scene

    out = check_output_path(output, [references] + scene_inputs(ground_truth or "") + ([path] if path else []))
    if path is not None and out.suffix.lower() not in (".mp4", ".gif"):
        raise InputError(f"--path plays a video: the output must be .mp4 or .gif, got {out.name}")
    if not 0 < fps <= 120:
        raise InputError(f"--fps must be in (0, 120], got {fps:g}")
    refs = load_references(references)
    if compare_photo is not None:
        if path is not None:
            raise InputError("--compare-photo renders one frame: leave out --path")
        camera = f"frame:{compare_photo}"
    if refs.albedo_from_photo and params.relight:
        # a capture's albedo is its photo and it has no lights: drawn as recorded (relit it is dark)
        params = replace(params, relight=False)
    if path is not None:
        from ..viewer.path import CameraPath

        walk = CameraPath.load(path)
        lens = refs.views[0].view.camera
        views = [walk.view(k / fps, lens) for k in range(int(walk.duration * fps) + 1)]
    else:
        views = [parse_camera(camera, refs, extrapolate)]
    w, h = parse_size(size) if size else refs.views[0].size
    ctx = Context()
    if ground_truth:
        truth = resolve_scene(ground_truth)
        images = [render_scene(truth, view, (w, h), ctx, RenderSettings(shadows=False)) for view in views]
    else:
        renderer = IbrRenderer(ctx)
        renderer.prepare(refs)
        images = [renderer.render(Frame(view, (w, h), k / fps, k), params) for k, view in enumerate(views)]
        renderer.release()
    if path is not None:
        write_video(out, images, fps)
        typer.echo(f"wrote {out} ({len(images)} frames of {w}×{h} at {fps:g} fps)")
    else:
        write_image(out, images[0])
        typer.echo(f"wrote {out} ({w}×{h})")
    if compare_photo is not None:
        _compare(refs, compare_photo, images[0], (w, h), score_space)


def _compare(refs, k: int, image: np.ndarray, size: tuple[int, int], space: str) -> None:
    """PSNR and SSIM of ``image`` against frame ``k``'s photo, over the pixels the render covers, in
    ``space`` (the literature's: the displayed sRGB image)."""
    from ..core.images import read_image
    from ..core.scores import image_scores

    photo = refs.frames[k][1]
    photo = read_image(photo)[..., :3] if isinstance(photo, (str, Path)) else np.asarray(photo)[..., :3]
    if photo.shape[:2] != (size[1], size[0]):
        raise InputError(
            f"--compare-photo {k}: the photo is {photo.shape[1]}×{photo.shape[0]}; render at its size "
            f"(leave out --size)"
        )
    covered = np.abs(image[..., :3]).sum(axis=-1) > 0  # holes are black: no reference saw them
    typer.echo(f"against frame {k}'s photo: {image_scores(image, photo, covered, space)}")
