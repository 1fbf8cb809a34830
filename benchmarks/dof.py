"""Depth of field (issue 13): every method's error against a converged accumulation reference and its
time, in one run. 1024×768 per eye, both eyes of a stereo pair, on the museum (49k triangles) and the
living room (62k). Errors: PSNR over the whole image and within 4 px of depth edges (where leaking
and banding show), and SSIM; the reference's convergence is shown by N/2 against N lens positions."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
from scipy import ndimage
from skimage.metrics import structural_similarity

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.dof.focus import object_distance
from illusio.dof.params import DofParams
from illusio.dof.renderer import DofRenderer
from illusio.scene.builtin import builtin_scene

from .runner import Timing, time_case

SIZE = (1024, 768)
CASES = (("museum", "exhibit-superquadric"), ("living-room", "coffee-table-top"))
METHODS = ("accumulation-32", "gather", "mipmap", "planes", "sharp")


def psnr(image, reference, mask=None) -> float:
    diff = (np.asarray(image, np.float64) - reference) ** 2
    mse = float(diff[mask].mean() if mask is not None else diff.mean())
    return float("inf") if mse == 0 else 10 * np.log10(1.0 / mse)


def edge_mask(depth: np.ndarray, width: int = 4) -> np.ndarray:
    """Pixels within ``width`` of a depth edge (a jump of more than 5 % in log depth)."""
    z = np.log(np.where(depth > 0, depth, 1e4))
    edges = (np.abs(ndimage.sobel(z, 0)) + np.abs(ndimage.sobel(z, 1))) > 0.4
    return ndimage.binary_dilation(edges, iterations=width)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (256, 192) if quick else SIZE
    samples = 32 if quick else 128
    cases = CASES[:1] if quick else CASES
    eyes = ("left",) if quick else ("left", "right")
    timings: list[Timing] = []
    ratios: dict[str, float] = {}
    renderer = DofRenderer(ctx)
    for scene_name, focus_on in cases:
        scene = builtin_scene(scene_name)
        renderer.prepare(scene)
        view = scene.camera()
        base = DofParams(focus_distance=object_distance(scene, focus_on, view), aperture_mm=120.0, max_coc=16.0,
                         eye_separation=0.065)
        frame = Frame(view, size)
        variants = {"accumulation-32": replace(base, method="accumulation", samples=32), "gather": base,
                    "mipmap": replace(base, method="mipmap"), "planes": replace(base, method="planes"),
                    "sharp": replace(base, method="mipmap", aperture_mm=0.0)}
        for eye in eyes:
            reference_params = replace(base, method="accumulation", samples=samples, stereo=eye)
            t0 = time.perf_counter()
            reference = renderer.render(frame, reference_params)
            reference_ms = (time.perf_counter() - t0) * 1000
            half = renderer.render(frame, replace(reference_params, samples=samples // 2, seed=1))
            renderer.render(frame, replace(base, stereo=eye))  # the gather's depth map of this eye
            edges = edge_mask(ctx.readback(renderer.maps()["depth"])[..., 0])
            key = f"{scene_name}/{eye}"
            timings.append(Timing(f"{key}/accumulation-{samples} (reference)", 1, reference_ms, reference_ms, reference_ms,
                                  f"{size[0]}x{size[1]}"))
            ratios[f"{key}: reference {samples // 2} vs {samples} samples, PSNR dB (converged)"] = psnr(half, reference)
            for name in METHODS:
                params = replace(variants[name], stereo=eye)
                image = renderer.render(frame, params)
                ratios[f"{key}: {name} PSNR dB"] = psnr(image, reference)
                ratios[f"{key}: {name} PSNR dB within 4 px of depth edges"] = psnr(image, reference, edges)
                ratios[f"{key}: {name} SSIM"] = float(structural_similarity(image, reference, channel_axis=2, data_range=1.0))
                t = time_case(f"{key}/{name}", lambda p=params: renderer.render(frame, p), max(1, repeat // 3), warmup=1,
                              notes=f"{size[0]}x{size[1]}, one eye")
                timings.append(t)
                if name == "planes":
                    ratios[f"{key}: reference time / {name} (goal >= 20)"] = reference_ms / t.median_ms
        renderer.release()
    return timings, ratios
