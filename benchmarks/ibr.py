"""Image-based rendering (issue 14): quality on held-out viewpoints and speed against rasterising.

Quality: the office showcase path (gallery/ibr.py), viewpoints that are not references, inside the
region the references cover; PSNR and SSIM against the rasteriser's render of the same camera, for
1, 3 and 6 references captured at twice the output's size (and 3 at the output's size), with bilinear
or nearest reference depth, with the 2D or 3D distance, with the speed run's settings. Speed: at
1024×768, an IBR frame of a 1M-triangle scene from 3 references (at the output's size, and at twice
it; speed_params) against rasterising the scene itself, camera moving (the reconstruction redone
every frame) and still (only the selection and the lighting).

Real captures (issue 30): an RGB-D capture generated along a path in the office (9 frames through
off-centre intrinsics, f_x ≠ f_y, depth with 0.4 % noise and 3 % dropped pixels), frames 0, 4 and 8
imported as references (captures.frames_to_references), the other six rendered at their own poses
and scored against their photos over the pixels with depth; beside it, in the same run, the two
baselines: a plain z-buffered point splat of the same references (every reference pixel projected
to its nearest target pixel, the nearest depth kept) and the photo of the nearest reference.

Growth (issue 30): the frame time of IBR (camera moving) and of rasterising the scene itself as the
scene grows to 1M, 4M and 16M triangles, the references captured once per scene.

Scores are of the displayed sRGB image (core.scores, as the view-synthesis literature states them),
LPIPS beside them where the ``lpips`` package is installed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.core.scores import image_scores, psnr
from illusio.gallery.ibr import showcase_path
from illusio.ibr.captures import CaptureFrame, Intrinsics, frames_to_references
from illusio.ibr.params import IbrParams
from illusio.ibr.proxy_mesh import unproject
from illusio.ibr.reference_views import capture, orbit_views
from illusio.ibr.renderer import IbrRenderer
from illusio.passes.scene_renderer import RenderSettings, SceneRenderer
from illusio.scene.builtin import builtin_scene, shapes, turntable
from illusio.scene.camera import Pose, View

from .runner import Timing, paired_ratio, time_case, time_interleaved

QUALITY_SIZE = (640, 480)
SPEED_SIZE = (1024, 768)


def speed_params(scale: int) -> IbrParams:
    """The speed run's settings for references ``scale`` times the output's size: a coarser
    reconstruction, the mesh every 8 output pixels (the text's first pass is an approximate depth
    buffer; the selection corrects the depth), and its holes filled 2 pixels deep."""
    return IbrParams(mesh_step=8 * scale, fill_radius=2)


def seam_errors(images, truths, sources, depths) -> tuple[float, float]:
    """The error where the source view changes (a pixel whose 3×3 neighbourhood came from more than
    one reference) on flat, smooth surfaces — true depth within 2 % and true colour within 0.02 over
    5×5, so occlusion and texture edges do not count — as (mean, 99th percentile) of the absolute
    error in 1/255 steps of linear colour. A visible seam is a jump of a step or more there."""
    from scipy import ndimage

    at_seam = []
    for image, true, source, depth in zip(images, truths, sources, depths):
        error = np.abs(np.asarray(image, np.float64) - true).mean(axis=-1)
        spread = np.max(
            [ndimage.maximum_filter(true[..., c], 5) - ndimage.minimum_filter(true[..., c], 5) for c in range(3)],
            axis=0,
        )
        flat = (
            (depth > 0) & (ndimage.minimum_filter(depth, 5) > 0.98 * ndimage.maximum_filter(depth, 5)) & (spread < 0.02)
        )
        flat &= ndimage.minimum_filter(source, 3) > 0
        boundary = (ndimage.maximum_filter(source, 3) != ndimage.minimum_filter(source, 3)) & flat
        at_seam.append(error[boundary])
    errors = np.concatenate(at_seam) * 255
    if not len(errors):  # no boundary on a flat surface at this size (--quick)
        return float("nan"), float("nan")
    return float(errors.mean()), float(np.percentile(errors, 99))


#: GL camera axes (y up, looking down −z) ↔ a capture's (y down, z forward)
_FLIP = np.diag([1.0, -1.0, -1.0, 1.0])


def point_splat(references, view, size) -> np.ndarray:
    """The baseline: every pixel of every reference with depth, unprojected to the world and
    projected into ``view`` at the nearest pixel; the nearest depth wins (z-buffer). Black where
    nothing lands. (H, W, 3)."""
    w, h = size
    colour = np.zeros((h * w, 3), np.float32)
    best = np.full(h * w, np.inf)
    for ref in references.views:
        rw, rh = ref.size
        ys, xs = np.mgrid[0:rh, 0:rw] + 0.5
        valid = ref.depth > 0
        world = unproject(ref.view, (rw, rh), xs[valid], ys[valid], ref.depth[valid])
        px, depth = view.project(world, size)
        col, row = np.floor(px[:, 0]).astype(int), np.floor(px[:, 1]).astype(int)
        inside = (col >= 0) & (col < w) & (row >= 0) & (row < h) & (depth > 0)
        pixel = row[inside] * w + col[inside]
        order = np.lexsort((depth[inside], pixel))
        first = np.r_[True, pixel[order][1:] != pixel[order][:-1]]
        take, near = pixel[order][first], depth[inside][order][first]
        closer = near < best[take]
        best[take[closer]] = near[closer]
        colour[take[closer]] = ref.colour[valid][inside][order][first][closer]
    return colour.reshape(h, w, 3)


def rgbd_quality(ctx: Context, quick: bool, ratios: dict) -> None:
    """The real-capture rows of the module docstring."""
    size = (160, 120) if quick else (320, 240)
    w, h = size
    intrinsics = Intrinsics(w, h, 0.78 * w, 0.84 * w, 0.52 * w, 0.47 * h)
    scene = builtin_scene("office")
    base = scene.camera()
    eye, target = np.array(base.pose.position), np.array(base.pose.target)
    ahead = target - eye
    right = np.cross(ahead / np.linalg.norm(ahead), (0, 1, 0))
    lens = intrinsics.camera(0.05, 30.0)
    views = [View(Pose(tuple(eye + 0.25 * ahead + (k - 4) * 0.08 * right), tuple(target)), lens) for k in range(9)]
    recorded = capture(scene, views, size, ctx)
    rng = np.random.default_rng(3)
    frames = []
    for k, (v, ref) in enumerate(zip(views, recorded.views)):
        d = ref.depth * (1 + rng.normal(0, 0.004, ref.depth.shape))
        d[rng.random(d.shape) < 0.03] = 0.0
        pose = np.linalg.inv(v.view_matrix().astype(np.float64)) @ _FLIP
        frames.append(
            CaptureFrame(
                f"frame {k}",
                np.clip(ref.colour, 0, 1).astype(np.float32),
                np.where(ref.depth > 0, d, 0.0).astype(np.float32),
                intrinsics,
                pose,
            )
        )
    chosen = [0, 4, 8]
    refs = frames_to_references(frames, chosen)
    renderer = IbrRenderer(ctx)
    renderer.prepare(refs)
    scores = {"ibr": [], "point splat": [], "nearest reference's photo": []}
    for k in (k for k in range(9) if k not in chosen):
        view, photo = refs.frames[k]
        mask = frames[k].depth > 0
        image = renderer.render(Frame(view, size), IbrParams(relight=False))[..., :3]  # drawn as recorded
        scores["ibr"].append(psnr(image, photo, mask))
        scores["point splat"].append(psnr(point_splat(refs, view, size), photo, mask))
        nearest = min(chosen, key=lambda j: abs(j - k))  # along the path, the nearest camera
        scores["nearest reference's photo"].append(psnr(frames[nearest].colour, photo, mask))
    renderer.release()
    for label, values in scores.items():
        ratios[f"rgbd capture, held-out frames: {label}: PSNR dB, sRGB (mean of 6)"] = float(np.mean(values))
    ibr = float(np.mean(scores["ibr"]))
    ratios["rgbd capture: ibr - point splat, dB (goal >= 3)"] = ibr - float(np.mean(scores["point splat"]))
    ratios["rgbd capture: ibr - nearest reference's photo, dB (goal >= 8)"] = ibr - float(
        np.mean(scores["nearest reference's photo"])
    )


def growth(ctx: Context, repeat: int, quick: bool, timings: list, ratios: dict) -> None:
    """The growth rows of the module docstring."""
    size = (256, 192) if quick else SPEED_SIZE
    counts = {"62k": (176, 177)} if quick else {"1M": (1000, 501), "4M": (2000, 1001), "16M": (4000, 2001)}
    by = {}
    for label, (segments, rings) in counts.items():
        big = turntable(shapes.sphere(1.0, segments, rings))
        raster, ibr = SceneRenderer(ctx), IbrRenderer(ctx)
        raster.prepare(big)
        ibr.prepare(capture(big, orbit_views(big, 3, 0.8), size, ctx))
        base = big.camera()
        right = base.pose.axes()[0]
        step = [0]

        def view_at(k):
            return View(
                Pose(tuple(np.asarray(base.pose.position) + right * 0.02 * (k % 20 - 10)), base.pose.target),
                base.camera,
            )

        def moving():
            step[0] += 1
            ctx.release(ibr.render_texture(Frame(view_at(step[0]), size), speed_params(1)))
            ctx.finish()

        def rasterise():
            ctx.release(raster.render_texture(Frame(view_at(0), size), RenderSettings(shadows=False)))
            ctx.finish()

        triangles = len(big.nodes[0].mesh.faces) + sum(len(n.mesh.faces) for n in big.nodes[1:])
        note = f"{size[0]}x{size[1]}, {triangles:,} triangles, 3 references"
        cases = {f"growth/raster {label}": (rasterise, note), f"growth/ibr camera moving {label}": (moving, note)}
        got = time_interleaved(cases, max(1, min(repeat, 5 if label != "16M" else 3)))
        timings += got
        t = {x.name: x.median_ms for x in got}
        by[label] = (t[f"growth/raster {label}"], t[f"growth/ibr camera moving {label}"])
        ratios[f"growth, {label} triangles: raster / ibr frame time"] = by[label][0] / by[label][1]
        raster.release()
        ibr.release()
        del big
    labels = list(by)
    if len(labels) > 1:
        first, last = by[labels[0]], by[labels[-1]]
        ratios[f"growth: raster time {labels[-1]} / {labels[0]}"] = last[0] / first[0]
        ratios[f"growth: ibr time {labels[-1]} / {labels[0]} (flat: ~1)"] = last[1] / first[1]
        ratios[f"growth: raster / ibr at {labels[-1]} (goal >= 5 on llvmpipe)"] = last[0] / last[1]


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    rgbd_quality(ctx, quick, ratios)
    growth(ctx, repeat, quick, timings, ratios)
    t, r = _office_and_speed(ctx, repeat, quick)
    return timings + t, {**ratios, **r}


def _office_and_speed(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (160, 120) if quick else QUALITY_SIZE
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    scene = builtin_scene("office")
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    path = showcase_path(scene)
    times = np.linspace(0.25, path.duration - 0.25, 3 if quick else 7)
    views = [path.view(t, scene.camera().camera) for t in times]
    truths = [truth.render(Frame(v, size), RenderSettings(shadows=False)) for v in views]
    truth_depths = []
    for v in views:
        g = truth.gbuffer(Frame(v, size))
        truth_depths.append(ctx.readback(g["depth"])[..., 0])
        g.release()
    renderer = IbrRenderer(ctx)
    for count, scale in ((1, 2), (3, 2), (6, 2), (3, 1)):
        renderer.prepare(capture(scene, orbit_views(scene, count, 1.6), (size[0] * scale, size[1] * scale), ctx))
        variants = {
            "": IbrParams(),
            ", the speed run's settings (mesh every 8 output px, holes filled 2 px)": speed_params(scale),
        }
        if scale == 2:
            variants |= {
                ", nearest depth": IbrParams(bilinear_depth=False),
                ", 3d distance": IbrParams(distance="3d", max_distance=0.05),
            }
        for label, params in variants.items():
            if label and count != 3:
                continue
            label = label + (", references at the output's size" if scale == 1 else "")
            images, sources = [], []
            for v in views:
                images.append(renderer.render(Frame(v, size), params))
                sources.append(np.rint(ctx.readback(renderer.maps()["source"])[..., 0]).astype(int))
            if count == 3 and scale == 2 and not label:
                mean, p99 = seam_errors(images, truths, sources, truth_depths)
                ratios["office, 3 references: error at view boundaries on flat surfaces, 1/255 steps: mean"] = mean
                ratios[
                    "office, 3 references: error at view boundaries on flat surfaces, 1/255 steps: 99th percentile"
                ] = p99
            scores = [image_scores(i, t) for i, t in zip(images, truths)]
            ratios[f"office, {count} references{label}: PSNR dB, sRGB (mean over the path)"] = float(
                np.mean([s.psnr for s in scores])
            )
            ratios[f"office, {count} references{label}: SSIM, sRGB"] = float(np.mean([s.ssim for s in scores]))
            if scores[0].lpips is not None:
                ratios[f"office, {count} references{label}: LPIPS"] = float(np.mean([s.lpips for s in scores]))
    renderer.release()
    truth.release()

    size = (256, 192) if quick else SPEED_SIZE
    big = turntable(shapes.sphere(1.0, 1000, 501))  # 1,000,002 triangles with the floor
    raster = SceneRenderer(ctx)
    raster.prepare(big)
    settings = RenderSettings(shadows=False)
    base = big.camera()
    # two renderers, references at the output's size and at twice it (where the office reaches 30 dB)
    twice = IbrRenderer(ctx)
    twice.prepare(capture(big, orbit_views(big, 3, 0.8), (size[0] * 2, size[1] * 2), ctx))
    refs = capture(big, orbit_views(big, 3, 0.8), size, ctx)
    renderer.prepare(refs)
    still = IbrRenderer(ctx)  # its own, so the interleaved moving frames do not drop its depth
    still.prepare(refs)
    moving = [0]

    def view_at(k):
        right, _, _ = base.pose.axes()
        return View(
            Pose(tuple(np.asarray(base.pose.position) + right * 0.02 * (k % 20 - 10)), base.pose.target), base.camera
        )

    def ibr_moving(which=renderer, scale=1):
        moving[0] += 1
        ctx.release(which.render_texture(Frame(view_at(moving[0]), size), speed_params(scale)))
        ctx.finish()

    def ibr_still(selection="single-pass"):
        ctx.release(still.render_texture(Frame(view_at(0), size), replace(speed_params(1), selection=selection)))
        ctx.finish()

    def rasterise():
        ctx.release(raster.render_texture(Frame(view_at(0), size), settings))
        ctx.finish()

    note = f"{size[0]}x{size[1]}, 1,000,002 triangles, 3 references"
    cases = {
        "raster/1M triangles": (rasterise, note),
        "ibr/camera moving": (ibr_moving, note + ", reconstruction each frame"),
        "ibr/camera moving, references at twice the size": (
            lambda: ibr_moving(twice, 2),
            note + " at twice the output's size, reconstruction each frame",
        ),
        "ibr/camera still": (ibr_still, note + ", selection and lighting only"),
    }
    samples: dict[str, list[float]] = {}
    timings += time_interleaved(cases, repeat, samples=samples)  # the goal: the machine's speed drifts
    single = time_case("ibr/camera still, single pass", ibr_still, repeat, notes=note + ", apart from the others")
    multi = time_case(
        "ibr/camera still, multi-pass",
        lambda: ibr_still("multi-pass"),
        repeat,
        notes=note + ", the text's draw per reference, apart from the others",
    )
    timings += [single, multi]
    by = {t.name: t.median_ms for t in timings}
    # each round's raster frame over the IBR frame beside it, the median over rounds (paired_ratio)
    for label, case in (
        ("camera moving (goal > 1)", "ibr/camera moving"),
        ("camera moving, references at twice the size", "ibr/camera moving, references at twice the size"),
        ("camera still", "ibr/camera still"),
    ):
        ratios[f"raster / ibr time, {label}"] = paired_ratio(samples, "raster/1M triangles", case)
    ratios["multi-pass / single-pass selection time, camera still"] = (
        by["ibr/camera still, multi-pass"] / by["ibr/camera still, single pass"]
    )
    renderer.release()
    twice.release()
    still.release()
    raster.release()
    return timings, ratios
