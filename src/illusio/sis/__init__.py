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

from ..core.lazy import lazy_exports

# names -> the module that defines them; imported on first use (numba and the passes load only when
# a stereogram is made, not for `illusio --help` or for reading the Params' defaults)
_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(
        ("DecodeReport", "check", "decode_separation", "expected_separation", "separation_to_depth"), "decode"
    ),
    **dict.fromkeys(("check_depth", "read_depth"), "depth"),
    **dict.fromkeys(("ALGORITHMS", "PATTERNS", "StereogramParams", "MultiSceneParams"), "params"),
    **dict.fromkeys(
        (
            "depth_from_separation",
            "depth_range",
            "max_separation_px",
            "screen_width_cm",
            "separation_cm",
            "separation_px",
        ),
        "physics",
    ),
    **dict.fromkeys(("MultiSceneRenderer", "MultiSceneSubject", "hidden_view_from_viewer", "multiscene"), "multiscene"),
    **dict.fromkeys(("StereogramRenderer", "draw_guides", "stereogram", "stereogram_cpu"), "stereogram"),
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
