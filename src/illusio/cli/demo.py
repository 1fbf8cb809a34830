"""illusio demo: run every showcase and write a gallery (index.html) of the results."""

from __future__ import annotations

import time
from pathlib import Path

import typer

from .common import parse_size, progress


def demo(
    out: Path = typer.Option(Path("demo-out"), "--out", help="folder for the images and index.html"),
    size: str = typer.Option("960x600", "--size", help="WIDTHxHEIGHT of the scene images"),
    only: str = typer.Option(None, "--only", help="comma-separated showcase names (default: all)"),
) -> None:
    """Render the built-in showcases and write OUT/index.html, a line for each as it starts and ends."""
    from ..core.context import Context
    from ..core.errors import InputError
    from ..gallery import SHOWCASES, traced, write_gallery

    w, h = parse_size(size)
    chosen = SHOWCASES
    if only:
        names = [n.strip() for n in only.split(",") if n.strip()]
        unknown = set(names) - {n for n, _ in SHOWCASES}
        if unknown:
            raise InputError(
                f"--only: unknown showcase(s) {', '.join(sorted(unknown))}; "
                f"choose from {', '.join(n for n, _ in SHOWCASES)}"
            )
        chosen = [(n, f) for n, f in SHOWCASES if n in names]
    ctx = Context()
    sections = []
    t0 = time.perf_counter()
    try:
        # a counted phase: a bar with its ETA on a terminal (the demo takes minutes), beside the lines
        with progress(len(chosen), "demo: showcases") as advance:
            for k, (name, showcase) in enumerate(chosen, 1):
                typer.echo(f"demo: [{k}/{len(chosen)}] {name} ...")
                t = time.perf_counter()
                made = traced.renders_made()
                sections.append(showcase(ctx, out, (w, h)))
                made_here = traced.renders_made() - made
                typer.echo(
                    f"demo: [{k}/{len(chosen)}] {name}: {len(sections[-1].items)} images in "
                    f"{time.perf_counter() - t:.1f} s" + (f" ({made_here} path-traced)" if made_here else "")
                )
                advance()
    finally:
        traced.clear()
    renderer = ctx.info()["renderer"]
    page = write_gallery(
        out,
        "illusio — demo gallery",
        sections,
        footer=f"Rendered on {renderer} in {time.perf_counter() - t0:.1f} s by `illusio demo`.",
    )
    n = sum(len(s.items) for s in sections)
    typer.echo(f"wrote {n} images and {page}")
