"""Line drawings of meshes: apparent ridges (Judd et al. 2007) by the hybrid GPU method of Jardim &
de Figueiredo as the report describes it, beside silhouettes, suggestive contours, ridges & valleys
and image edges.

Kept, frame after frame (the Renderer protocol of illusio.core.renderer)::

    renderer = LineRenderer(ctx)
    renderer.prepare(mesh)
    image = renderer.render(Frame(view, (1024, 1024)), LineParams(tau=-1.0))

One-shot: ``line_drawing(mesh, LineParams())``.
"""

from ..core.lazy import lazy_exports

# names -> the module that defines them; imported on first use, so that `illusio --help` and the
# CLI's defaults (lines.params) do not pay for numba and the passes
_EXPORTS = {
    "TECHNIQUES": "technique",
    "LineRenderer": "drawing",
    "Drawing": "drawing",
    "framing_view": "drawing",
    "line_drawing": "drawing",
    "LineParams": "params",
    "CurvatureParams": "params",
    "LINE_TYPES": "params",
    "METHODS": "params",
    "Curvature": "curvature",
    "estimate_curvature": "curvature",
    "DEBUG_VIEWS": "debug",
    "debug_view": "debug",
    "write_drawing_svg": "svg",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
