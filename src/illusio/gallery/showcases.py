"""The showcases ``illusio demo`` runs, in order. A technique adds its own here when it lands."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from ..core.context import Context
from ..core.images import write_image
from ..core.renderer import Frame
from ..passes.scene_renderer import SceneRenderer
from ..scene.builtin import SCENES, SHAPES, builtin_scene, shape, turntable
from .html import Item, Section
from .viewer import viewer_showcase

__all__ = ["SHOWCASES", "builtin_scenes", "builtin_shapes"]


def builtin_scenes(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    """Every built-in scene through each of its cameras."""
    renderer = SceneRenderer(ctx)
    section = Section(
        "Built-in scenes",
        "Procedural scenes rendered with the shared core: G-buffer, cube shadow maps, "
        "Lambert + Phong shading from point and rectangular area lights.",
    )
    for name in SCENES:
        scene = builtin_scene(name)
        renderer.prepare(scene)
        for cam_name, view in scene.cameras.items():
            t0 = time.perf_counter()
            img = renderer.render(Frame(view, size))
            ms = (time.perf_counter() - t0) * 1000
            rel = f"scenes/{name}-{cam_name}.png"
            write_image(out_dir / rel, img)
            tris = renderer.gpu_scene.triangle_count
            section.items.append(
                Item(
                    rel,
                    f"{name} — camera '{cam_name}'",
                    f"{len(scene.nodes)} nodes, {tris:,} triangles, {len(scene.lights)} lights; "
                    f"{size[0]}×{size[1]} in {ms:.0f} ms on {ctx.info()['renderer']}",
                    command=f"illusio render {name} --camera {cam_name} --size {size[0]}x{size[1]} -o {name}.png",
                )
            )
    return section


def builtin_shapes(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    """Each procedural shape on the turntable."""
    renderer = SceneRenderer(ctx)
    section = Section("Built-in shapes", "Procedural meshes (no data files), each on the turntable scene.")
    small = (max(1, size[0] // 2), max(1, size[1] // 2))
    for name in SHAPES:
        scene = turntable(shape(name))
        renderer.prepare(scene)
        img = renderer.render(Frame(None, small))
        rel = f"shapes/{name}.png"
        write_image(out_dir / rel, img)
        m = scene.node("subject").mesh
        section.items.append(
            Item(
                rel,
                name,
                f"{len(m.vertices):,} vertices, {len(m.faces):,} triangles",
                command=f"illusio render {name} --size {small[0]}x{small[1]} -o {name}.png",
            )
        )
    return section


def _showcases() -> list[tuple[str, Callable[[Context, Path, tuple[int, int]], Section]]]:
    """The core's scenes and shapes, each technique's section (core.technique: ``showcase``) in the
    registry's order, then the viewer's camera paths."""
    from ..core.technique import techniques

    own = [(t.name, t.showcase_function()) for t in techniques().values() if t.showcase]
    return [("scenes", builtin_scenes), ("shapes", builtin_shapes)] + own + [("viewer", viewer_showcase)]


SHOWCASES: list[tuple[str, Callable[[Context, Path, tuple[int, int]], Section]]] = _showcases()
