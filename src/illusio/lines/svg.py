"""SVG output an illustrator can edit and a plotter can draw: one layer (``<g id="line type">``) per
line type, in drawing order; visible object-space lines as polylines and image-space lines (the
hybrid apparent ridges, image-space silhouettes) traced from their pixels; then, per type, the pieces
whose ends meet chained into the longest paths the drawing allows (:func:`join_polylines`); a ridge
running along a silhouette left to the silhouette (drawn once); optionally each path drawn as a curve
through its points (Catmull–Rom splines as cubic Béziers). Widths, colours and the fade of the
page's style are kept."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..core.images import atomic_output, linear_to_srgb
from ..scene.camera import View
from .object_space import Segments, chain
from .params import LineParams
from .reference import image_silhouettes
from .style import LineStyle, ridge_strength

__all__ = [
    "Layer",
    "visible_polylines",
    "trace_polylines",
    "join_polylines",
    "stroke_statistics",
    "write_svg",
    "drawing_groups",
    "write_drawing_svg",
]

#: a path at least this long (px) counts as a long stroke in :func:`stroke_statistics`
LONG_STROKE = 50.0
#: how far (px) a smoothed path's points may move off the traced line before the spline is fitted
SMOOTH_TOLERANCE = 0.5
#: how far (output px) beyond the edges of a silhouette's stroke a ridge counts as drawn along it
REACH_MARGIN = 1.0
#: opacity levels of faded strokes: a path is split where its fade crosses a level
FADE_LEVELS = 4


def visible_polylines(
    segments: Segments, view: View, size, depth: np.ndarray, slack: float = 0.002
) -> list[np.ndarray]:
    """Polylines (K, 2) in pixels (x right, y down) of the parts of ``segments`` the surface does not
    hide (``depth``: (H, W) view depth of the visible surface, 0 = background). A point is seen
    where a pixel of its 3×3 neighbourhood is background (an outline: the page's stroke covers
    it there) or where its view depth is at most the farthest surface around it times 1 + ``slack``
    (a line on the surface). A slack of 1 % let a CAD part's hidden silhouettes through, 2–4 px
    inside its outline (fandisk: 23 % of the SVG's ink off the PNG's lines)."""
    w, h = size
    out = []
    for line in chain(segments):
        px, d = view.project(line, (w, h))
        xi = np.clip(px[:, 0].astype(int), 0, w - 1)
        yi = np.clip(px[:, 1].astype(int), 0, h - 1)
        around = np.stack(
            [depth[np.clip(yi + dy, 0, h - 1), np.clip(xi + dx, 0, w - 1)] for dy in (-1, 0, 1) for dx in (-1, 0, 1)]
        )
        visible = (d > 0) & ((around <= 0).any(axis=0) | (d <= around.max(axis=0) * (1 + slack)))
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


@dataclass
class Layer:
    """One line type's strokes: polylines (K, 2) in pixels (x right, y down), a linear RGB colour,
    a width in px, and per polyline an opacity in (0, 1] (None: all opaque)."""

    polylines: list
    colour: tuple
    width: float
    opacities: list | None = None


def _outward(line: np.ndarray, at_end: bool, reach: float = 3.0) -> np.ndarray:
    """The unit direction in which ``line`` leaves through an end: from its point about ``reach``
    px back from that end (its next vertex where the line is shorter) to the end."""
    pts = line[::-1] if at_end else line
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    k = int(np.searchsorted(np.cumsum(steps), reach)) + 1
    d = pts[0] - pts[min(k, len(pts) - 1)]
    n = np.linalg.norm(d)
    return d / n if n > 1e-12 else d


def join_polylines(lines, gap: float = 1.5, max_turn: float = 60.0) -> list[np.ndarray]:
    """Chain polylines whose ends lie within ``gap`` px into longer ones. Candidate joins are taken
    closest and straightest first (cost: the gap plus ``gap`` × turn / ``max_turn``), each end used
    once, never turning by more than ``max_turn`` degrees; a chain whose own two ends meet is closed
    (its first point repeated). Chains come in drawing order (of their first piece), each piece in the
    direction the chain runs. ``gap`` 0 returns the pieces as they are."""
    from scipy.spatial import cKDTree

    lines = [np.asarray(line, np.float64) for line in lines if len(line) >= 2]
    if gap <= 0 or len(lines) < 1:
        return lines
    ends = np.array([line[k] for line in lines for k in (0, -1)])  # end 2i: the start of i, 2i + 1: its end
    outward = np.array([_outward(line, bool(k)) for line in lines for k in (0, 1)])
    length = np.array([np.linalg.norm(np.diff(line, axis=0), axis=1).sum() for line in lines])
    candidates = []
    for a, b in cKDTree(ends).query_pairs(gap, output_type="ndarray"):
        if a // 2 == b // 2 and length[a // 2] <= 4 * gap:
            continue  # a short piece's own two ends: not a loop
        turn = np.degrees(np.arccos(np.clip(-float(outward[a] @ outward[b]), -1.0, 1.0)))
        if turn <= max_turn:
            candidates.append((float(np.linalg.norm(ends[a] - ends[b])) + gap * turn / max_turn, int(a), int(b)))
    partner = np.full(len(ends), -1)
    root = list(range(len(lines)))

    def find(i):
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    closed = set()
    for _, a, b in sorted(candidates):
        if partner[a] >= 0 or partner[b] >= 0:
            continue
        ra, rb = find(a // 2), find(b // 2)
        if ra == rb:  # the chain's two free ends: it closes
            closed.add(ra)
        else:
            root[max(ra, rb)] = min(ra, rb)
        partner[a], partner[b] = b, a
    out, done = [], np.zeros(len(lines), bool)
    for first in range(len(lines)):  # drawing order: a chain where its first piece is
        if done[first]:
            continue
        # walk back to a free end (or, round a loop, start here)
        end, seen = 2 * first, set()
        while partner[end] >= 0 and (end // 2) not in seen:
            seen.add(end // 2)
            end = partner[end] ^ 1
        if (end // 2) in seen:
            end = 2 * first
        pieces, cur = [], end  # enter that piece through its free end, and walk on
        while True:
            i = cur // 2
            if done[i]:
                break
            done[i] = True
            pieces.append(lines[i] if cur % 2 == 0 else lines[i][::-1])
            nxt = partner[cur ^ 1]
            if nxt < 0:
                break
            cur = nxt
        chain = pieces[0]
        for piece in pieces[1:]:
            same = np.linalg.norm(piece[0] - chain[-1]) < 1e-9
            chain = np.concatenate([chain, piece[1:] if same else piece])
        if find(first) in closed and len(chain) > 2 and np.linalg.norm(chain[0] - chain[-1]) > 1e-9:
            chain = np.concatenate([chain, chain[:1]])
        out.append(chain)
    return out


def stroke_statistics(polylines, long_stroke: float = LONG_STROKE) -> dict:
    """paths: their count; length: their total length (px); long_share: the share of that length in
    paths at least ``long_stroke`` px long (1 when there are none)."""
    lengths = np.array([np.linalg.norm(np.diff(np.asarray(p, float), axis=0), axis=1).sum() for p in polylines])
    total = float(lengths.sum())
    long = float(lengths[lengths >= long_stroke].sum())
    return {"paths": len(lengths), "length": total, "long_share": long / total if total > 0 else 1.0}


def _srgb_hex(colour) -> str:
    """A linear RGB colour as SVG's #rrggbb (sRGB encoded)."""
    srgb = linear_to_srgb(np.clip(np.asarray(colour, np.float64), 0, 1))
    return "#" + "".join(f"{int(round(c * 255)):02x}" for c in srgb)


def _path_data(line: np.ndarray, smooth: bool) -> str:
    """An SVG path's ``d``: straight segments, or with ``smooth`` the line simplified by
    Douglas–Peucker within SMOOTH_TOLERANCE px (a mesh's zero crossings zigzag at the pixel scale)
    and the uniform Catmull–Rom spline through the points kept, as cubic Béziers (controls
    P1 + (P2 − P0)/6 and P2 − (P3 − P1)/6; a closed line wraps round, an open one repeats its ends)."""
    from skimage.measure import approximate_polygon

    pts = np.asarray(line, np.float64)
    if smooth:
        pts = approximate_polygon(pts, SMOOTH_TOLERANCE)
    if not smooth or len(pts) < 3:
        return "M" + " L".join(f"{x:.2f},{y:.2f}" for x, y in pts)
    closed = len(pts) > 3 and np.linalg.norm(pts[0] - pts[-1]) < 1e-9
    if closed:
        ring = pts[:-1]
        padded = np.concatenate([ring[-1:], ring, ring[:2]])
    else:
        padded = np.concatenate([pts[:1], pts, pts[-1:]])
    parts = [f"M{padded[1][0]:.2f},{padded[1][1]:.2f}"]
    for k in range(1, len(padded) - 2):
        p0, p1, p2, p3 = padded[k - 1 : k + 3]
        c1, c2 = p1 + (p2 - p0) / 6, p2 - (p3 - p1) / 6
        parts.append(f"C{c1[0]:.2f},{c1[1]:.2f} {c2[0]:.2f},{c2[1]:.2f} {p2[0]:.2f},{p2[1]:.2f}")
    return " ".join(parts) + (" Z" if closed else "")


def write_svg(path: str | os.PathLike, size, layers: dict[str, Layer], smooth: bool = False) -> Path:
    """layers: line type → :class:`Layer`, drawn in this order, each a ``<g>`` with the type as its
    id (an Inkscape layer). Polylines as ``<polyline>``, or with ``smooth`` as curved ``<path>``s
    (:func:`_path_data`). Written atomically."""
    w, h = size
    parts = [
        '<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" '
        f'width="{w}" height="{h}" viewBox="0 0 {w} {h}">',
        f'<rect width="{w}" height="{h}" fill="white"/>',
    ]
    for name, layer in layers.items():
        parts.append(
            f'<g id={quoteattr(name)} inkscape:groupmode="layer" inkscape:label={quoteattr(name)} fill="none" '
            f'stroke="{_srgb_hex(layer.colour)}" stroke-width="{layer.width:g}" '
            'stroke-linecap="round" stroke-linejoin="round">'
        )
        opacities = layer.opacities or [1.0] * len(layer.polylines)
        for line, opacity in zip(layer.polylines, opacities):
            faded = f' stroke-opacity="{opacity:.3g}"' if opacity < 1 else ""
            if smooth:
                parts.append(f'<path d="{_path_data(line, True)}"{faded}/>')
            else:
                pts = " ".join(f"{x:.2f},{y:.2f}" for x, y in line)
                parts.append(f'<polyline points="{pts}"{faded}/>')
        parts.append("</g>")
    parts.append("</svg>\n")
    p = Path(path)
    with atomic_output(p) as tmp:
        Path(tmp).write_text("\n".join(parts), encoding="utf-8")
    return p


def _rasterised(polylines, shape) -> np.ndarray:
    """The pixels (H, W) bool the polylines pass through (their segments drawn one pixel wide)."""
    from skimage.draw import line as draw_line

    h, w = shape
    mask = np.zeros(shape, bool)
    for p in polylines:
        ij = np.round(np.asarray(p)[:, ::-1] - 0.5).astype(int)
        for (r0, c0), (r1, c1) in zip(ij[:-1], ij[1:]):
            rr, cc = draw_line(r0, c0, r1, c1)
            keep = (rr >= 0) & (rr < h) & (cc >= 0) & (cc < w)
            mask[rr[keep], cc[keep]] = True
    return mask


def _faded(lines, strength: np.ndarray, levels: int = FADE_LEVELS):
    """Each polyline split where the fade (``strength`` (H, W) in [0, 1], read at its points)
    crosses one of ``levels`` opacity levels; returns (polylines, opacities)."""
    h, w = strength.shape
    out, opacity = [], []
    for line in lines:
        xi = np.clip(line[:, 0].astype(int), 0, w - 1)
        yi = np.clip(line[:, 1].astype(int), 0, h - 1)
        level = np.clip(np.ceil(strength[yi, xi] * levels), 1, levels)
        cuts = np.flatnonzero(np.diff(level)) + 1
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(line)]):
            piece = line[max(a - 1, 0) : b]  # shares a point with the piece before
            if len(piece) >= 2:
                out.append(piece)
                opacity.append(float(level[a]) / levels)
    return out, opacity


def _page_width(kind: str, params: LineParams, style: LineStyle, traced_from_pixels: bool) -> float:
    """A stroke's width (output px) as the PNG page draws it: a line of ``w`` page pixels (an
    object-space line its type's width, a traced line 1) widened by a disk of style.width × s page
    pixels and reduced by s (lines.style): (w + s·style.width − 1) / s."""
    s = style.supersample
    drawn = 1.0 if traced_from_pixels else params.width(kind)
    return (drawn + s * style.width - 1) / s


def drawing_groups(drawing, params: LineParams, style: LineStyle = LineStyle()) -> dict[str, Layer]:
    """The strokes of a :class:`~illusio.lines.drawing.Drawing` per line type, ready for
    :func:`write_svg`, in pixels of the output: ``drawing`` is the page the PNG is made from, drawn
    at ``style.supersample`` × the output size, so the SVG holds the PNG's lines. Object-space lines
    clipped by visibility; image-space lines (hybrid ridges, image silhouettes) traced from their
    pixels; ridge pixels within a stroke of a silhouette left out (a silhouette is drawn once); each
    type's pieces joined by :func:`join_polylines` within ``style.svg_join``. A stroke is as wide
    as the PNG draws it (:func:`_page_width`), in ``style.colour`` when given; with ``style.fade``
    the ridges are split into FADE_LEVELS opacities."""
    from scipy import ndimage

    scale = style.supersample
    depth = drawing.q_t1[..., 3]
    traced = {k: visible_polylines(s, drawing.view, drawing.size, depth) for k, s in drawing.segments.items()}
    if "silhouettes" in params.lines and params.silhouette_space == "image":
        traced["silhouettes"] = trace_polylines(image_silhouettes(depth, params.depth_jump))
    ridges = drawing.ridge_mask
    if ridges is not None:
        if traced.get("silhouettes"):
            covered = _rasterised(traced["silhouettes"], ridges.shape)
            reach = scale * ((_page_width("silhouettes", params, style, False) + style.width) / 2 + REACH_MARGIN)
            ridges = ridges & (ndimage.distance_transform_edt(~covered) > reach)
        traced = {"apparent-ridges": trace_polylines(ridges), **traced}
    pixel_lines = {"apparent-ridges"} | ({"silhouettes"} if params.silhouette_space == "image" else set())
    layers = {}
    for kind, lines in traced.items():
        lines = join_polylines(lines, style.svg_join * scale)
        opacities = None
        if kind == "apparent-ridges" and style.fade:
            lines, opacities = _faded(lines, ridge_strength(drawing.q_t1, drawing.ridge_mask))
        lines = [line / scale for line in lines]
        colour = style.colour if style.colour is not None else params.colour(kind)
        layers[kind] = Layer(
            lines, colour, _page_width(kind, params, style, traced_from_pixels=kind in pixel_lines), opacities
        )
    return layers


def write_drawing_svg(path: str | os.PathLike, drawing, params: LineParams, style: LineStyle = LineStyle()) -> int:
    """Write ``drawing`` (made at ``style.supersample`` × the output size) as an SVG (atomically) in
    ``style``; returns the number of paths."""
    layers = drawing_groups(drawing, params, style)
    size = tuple(n // style.supersample for n in drawing.size)
    write_svg(path, size, layers, smooth=style.svg_smooth)
    return sum(len(layer.polylines) for layer in layers.values())
