"""Autostereograms and multi-scene images (Dehos, Hébert, Renaud 2014).

Kept, frame after frame (the Renderer protocol of illusio.core.renderer)::

    renderer = StereogramRenderer(ctx)
    renderer.prepare(depth)
    image = renderer.render(Frame(size=(w, h), index=n), StereogramParams(pattern="snow"))

One-shot::

    from illusio.sis import stereogram, StereogramParams
    image = stereogram(depth, StereogramParams(algorithm="fast", strip_width=100, depth_factor=50))

``depth`` is D, float32 (H, W) in [0, 1] with 0 = near (files use white = near: see
:func:`read_depth`). A window keeps a :class:`StereogramRenderer` (or a :class:`MultiSceneRenderer`
for a stereogram inside a 3D scene) and calls it every frame.
"""

from .decode import DecodeReport, check, decode_separation, expected_separation, separation_to_depth
from .depth import check_depth, read_depth
from .params import ALGORITHMS, PATTERNS, StereogramParams
from .physics import (depth_from_separation, depth_range, max_separation_px, screen_width_cm, separation_cm,
                      separation_px)
from .multiscene import MultiSceneParams, MultiSceneRenderer, MultiSceneSubject, hidden_view_from_viewer, multiscene
from .stereogram import StereogramRenderer, draw_guides, stereogram, stereogram_cpu

__all__ = [
    "StereogramParams", "ALGORITHMS", "PATTERNS", "StereogramRenderer", "stereogram", "stereogram_cpu",
    "MultiSceneParams", "MultiSceneRenderer", "MultiSceneSubject", "hidden_view_from_viewer", "multiscene",
    "draw_guides", "check_depth", "read_depth", "DecodeReport", "check", "decode_separation",
    "expected_separation", "separation_to_depth", "separation_cm", "screen_width_cm", "separation_px",
    "depth_from_separation", "max_separation_px", "depth_range",
]
