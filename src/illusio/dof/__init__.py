"""Stereoscopic depth of field (Piranda & de Sorbier): blur from a thin-lens eye, one focus for both
eyes of a stereo pair.

Kept, frame after frame (the Renderer protocol of illusio.core.renderer)::

    renderer = DofRenderer(ctx)
    renderer.prepare(scene)
    image = renderer.render(Frame(view, (1024, 768)), DofParams(focus_distance=2.5, stereo="anaglyph"))

One-shot: ``depth_of_field(scene, DofParams(...))``. Methods so far: "accumulation" (the reference)
and "gather" (the depth-aware convolution).
"""

from ..core.lazy import lazy_exports

_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(("DofRenderer", "depth_of_field"), "renderer"),
    **dict.fromkeys(("DofParams", "METHODS", "STEREO_OUTPUTS"), "params"),
    **dict.fromkeys(("image_distance", "coc_diameter", "coc_pixels", "fov_for_focal_length"), "lens"),
    "object_distance": "focus",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
