"""The depth-of-field showcase: the museum focused on one exhibit by each method, the circle of
confusion map and the planes beside them, each method's error against the accumulation reference, an
anaglyph of the stereo pair (one focus for both eyes), and Figure 11's scenario as a stereo video."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..core.renderer import Frame
from ..dof.focus import object_distance
from ..dof.params import DofParams
from ..dof.reference import plane_index
from ..dof.renderer import DofRenderer
from ..scene.builtin import builtin_scene
from .html import Item, Section

__all__ = ["dof_showcase"]


def dof_showcase(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    section = Section("Stereoscopic depth of field (Piranda & de Sorbier)",
                      "A thin-lens eye focused on one exhibit of the museum: what is far from the focal plane is "
                      "blurred, so it draws the eye less and its large disparities tire it less.")
    scene = builtin_scene("museum")
    view = scene.camera()
    renderer = DofRenderer(ctx)
    renderer.prepare(scene)
    frame = Frame(view, size)
    base = DofParams(focus_distance=object_distance(scene, "exhibit-superquadric", view), aperture_mm=120.0, max_coc=16.0)
    reference = None
    for method, params in (("accumulation", replace(base, method="accumulation", samples=48)), ("gather", base),
                           ("mipmap", replace(base, method="mipmap")), ("planes", replace(base, method="planes"))):
        t0 = time.perf_counter()
        image = renderer.render(frame, params)
        ms = (time.perf_counter() - t0) * 1000
        if reference is None:
            reference = image
            note = f"{params.samples} lens positions averaged: the reference; {ms:.0f} ms"
        else:
            note = f"mean error against the reference {np.abs(image - reference).mean():.4f}; {ms:.0f} ms"
            maps = {k: ctx.readback(renderer.maps()[k])[..., 0] for k in ("coc", "depth")}
        write_image(out_dir / f"dof/museum-{method}.png", image)
        section.items.append(Item(f"dof/museum-{method}.png", f"{method}, focus on the blue superquadric at {base.focus_distance:.2f} m, "
                                  f"aperture {base.aperture_mm:g} mm", note))
    write_image(out_dir / "dof/museum-coc.png", np.clip(maps["coc"] / base.max_coc, 0, 1), srgb=False)
    section.items.append(Item("dof/museum-coc.png", "circle of confusion (white = the largest drawn, "
                              f"{base.max_coc:g} px)", "dof.lens: A·|1/d − 1/d_f|·H / (2 tan(fov/2))"))
    distances = renderer.last_planes
    write_image(out_dir / "dof/museum-planes.png", plane_index(maps["depth"], distances) / (len(distances) - 1), srgb=False)
    section.items.append(Item("dof/museum-planes.png", "the planes each pixel takes, in grey levels (Figure 8)",
                              f"{base.planes_behind} behind, {base.planes_front} in front of the focal plane, "
                              f"{base.distribution} spreading"))
    anaglyph = renderer.render(frame, replace(base, stereo="anaglyph"))
    write_image(out_dir / "dof/museum-anaglyph.png", anaglyph)
    section.items.append(Item("dof/museum-anaglyph.png", "the stereo pair as a red-cyan anaglyph (Dubois)",
                              "one focus for both eyes; zero parallax at the focus distance"))
    section.items.append(_scenario_video(ctx, out_dir, size))
    renderer.release()
    return section


def _scenario_video(ctx: Context, out_dir: Path, size: tuple[int, int], fps: float = 8.0) -> Item:
    """Figure 11: the shipped scenario on the futuristic scene, as an anaglyph video whose focus
    follows the script (the ship, the robot when it fires, the projectile, the ship again)."""
    from ..core.images import VideoWriter
    from ..dof.scenario import load_scenario, shipped_scenario
    from ..dof.timeline import ScenarioPlayer

    scene = builtin_scene("futuristic")
    player = ScenarioPlayer(load_scenario(shipped_scenario("futuristic")), scene)
    view = scene.camera()
    renderer = DofRenderer(ctx)
    params = DofParams(method="planes", aperture_mm=300.0, stereo="anaglyph", max_coc=16.0)
    small = (max(64, size[0] // 2), max(36, size[1] // 2))
    count = int(player.loop * fps)
    with VideoWriter(out_dir / "dof/futuristic-scenario.mp4", fps) as video:
        for i in range(count):
            t = i / fps
            player.apply(scene, t)
            renderer.prepare(scene)
            focus = player.focus_distance(view, t)
            video.append(renderer.render(Frame(view, small, t, i), replace(params, focus_distance=focus or params.focus_distance)))
    renderer.release()
    return Item("dof/futuristic-scenario.mp4", "Figure 11 — the scenario (dof/scenarios/futuristic.txt) as a red-cyan anaglyph",
                f"planes method; the focus follows the script: ship, robot when it fires, projectile, ship; {count} frames at {fps:g} fps")
