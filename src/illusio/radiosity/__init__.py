"""Hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991) as Loscos' chapter 4 runs it: quadtrees
over the input polygons, links with form factors and ray-cast visibility, BF/BFV refinement, gather
and push-pull, interactive re-solves with the links kept, dynamic updates (Drettakis & Sillion 1997),
a final gather at each pixel (or the corners' Gouraud display on the GPU) and path-traced ground
truth from Mitsuba 3.

    from illusio.radiosity import Radiosity, HierarchyParams, scene_polygons
    solution = Radiosity(scene_polygons(builtin_scene("office")), HierarchyParams()).build()
    solution.set_lamps({"lamp-0": 0.0})          # links kept, re-solved
"""

from ..core.lazy import lazy_exports

_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(("DisplayPass", "LeafMesh", "leaf_mesh"), "display"),
    "point_polygon": "formfactor",
    **dict.fromkeys(("CRITERIA", "SHOW", "HierarchyParams", "RadiosityParams"), "params"),
    **dict.fromkeys(("Polygons", "scene_polygons"), "polygons"),
    "RadiosityRenderer": "renderer",
    **dict.fromkeys(("Radiosity", "Stats"), "engine"),
    # the engine's parts that relighting builds on (its saved sessions hold hierarchies and links)
    "CornerGather": "corner_cache",
    "corner_average": "display",
    **dict.fromkeys(("Hierarchy", "HIERARCHY_FIELDS"), "hierarchy"),
    "Links": "links",
    "render_mitsuba": "mitsuba",
    "reference_display": "reference",
    **dict.fromkeys(("polygon_areas", "quads_from_triangles"), "polygons"),
    **dict.fromkeys(("VISIBLE", "PARTIAL", "INVISIBLE"), "visibility"),
}

__all__ = list(_EXPORTS) + ["radiosity_image"]

__getattr__ = lazy_exports(__name__, _EXPORTS)


def radiosity_image(scene, size=(640, 480), params=None, view=None, ctx=None):
    """One-shot: the scene's radiosity solution rendered from ``view`` (default: its main camera), as
    float32 (H, W, 3) radiance × exposure, row 0 at the top, clipped to [0, 1]; params: a
    RadiosityParams (default: its defaults)."""
    from ..core.context import default_context
    from ..core.renderer import Frame
    from .renderer import RadiosityRenderer

    ctx = ctx or default_context()
    renderer = ctx.kept(RadiosityRenderer)
    renderer.prepare(scene)
    return renderer.render(Frame(view, size), params)
