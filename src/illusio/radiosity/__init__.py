"""Hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991) as Loscos' chapter 4 runs it: quadtrees
over the input polygons, links with form factors and ray-cast visibility, BF/BFV refinement, gather
and push-pull, interactive re-solves with the links kept, dynamic updates (Drettakis & Sillion 1997),
Gouraud display on the GPU and path-traced ground truth from Mitsuba 3.

    from illusio.radiosity import Radiosity, HierarchyParams, scene_polygons
    solution = Radiosity(scene_polygons(builtin_scene("office")), HierarchyParams()).build()
    solution.set_lamps({"lamp-0": 0.0})          # links kept, re-solved
"""

from .display import DisplayPass, LeafMesh, leaf_mesh
from .formfactor import point_polygon
from .params import CRITERIA, SHOW, HierarchyParams, RadiosityParams
from .polygons import Polygons, scene_polygons
from .renderer import RadiosityRenderer
from .solution import Radiosity, Stats
from .technique import TECHNIQUES
from .visibility import INVISIBLE, PARTIAL, VISIBLE

__all__ = ["TECHNIQUES", "Radiosity", "RadiosityRenderer", "RadiosityParams", "HierarchyParams", "Polygons", "scene_polygons",
           "Stats", "CRITERIA", "SHOW", "VISIBLE", "PARTIAL", "INVISIBLE", "radiosity_image",
           "DisplayPass", "LeafMesh", "leaf_mesh", "point_polygon"]


def radiosity_image(scene, size=(640, 480), params: RadiosityParams = RadiosityParams(), view=None, ctx=None):
    """One-shot: the scene's radiosity solution rendered from ``view`` (default: its main camera), as
    float32 (H, W, 3) radiance × exposure, row 0 at the top, clipped to [0, 1]."""
    from ..core.context import default_context
    from ..core.renderer import Frame

    ctx = ctx or default_context()
    renderer = ctx.kept(RadiosityRenderer)
    renderer.prepare(scene)
    return renderer.render(Frame(view, size), params)
