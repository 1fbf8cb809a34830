"""Depth of field: each method's time and error against a converged accumulation reference, in one
run (issue 13; the improved planes variant is still to come). 1024×768 on the museum, mono and stereo."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.dof.focus import object_distance
from illusio.dof.params import DofParams
from illusio.dof.renderer import DofRenderer
from illusio.scene.builtin import builtin_scene

from .runner import Timing, time_case

SIZE = (1024, 768)


def psnr(image: np.ndarray, reference: np.ndarray) -> float:
    mse = float(np.mean((np.asarray(image, np.float64) - reference) ** 2))
    return float("inf") if mse == 0 else 10 * np.log10(1.0 / mse)


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    size = (256, 192) if quick else SIZE
    scene = builtin_scene("museum")
    view = scene.camera()
    renderer = DofRenderer(ctx)
    renderer.prepare(scene)
    frame = Frame(view, size)
    base = DofParams(focus_distance=object_distance(scene, "exhibit-superquadric", view), aperture_mm=120.0, max_coc=16.0)
    samples = 64 if quick else 128
    reference_params = replace(base, method="accumulation", samples=samples)
    reference = renderer.render(frame, reference_params)
    half = renderer.render(frame, replace(base, method="accumulation", samples=samples // 2, seed=1))
    timings: list[Timing] = []
    ratios: dict[str, float] = {f"accumulation {samples // 2} vs {samples} samples: PSNR dB (converged)": psnr(half, reference)}
    cases = {"accumulation-32": replace(base, method="accumulation", samples=32), "gather": base,
             "mipmap": replace(base, method="mipmap"), "planes": replace(base, method="planes"),
             "sharp (no blur)": replace(base, aperture_mm=0.0, method="mipmap")}
    for name, params in cases.items():
        image = renderer.render(frame, params)
        ratios[f"{name}: PSNR dB against the reference"] = psnr(image, reference)
        timings.append(time_case(name, lambda p=params: renderer.render(frame, p), max(1, repeat // 3), warmup=1,
                                 notes=f"{size[0]}x{size[1]} mono, museum, max CoC {base.max_coc:g} px"))
    stereo = replace(base, stereo="side-by-side")
    timings.append(time_case("gather, stereo pair", lambda: renderer.render(frame, stereo), max(1, repeat // 3), warmup=1,
                             notes=f"{size[0]}x{size[1]} per eye"))
    timings.append(time_case(f"accumulation-{samples} (the reference)", lambda: renderer.render(frame, reference_params), 1,
                             warmup=0, notes=f"{size[0]}x{size[1]} mono"))
    by = {t.name: t.median_ms for t in timings}
    for name in ("gather", "mipmap", "planes"):
        ratios[f"reference / {name} time" + (" (goal >= 20)" if name == "planes" else "")] = \
            by[f"accumulation-{samples} (the reference)"] / by[name]
    ratios["gather stereo frames per second"] = 1000 / by["gather, stereo pair"]
    renderer.release()
    return timings, ratios
