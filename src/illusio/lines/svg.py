"""SVG output for plotters: visible object-space lines as polylines, one group per line type, and
image-space lines (the hybrid apparent ridges, image-space silhouettes) traced from their pixels."""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..core.images import atomic_output
from ..scene.camera import View
from .object_space import Segments, chain
from .params import LineParams
from .reference import image_silhouettes

__all__ = ["visible_polylines", "trace_polylines", "write_svg", "drawing_groups", "write_drawing_svg"]


def visible_polylines(segments: Segments, view: View, size, depth: np.ndarray, slack: float = 0.01) -> list[np.ndarray]:
    """Polylines (K, 2) in pixels (x right, y down) of the parts of ``segments`` the surface does not
    hide: a point is visible where its view depth is at most the surface's (``depth``: (H, W) view
    depth of the visible surface, 0 = background) times 1 + ``slack``."""
    w, h = size
    out = []
    for line in chain(segments):
        px, d = view.project(line, (w, h))
        xi = np.clip(px[:, 0].astype(int), 0, w - 1)
        yi = np.clip(px[:, 1].astype(int), 0, h - 1)
        # a line on the surface is seen if it is not behind what the nearest pixel around it shows
        near = np.max(
            np.stack(
                [
                    depth[np.clip(yi + dy, 0, h - 1), np.clip(xi + dx, 0, w - 1)]
                    for dy in (-1, 0, 1)
                    for dx in (-1, 0, 1)
                ]
            ),
            axis=0,
        )
        visible = (d > 0) & ((near <= 0) | (d <= near * (1 + slack)))
        start = None
        for i, v in enumerate(np.append(visible, False)):
            if v and start is None:
                start = i
            elif not v and start is not None:
                if i - start >= 2:
                    out.append(px[start:i])
                start = None
    return out


# 8-neighbour offsets (dy, dx), in turning order
_NEIGHBOURS = ((-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1))


def trace_polylines(mask: np.ndarray, tolerance: float = 0.5, min_pixels: int = 2) -> list[np.ndarray]:
    """Polylines (K, 2) in pixels (x right, y down, pixel centres at .5) along a line mask (H, W)
    bool, row 0 on top: thinned to one-pixel skeletons, walked from ends and junctions (then round
    closed loops), simplified by Douglas–Peucker within ``tolerance`` px. Pieces shorter than
    ``min_pixels`` are dropped (single pixels: specks, not lines)."""
    from skimage.measure import approximate_polygon
    from skimage.morphology import skeletonize

    skeleton = np.pad(skeletonize(np.asarray(mask, bool)), 1)  # a frame of False: no bounds checks
    ys, xs = np.nonzero(skeleton)
    degree = sum(np.roll(skeleton, (-dy, -dx), (0, 1))[ys, xs].astype(int) for dy, dx in _NEIGHBOURS)
    nodes = {(y, x) for y, x, d in zip(ys, xs, degree) if d != 2}
    used: set[tuple[tuple[int, int], tuple[int, int]]] = set()

    def walk(start, first):
        path = [start, first]
        used.add((start, first))
        used.add((first, start))
        prev, cur = start, first
        while cur not in nodes and cur != start:
            for dy, dx in _NEIGHBOURS:
                nxt = (cur[0] + dy, cur[1] + dx)
                if skeleton[nxt] and nxt != prev and (cur, nxt) not in used:
                    break
            else:
                break
            used.add((cur, nxt))
            used.add((nxt, cur))
            path.append(nxt)
            prev, cur = cur, nxt
        return path

    paths = []
    for start in sorted(nodes) + [(y, x) for y, x in zip(ys, xs)]:  # ends and junctions first, then loops
        for dy, dx in _NEIGHBOURS:
            nxt = (start[0] + dy, start[1] + dx)
            if skeleton[nxt] and (start, nxt) not in used:
                paths.append(walk(start, nxt))
    out = []
    for path in paths:
        if len(path) < min_pixels or (len(path) == 2 and path[0] in nodes and path[1] in nodes):
            continue  # a speck, or a step between two pixels of one junction
        yx = np.asarray(path, np.float64) - 1.0  # undo the padding
        xy = approximate_polygon(yx[:, ::-1] + 0.5, tolerance)
        out.append(xy)
    return out


def write_svg(path: str | os.PathLike, size, groups: dict[str, tuple[list[np.ndarray], tuple, float]]) -> Path:
    """groups: line type → (polylines in pixels, linear RGB colour, width px). Written atomically."""
    w, h = size
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">',
        f'<rect width="{w}" height="{h}" fill="white"/>',
    ]
    for name, (lines, colour, width) in groups.items():
        rgb = "#" + "".join(f"{int(round(np.clip(c, 0, 1) ** (1 / 2.2) * 255)):02x}" for c in colour)
        parts.append(
            f'<g id={quoteattr(name)} fill="none" stroke="{rgb}" stroke-width="{width:g}" '
            'stroke-linecap="round" stroke-linejoin="round">'
        )
        for line in lines:
            pts = " ".join(f"{x:.2f},{y:.2f}" for x, y in line)
            parts.append(f'<polyline points="{pts}"/>')
        parts.append("</g>")
    parts.append("</svg>\n")
    p = Path(path)
    with atomic_output(p) as tmp:
        Path(tmp).write_text("\n".join(parts), encoding="utf-8")
    return p


def drawing_groups(drawing, params: LineParams) -> dict[str, tuple[list[np.ndarray], tuple, float]]:
    """The polylines of a :class:`~illusio.lines.drawing.Drawing` per line type, ready for
    :func:`write_svg`: object-space lines clipped by visibility; image-space lines (hybrid ridges,
    image silhouettes) traced from their pixels, so the SVG holds the same lines as the PNG."""
    depth = drawing.q_t1[..., 3]
    groups = {
        k: (visible_polylines(s, drawing.view, drawing.size, depth), params.colour(k), params.width(k))
        for k, s in drawing.segments.items()
    }
    if drawing.ridge_mask is not None:
        groups["apparent-ridges"] = (
            trace_polylines(drawing.ridge_mask),
            params.colour("apparent-ridges"),
            params.width("apparent-ridges"),
        )
    if "silhouettes" in params.lines and params.silhouette_space == "image":
        groups["silhouettes"] = (
            trace_polylines(image_silhouettes(depth, params.depth_jump)),
            params.colour("silhouettes"),
            params.width("silhouettes"),
        )
    return groups


def write_drawing_svg(path: str | os.PathLike, drawing, params: LineParams) -> int:
    """Write ``drawing`` as an SVG (atomically); returns the number of polylines."""
    groups = drawing_groups(drawing, params)
    write_svg(path, drawing.size, groups)
    return sum(len(g[0]) for g in groups.values())
