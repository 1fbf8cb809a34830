"""Depth of field (issues 13, 32) at equal quality: each method's PSNR and SSIM against a converged
accumulation (256 lens positions; 128 against 256 shows it has converged), and the accumulation of
the fewest positions that reaches the same PSNR, with its time: the speed-up that counts. 1024×768
per eye, both eyes, on two views with strong blur (the museum and the living room). Scores are of
the displayed sRGB image (core.scores, the literature's convention), LPIPS beside them where the
``lpips`` package is installed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy import ndimage

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.core.scores import image_scores, psnr
from illusio.dof.focus import object_distance
from illusio.dof.params import DofParams
from illusio.dof.renderer import DofRenderer
from illusio.scene.builtin import builtin_scene

from .runner import Timing, time_case

SIZE = (1024, 768)
#: (scene, what the focus is on: an object or metres, aperture mm, largest circle px): views where
#: blur is strong, the unblurred image ≤ 30 dB against the converged reference (the issue's
#: measurement: museum 3 m, 150 mm); the living room's circles reach past the default 24 px
CASES = (("museum", 3.0, 150.0, 24.0), ("living-room", "coffee-table-top", 500.0, 48.0))
#: gather: the sampled gather at its default points; gather-exact: every pixel of its kernel
METHODS = ("gather", "gather-exact", "mipmap", "planes", "sharp")
#: lens positions of the accumulation ladder: the baseline at each quality
LADDER = (1, 2, 4, 8, 16, 32, 64, 128)


def edge_mask(depth: np.ndarray, width: int = 4) -> np.ndarray:
    """Pixels within ``width`` of a depth edge (a jump of more than 5 % in log depth)."""
    z = np.log(np.where(depth > 0, depth, 1e4))
    edges = (np.abs(ndimage.sobel(z, 0)) + np.abs(ndimage.sobel(z, 1))) > 0.4
    return ndimage.binary_dilation(edges, iterations=width)


def matched(ladder: dict[int, tuple[float, float]], quality: float) -> tuple[float, float] | None:
    """The lens positions an accumulation needs to reach ``quality`` dB and its time (ms): between
    two rungs of the ladder, log2(positions) and log(time) interpolated linearly in PSNR (PSNR grows
    by ~3.7 dB per doubling here); at or below the first rung, the first rung; None above the last."""
    rungs = sorted(ladder)
    if quality <= ladder[rungs[0]][0]:
        return float(rungs[0]), ladder[rungs[0]][1]
    for lo, hi in zip(rungs, rungs[1:]):
        (q0, t0), (q1, t1) = ladder[lo], ladder[hi]
        if q0 < quality <= q1:
            f = (quality - q0) / (q1 - q0)
            return float(2 ** (np.log2(lo) + f * (np.log2(hi) - np.log2(lo)))), float(t0 * (t1 / t0) ** f)
    return None


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    """Equal quality: each method against the accumulation that reaches its PSNR (not an
    over-converged one), both measured in this run."""
    size = (256, 192) if quick else SIZE
    samples = 64 if quick else 256
    ladder_sizes = tuple(n for n in LADDER if n <= samples // 4)
    cases = CASES[:1] if quick else CASES
    eyes = ("left",) if quick else ("left", "right")
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    renderer = DofRenderer(ctx)
    for scene_name, focus_on, aperture, max_coc in cases:
        scene = builtin_scene(scene_name)
        renderer.prepare(scene)
        view = scene.camera()
        focus = focus_on if isinstance(focus_on, float) else object_distance(scene, focus_on, view)
        base = DofParams(focus_distance=focus, aperture_mm=aperture, eye_separation=0.065, max_coc=max_coc)
        frame = Frame(view, size)
        variants = {
            "gather": base,
            "gather-exact": replace(base, gather_taps=0),
            "mipmap": replace(base, method="mipmap"),
            "planes": replace(base, method="planes"),
            "sharp": replace(base, method="mipmap", aperture_mm=0.0),
        }
        for eye in eyes:
            key = f"{scene_name}/{eye}"
            reference_params = replace(base, method="accumulation", samples=samples, stereo=eye)
            reference = renderer.render(frame, reference_params)
            half = renderer.render(frame, replace(reference_params, samples=samples // 2, seed=1))
            ratios[f"{key}: reference {samples // 2} vs {samples} positions, PSNR dB, sRGB (converged)"] = psnr(
                half, reference
            )
            renderer.render(frame, replace(base, stereo=eye))  # the gather's depth map of this eye
            edges = edge_mask(ctx.readback(renderer.maps()["depth"])[..., 0])
            ladder = {}
            for n in ladder_sizes:  # another seed: not the reference's own positions
                params = replace(reference_params, samples=n, seed=7)
                image = renderer.render(frame, params)
                t = time_case(
                    f"{key}/accumulation-{n}",
                    lambda p=params: renderer.render(frame, p),
                    max(1, repeat // 3),
                    warmup=1,
                    notes=f"{size[0]}x{size[1]}, one eye",
                )
                timings.append(t)
                ladder[n] = (psnr(image, reference), t.median_ms)
                ratios[f"{key}: accumulation-{n} PSNR dB, sRGB"] = ladder[n][0]
            for name in METHODS:
                params = replace(variants[name], stereo=eye)
                image = renderer.render(frame, params)
                quality = psnr(image, reference)
                ratios[f"{key}: {name} PSNR dB, sRGB"] = quality
                ratios[f"{key}: {name} PSNR dB, sRGB, within 4 px of depth edges"] = psnr(image, reference, edges)
                scores = image_scores(image, reference)
                ratios[f"{key}: {name} SSIM, sRGB"] = scores.ssim
                if scores.lpips is not None:
                    ratios[f"{key}: {name} LPIPS"] = scores.lpips
                t = time_case(
                    f"{key}/{name}",
                    lambda p=params: renderer.render(frame, p),
                    max(1, repeat // 3),
                    warmup=1,
                    notes=f"{size[0]}x{size[1]}, one eye",
                )
                timings.append(t)
                if name == "sharp":
                    continue
                match = matched(ladder, quality)
                if match is None:
                    ratios[f"{key}: {name} beyond accumulation-{max(ladder)} (speed-up at least)"] = (
                        ladder[max(ladder)][1] / t.median_ms
                    )
                else:
                    ratios[f"{key}: {name} matched by accumulation positions"] = match[0]
                    ratios[f"{key}: {name} speed-up at equal PSNR (goal >= 5, best >= 10)"] = match[1] / t.median_ms
        renderer.release()
    return timings, ratios
