"""The autostereogram showcase: Figure 28 (depth, random-dot and texture stereograms), the four
algorithms with their self-check scores, and the multi-scene TV of Figure 23."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..scene import builtin_scene
from ..scene.builtin import shape, textures
from ..sis.decode import check
from ..sis.depth import depth_from_scene, hidden_scene
from ..sis.multiscene import MultiSceneParams, MultiSceneRenderer
from ..sis.params import ALGORITHMS, StereogramParams
from ..sis.reference import separation
from ..sis.stereogram import StereogramRenderer
from .html import Item, Section

__all__ = ["sis_showcase"]


def sis_showcase(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    section = Section("Autostereograms (Dehos et al. 2014)",
                      "Focus behind the screen (wall-eyed) until the two guide dots fuse into one: the hidden shape appears.")
    w, h = size
    scale = w / 1920
    sis = StereogramRenderer(ctx)
    depth = depth_from_scene(ctx, hidden_scene(shape("torus-knot")), (w, h))
    write_image(out_dir / "sis/depth.png", 1.0 - depth)
    section.items.append(Item("sis/depth.png", "Figure 28 — depth map", "rendered torus knot, white = near"))
    base = StereogramParams(strip_width=max(2.0, 100 * scale), depth_factor=max(1.0, 50 * scale), guides=True)
    texture_path = out_dir / "sis/planks-texture.png"
    write_image(texture_path, textures.planks(256, 3, 5))  # the wallpaper stripes are too faint to fuse
    for name, params in (("random-dot", base), ("texture", StereogramParams(**{**base.__dict__, "pattern": str(texture_path)}))):
        img = sis.render(depth, params)
        rel = f"sis/{name}.png"
        write_image(out_dir / rel, img)
        section.items.append(Item(rel, f"Figure 28 — {name} stereogram", f"fast GPU pass, W_s = {params.strip_width:.0f}, β = {params.depth_factor:.0f} px"))
    sep = separation(depth, base.strip_width, base.depth_factor)
    for algorithm in ALGORITHMS:
        params = StereogramParams(**{**base.__dict__, "algorithm": algorithm, "guides": False})
        img = sis.render(depth, params)
        report = check(img, sep, int(params.far_separation + 0.5), "centre" if algorithm == "symmetric" else "left")
        rel = f"sis/algorithm-{algorithm}.png"
        write_image(out_dir / rel, img)
        section.items.append(Item(rel, f"{algorithm} algorithm", f"self-check: {report}"))
    scene = builtin_scene("living-room")
    multi = MultiSceneRenderer(ctx)
    hidden = hidden_scene(shape("torus-knot"))
    for camera in ("tv", "main"):
        keep = {}
        img = multi.render(scene, hidden, scene.camera(camera), (w, h), MultiSceneParams(), frame=1, keep=keep)
        rel = f"sis/tv-{camera}.png"
        write_image(out_dir / rel, img)
        section.items.append(Item(rel, f"Figure 23 — TV snow hiding a torus knot ('{camera}' camera)", "stereogram computed in screen space, shown as the TV's glow"))
        d = keep["depth"]
        write_image(out_dir / f"sis/tv-{camera}-depth.png", np.where(d >= 0, 1.0 - d, 0.0))
        section.items.append(Item(f"sis/tv-{camera}-depth.png", "its screen-space depth (step 2 of Figure 22)", "white = near, black = off the TV"))
    interactive = MultiSceneParams(host="rug", stereogram=StereogramParams(pattern="random-dot", strip_width=100, depth_factor=40),
                                   emission=0.0, interactive=True)
    img = multi.render(scene, hidden, scene.camera("main"), (w, h), interactive, frame=1)
    write_image(out_dir / "sis/interactive-rug.png", img)
    section.items.append(Item("sis/interactive-rug.png", "Figure 25 — interaction mode on the rug",
                              "the hidden knot is seen from where the viewer stands relative to the rug"))
    return section
