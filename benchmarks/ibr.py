"""Image-based rendering (issue 14): quality on held-out viewpoints and speed against rasterising.

Quality: the office showcase path (gallery/ibr.py), viewpoints that are not references, inside the
region the references cover; PSNR and SSIM against the rasteriser's render of the same camera, for
1, 3 and 6 references captured at twice the output's size (and 3 at the output's size), with bilinear
or nearest reference depth, with the 2D or 3D distance, with the speed run's settings. Speed: at
1024×768, an IBR frame of a 1M-triangle scene from 3 references (at the output's size, and at twice
it; speed_params) against rasterising the scene itself, camera moving (the reconstruction redone
every frame) and still (only the selection and the lighting)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from skimage.metrics import structural_similarity

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.gallery.ibr import showcase_path
from illusio.ibr.params import IbrParams
from illusio.ibr.references import capture, orbit_views
from illusio.ibr.renderer import IbrRenderer
from illusio.passes.scene_renderer import RenderSettings, SceneRenderer
from illusio.scene.builtin import builtin_scene, shapes, turntable
from illusio.scene.camera import Pose, View

from .runner import Timing, time_case, time_interleaved

QUALITY_SIZE = (640, 480)
SPEED_SIZE = (1024, 768)


def speed_params(scale: int) -> IbrParams:
    """The speed run's settings for references ``scale`` times the output's size: a coarser
    reconstruction, the mesh every 8 output pixels (the text's first pass is an approximate depth
    buffer; the selection corrects the depth), and its holes filled 2 pixels deep."""
    return IbrParams(mesh_step=8 * scale, fill_radius=2)


def psnr(a, b) -> float:
    return float(10 * np.log10(1 / max(float(np.mean((np.asarray(a, np.float64) - b) ** 2)), 1e-12)))


def seam_errors(images, truths, sources, depths) -> tuple[float, float]:
    """The error where the source view changes (a pixel whose 3×3 neighbourhood came from more than
    one reference) on flat, smooth surfaces — true depth within 2 % and true colour within 0.02 over
    5×5, so occlusion and texture edges do not count — as (mean, 99th percentile) of the absolute
    error in 1/255 steps of linear colour. A visible seam is a jump of a step or more there."""
    from scipy import ndimage

    at_seam = []
    for image, true, source, depth in zip(images, truths, sources, depths):
        error = np.abs(np.asarray(image, np.float64) - true).mean(axis=-1)
        spread = np.max([ndimage.maximum_filter(true[..., c], 5) - ndimage.minimum_filter(true[..., c], 5)
                         for c in range(3)], axis=0)
        flat = (depth > 0) & (ndimage.minimum_filter(depth, 5) > 0.98 * ndimage.maximum_filter(depth, 5)) & (spread < 0.02)
        flat &= ndimage.minimum_filter(source, 3) > 0
        boundary = (ndimage.maximum_filter(source, 3) != ndimage.minimum_filter(source, 3)) & flat
        at_seam.append(error[boundary])
    errors = np.concatenate(at_seam) * 255
    return float(errors.mean()), float(np.percentile(errors, 99))


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
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
        variants = {"": IbrParams(), ", the speed run's settings (mesh every 8 output px, holes filled 2 px)": speed_params(scale)}
        if scale == 2:
            variants |= {", nearest depth": IbrParams(bilinear_depth=False),
                         ", 3d distance": IbrParams(distance="3d", max_distance=0.05)}
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
                ratios["office, 3 references: error at view boundaries on flat surfaces, 1/255 steps: 99th percentile"] = p99
            ratios[f"office, {count} references{label}: PSNR dB (mean over the path)"] = float(
                np.mean([psnr(i, t) for i, t in zip(images, truths)]))
            ratios[f"office, {count} references{label}: SSIM"] = float(np.mean(
                [structural_similarity(i, t, channel_axis=2, data_range=1.0) for i, t in zip(images, truths)]))
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
        return View(Pose(tuple(np.asarray(base.pose.position) + right * 0.02 * (k % 20 - 10)), base.pose.target), base.camera)

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
    cases = {"raster/1M triangles": (rasterise, note),
             "ibr/camera moving": (ibr_moving, note + ", reconstruction each frame"),
             "ibr/camera moving, references at twice the size": (
                 lambda: ibr_moving(twice, 2), note + " at twice the output's size, reconstruction each frame"),
             "ibr/camera still": (ibr_still, note + ", selection and lighting only")}
    timings += time_interleaved(cases, repeat)          # the goal: the machine's speed drifts between cases
    single = time_case("ibr/camera still, single pass", ibr_still, repeat, notes=note + ", apart from the others")
    multi = time_case("ibr/camera still, multi-pass", lambda: ibr_still("multi-pass"), repeat,
                      notes=note + ", the text's draw per reference, apart from the others")
    timings += [single, multi]
    by = {t.name: t.median_ms for t in timings}
    ratios["raster / ibr time, camera moving (goal > 1)"] = by["raster/1M triangles"] / by["ibr/camera moving"]
    ratios["raster / ibr time, camera moving, references at twice the size"] = (
        by["raster/1M triangles"] / by["ibr/camera moving, references at twice the size"])
    ratios["raster / ibr time, camera still"] = by["raster/1M triangles"] / by["ibr/camera still"]
    ratios["multi-pass / single-pass selection time, camera still"] = (
        by["ibr/camera still, multi-pass"] / by["ibr/camera still, single pass"])
    renderer.release()
    twice.release()
    still.release()
    raster.release()
    return timings, ratios
