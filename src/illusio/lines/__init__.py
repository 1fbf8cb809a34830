"""Line drawings of meshes: apparent ridges (Judd et al. 2007) by the hybrid GPU method of Jardim &
de Figueiredo as the report describes it, beside silhouettes, suggestive contours, ridges & valleys
and image edges.

Kept, frame after frame (the Renderer protocol of illusio.core.renderer)::

    renderer = LineRenderer(ctx)
    renderer.prepare(mesh)
    image = renderer.render(Frame(view, (1024, 1024)), LineParams(tau=-1.0))

One-shot: ``line_drawing(mesh, LineParams())``.
"""

from .curvature import Curvature, estimate_curvature
from .debug import DEBUG_VIEWS, debug_view
from .drawing import Drawing, LineRenderer, framing_view, line_drawing
from .params import LINE_TYPES, METHODS, CurvatureParams, LineParams
from .svg import write_drawing_svg

__all__ = ["LineRenderer", "LineParams", "CurvatureParams", "Drawing", "LINE_TYPES", "METHODS", "framing_view",
           "line_drawing", "Curvature", "estimate_curvature", "DEBUG_VIEWS", "debug_view", "write_drawing_svg"]
