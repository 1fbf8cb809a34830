"""SVG strokes (issue 46): for each built-in shape and the test meshes, the default line drawing's
strokes as traced pieces (visible object-space polylines and the ridge pixels traced, as the SVG held
them before chaining) and as written (:func:`illusio.lines.svg.drawing_groups`: silhouettes drawn
once, ends within 1.5 px chained): paths per drawing, and the share of the total length in paths of
at least 50 px. Each written SVG is rendered by resvg (when resvg-py is installed) and its lines
scored against the PNG's (lines.compare: precision, recall, F1 within 2 px, a pixel a line at a
quarter of ink), and the time of the
SVG's strokes beside the time of the page they are traced from (both at the command's default 2×
antialiasing, lengths in output pixels)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from illusio.core.context import Context
from illusio.core.renderer import Frame
from illusio.lines.compare import line_mask, score
from illusio.lines.drawing import LineRenderer, framing_view
from illusio.lines.params import LineParams
from illusio.lines.style import LineStyle, stylise
from illusio.lines.svg import drawing_groups, stroke_statistics, trace_polylines, visible_polylines, write_svg
from illusio.scene.builtin.shapes import SHAPES, shape
from illusio.scene.mesh import load_mesh

from .runner import Timing

MODELS = Path(
    os.environ.get("ILLUSIO_MODELS", Path(__file__).resolve().parents[1].parent / "shared" / "data" / "models")
)
MESHES = ("stanford-bunny.obj", "spot.obj", "fandisk.off", "rocker-arm.obj")
SIZE = (1024, 1024)  # the lines command's default
#: a pixel counts as a line pixel at a quarter of ink (luminance under 0.75): the PNG's 1-px traced
#: ridges are half-covered pixels after its 2× reduction, on either side of 0.5
INK_LEVEL = 0.75
ANTIALIAS = 2  # the lines command's default page


def traced_pieces(drawing, params: LineParams) -> list:
    """Every stroke as the SVG writer traced it before chaining: each type's visible object-space
    polylines and the hybrid ridge pixels traced whole."""
    depth = drawing.q_t1[..., 3]
    pieces = [p for s in drawing.segments.values() for p in visible_polylines(s, drawing.view, drawing.size, depth)]
    if drawing.ridge_mask is not None:
        pieces += trace_polylines(drawing.ridge_mask)
    return pieces


def svg_image(path: Path) -> np.ndarray | None:
    """The SVG rendered by resvg, linear RGB float (H, W, 3), or None without resvg-py."""
    try:
        import resvg_py
    except ImportError:
        return None
    import io

    from PIL import Image

    from illusio.core.images import srgb_to_linear

    png = bytes(resvg_py.svg_to_bytes(svg_path=str(path), background="#ffffff"))
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), np.float32) / 255
    return srgb_to_linear(rgb)


def subjects(quick: bool) -> dict:
    names = ("blob", "torus-knot") if quick else tuple(SHAPES)
    out = {name: (lambda n=name: shape(n)) for name in names}
    if not quick:
        for file in MESHES:
            if (MODELS / file).exists():
                out[Path(file).stem] = lambda f=file: load_mesh(MODELS / f)
    return out


def measure(ctx: Context, name: str, mesh, folder: Path) -> dict:
    params, style = LineParams(), LineStyle(supersample=ANTIALIAS)
    renderer = LineRenderer(ctx)
    try:
        renderer.prepare(mesh)
        view = framing_view(mesh)
        t0 = time.perf_counter()
        page = renderer.drawing(Frame(view, (SIZE[0] * ANTIALIAS, SIZE[1] * ANTIALIAS)), params)
        page_ms = (time.perf_counter() - t0) * 1000
        png = stylise(page.image, style)
        t0 = time.perf_counter()
        layers = drawing_groups(page, params, style)
        chain_ms = (time.perf_counter() - t0) * 1000
    finally:
        renderer.release()
    before = stroke_statistics([p / ANTIALIAS for p in traced_pieces(page, params)])
    after = stroke_statistics([p for layer in layers.values() for p in layer.polylines])
    row = {
        "paths before": before["paths"],
        "paths after": after["paths"],
        "long share before": before["long_share"],
        "long share after": after["long_share"],
        "length after / before": after["length"] / max(before["length"], 1e-9),
        "chaining ms": chain_ms,
        "page drawing ms": page_ms,
    }
    svg = write_svg(folder / f"{name}.svg", SIZE, layers)
    rendered = svg_image(svg)
    if rendered is not None:
        s = score(line_mask(rendered, INK_LEVEL), line_mask(png, INK_LEVEL), tolerance=2.0)
        row.update({"SVG vs PNG precision": s.precision, "SVG vs PNG recall": s.recall, "SVG vs PNG F1": s.f1})
    return row


def run(ctx: Context, repeat: int, quick: bool = False) -> tuple[list[Timing], dict[str, float]]:
    import tempfile

    rows = {}
    with tempfile.TemporaryDirectory(prefix="illusio-svg-bench-") as tmp:
        for name, make in subjects(quick).items():
            rows[name] = measure(ctx, name, make(), Path(tmp))
    timings = [
        Timing(f"svg/{name}: chaining", 1, row["chaining ms"], row["chaining ms"], row["chaining ms"], "")
        for name, row in rows.items()
    ]
    ratios = {f"{name}: {key}": float(value) for name, row in rows.items() for key, value in row.items()}
    for key in ("paths before", "paths after"):
        ratios[f"all: {key}"] = float(sum(row[key] for row in rows.values()))
    ratios["all: smallest long share after"] = min(row["long share after"] for row in rows.values())
    drawn = [row for row in rows.values() if row["paths after"] > 0]  # the box draws no line at the defaults
    if drawn and all("SVG vs PNG F1" in row for row in drawn):
        ratios["all: smallest SVG vs PNG F1"] = min(row["SVG vs PNG F1"] for row in drawn)
    return timings, ratios
