"""The depth-of-field showcase: the museum focused on one exhibit by each method, the circle of
confusion map and the planes beside them, a table of each method's error against the accumulation
reference and its time, an anaglyph of the stereo pair (one focus for both eyes), Figure 11's
scenario as a stereo video, and Figure 12's museum walk with automatic focus."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..core.renderer import Frame
from ..core.scores import psnr
from ..dof.focus import object_distance
from ..dof.params import DofParams
from ..dof.reference import plane_index
from ..dof.renderer import DofRenderer
from ..scene.builtin import builtin_scene
from .figures import pyplot, save_figure
from .html import Item, Section, Table

#: the paper the figures below are from
PAPER = "Piranda & de Sorbier, "

__all__ = ["dof_showcase"]


def dof_showcase(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    section = Section(
        "Stereoscopic depth of field (Piranda & de Sorbier)",
        "A thin-lens eye focused on one exhibit of the museum: what is far from the focal plane is "
        "blurred, so it draws the eye less and its large disparities tire it less. Every method is "
        "scored against the accumulation reference.",
    )
    scene = builtin_scene("museum")
    view = scene.camera()
    renderer = DofRenderer(ctx)
    renderer.prepare(scene)
    frame = Frame(view, size)
    base = DofParams(
        focus_distance=object_distance(scene, "exhibit-superquadric", view), aperture_mm=120.0, max_coc=16.0
    )
    reference = renderer.render(frame, replace(base, method="accumulation", samples=64))
    write_image(out_dir / "dof/museum-accumulation.png", reference)
    section.items.append(
        Item(
            "dof/museum-accumulation.png",
            f"accumulation (the reference), focus on the blue "
            f"superquadric at {base.focus_distance:.2f} m, aperture {base.aperture_mm:g} mm",
            "64 lens positions averaged",
            command=f"illusio dof museum --focus-object exhibit-superquadric --size {size[0]}x{size[1]} "
            "-o accumulation.png",
            params=replace(base, method="accumulation", samples=64),
            derived=FOCUS_SET_BY_OBJECT,
        )
    )
    rows = []
    for method in ("gather", "mipmap", "planes"):
        params = replace(base, method=method)
        renderer.render(frame, params)  # compiled and warm
        t0 = time.perf_counter()
        image = renderer.render(frame, params)
        ms = (time.perf_counter() - t0) * 1000
        rows.append((method, f"{psnr(image, reference):.1f} dB", f"{ms:.0f} ms"))
        write_image(out_dir / f"dof/museum-{method}.png", image)
        section.items.append(
            Item(
                f"dof/museum-{method}.png",
                method,
                "PSNR and time in the table above",
                figure=PAPER + ("section 3.2" if method.startswith("planes") else "section 2"),
                command=f"illusio dof museum --focus-object exhibit-superquadric --size {size[0]}x{size[1]} "
                f"-o {method}.png",
                params=params,
                derived=FOCUS_SET_BY_OBJECT,
            )
        )
    section.tables.append(
        Table(
            f"Against the accumulation reference, {size[0]}×{size[1]}, {ctx.info()['renderer']}",
            ["method", "PSNR (sRGB)", "time"],
            [list(r) for r in rows],
        )
    )
    maps = {k: ctx.readback(renderer.maps()[k])[..., 0] for k in ("coc", "depth")}
    write_image(out_dir / "dof/museum-coc.png", np.clip(maps["coc"] / base.max_coc, 0, 1), srgb=False)
    section.items.append(
        Item(
            "dof/museum-coc.png",
            f"circle of confusion (black: in focus; white: the largest drawn, {base.max_coc:g} px)",
            "dof.lens: A·|1/d − 1/d_f|·H / (2 tan(fov/2))",
            command="illusio dof museum --focus-object exhibit-superquadric --debug coc -o coc.png",
            params=base,
            derived=FOCUS_SET_BY_OBJECT,
        )
    )
    distances = renderer.result().planes
    write_image(
        out_dir / "dof/museum-planes-debug.png",
        plane_index(maps["depth"], distances) / (len(distances) - 1),
        srgb=False,
    )
    section.items.append(
        Item(
            "dof/museum-planes-debug.png",
            "the planes each pixel takes, in grey levels",
            figure=PAPER + "Figure 8",
            command="illusio dof museum --focus-object exhibit-superquadric --debug planes -o planes.png",
            params=base,
            derived=FOCUS_SET_BY_OBJECT,
            details=f"{base.planes_behind} behind, {base.planes_front} in front of the focal plane, "
            f"{base.distribution} spreading",
        )
    )
    section.items.append(_table(out_dir / "dof/methods.png", rows, f"{size[0]}×{size[1]}, {ctx.info()['renderer']}"))
    anaglyph_params = replace(base, stereo="anaglyph", method="planes")
    anaglyph = renderer.render(frame, anaglyph_params)
    write_image(out_dir / "dof/museum-anaglyph.png", anaglyph)
    section.items.append(
        Item(
            "dof/museum-anaglyph.png",
            "the stereo pair as a red-cyan anaglyph (Dubois)",
            "one focus for both eyes; zero parallax at the focus distance",
            command="illusio dof museum -o m.png --focus-object exhibit-superquadric",
            params=anaglyph_params,
            derived=FOCUS_SET_BY_OBJECT,
        )
    )
    renderer.release()
    section.items.append(_scenario_video(ctx, out_dir, size))
    section.items.append(_museum_walk(ctx, out_dir, size))
    return section


def _table(path: Path, rows, note: str) -> Item:
    """The methods' scores as a small table image."""
    plt = pyplot()

    fig, ax = plt.subplots(figsize=(5.0, 0.5 + 0.35 * len(rows)), dpi=120)
    ax.axis("off")
    table = ax.table(
        cellText=[list(r) for r in rows], colLabels=["method", "PSNR vs reference (sRGB)", "time"], loc="center"
    )
    table.scale(1, 1.4)
    save_figure(fig, path, tight=True)
    return Item(f"dof/{path.name}", "every method against the accumulation reference", note)


def _museum_walk(ctx: Context, out_dir: Path, size: tuple[int, int], fps: float = 8.0) -> Item:
    """Figure 12: a walk through the museum with the focus on the exhibit nearest the visitor."""
    from ..core.images import VideoWriter
    from ..viewer.path import CameraPath, Keyframe

    scene = builtin_scene("museum")
    path = CameraPath(
        [
            Keyframe(0.0, (-4.5, 1.7, 4.5), (-3.4, 1.2, -2.2)),
            Keyframe(2.5, (-1.0, 1.7, 3.5), (-1.7, 1.2, 1.0)),
            Keyframe(5.0, (2.5, 1.7, 3.5), (1.7, 1.2, 1.0)),
            Keyframe(7.5, (4.5, 1.7, 0.5), (3.4, 1.3, -2.2)),
        ]
    )
    renderer = DofRenderer(ctx)
    renderer.prepare(scene)
    params = DofParams(method="planes", policy="nearest-exhibit", aperture_mm=150.0, max_coc=16.0)
    small = (max(64, size[0] // 2), max(36, size[1] // 2))
    count = int(path.duration * fps) + 1
    with VideoWriter(out_dir / "dof/museum-walk.mp4", fps) as video:
        for i in range(count):
            t = i / fps
            video.append(renderer.render(Frame(path.view(t, scene.camera().camera), small, t, i), params))
    renderer.release()
    return Item(
        "dof/museum-walk.mp4",
        "a museum walk, the focus on the exhibit nearest the visitor",
        figure=PAPER + "Figure 12",
        details=f"policy nearest-exhibit, accommodation {params.accommodation:g} s; {count} frames at {fps:g} fps",
    )


#: Figure 11 as docs/commands.md and the gallery give it: the paper's planes, an aperture that shows the blur
FIGURE_11_APERTURE = 500.0
FIGURE_11_PARAMS = DofParams(method="planes", aperture_mm=FIGURE_11_APERTURE, stereo="anaglyph")
FIGURE_11_ITEM = Item(
    "dof/futuristic-scenario.mp4",
    "the scenario (dof/scenarios/futuristic.txt) as a red-cyan anaglyph",
    figure=PAPER + "Figure 11",
    command="illusio dof futuristic --scenario futuristic --video fig11.mp4",
    params=FIGURE_11_PARAMS,
)
FIGURE_11_COMMAND = FIGURE_11_ITEM.command_line

#: the dof command sets the focus distance from --focus-object (an exhibit's distance from the camera)
FOCUS_SET_BY_OBJECT = ("focus_distance",)


def _scenario_video(ctx: Context, out_dir: Path, size: tuple[int, int], fps: float = 8.0) -> Item:
    """Figure 11: the shipped scenario on the futuristic scene, as an anaglyph video whose focus
    follows the script (the ship, the robot when it fires, the projectile, the ship again)."""
    from ..core.images import VideoWriter
    from ..dof.scenario import load_scenario, shipped_scenario
    from ..dof.timeline import ScenarioPlayer

    scene = builtin_scene("futuristic")
    player = ScenarioPlayer(load_scenario(shipped_scenario("futuristic")), scene)
    view = scene.camera()
    renderer = DofRenderer(ctx)
    params = FIGURE_11_PARAMS
    small = (max(64, size[0] // 2), max(36, size[1] // 2))
    count = int(player.loop * fps)
    focuses, largest = [], 0.0
    with VideoWriter(out_dir / "dof/futuristic-scenario.mp4", fps) as video:
        for i in range(count):
            t = i / fps
            player.apply(scene, t)
            renderer.prepare(scene)
            focus = player.focus_distance(view, t)
            video.append(
                renderer.render(
                    Frame(view, small, t, i), replace(params, focus_distance=focus or params.focus_distance)
                )
            )
            focuses.append(renderer.result().focus_distance)
            largest = max(largest, float(ctx.readback(renderer.maps()["coc"]).max()))
    renderer.release()
    return replace(
        FIGURE_11_ITEM,
        details=f"the paper's planes; the focus follows the script (ship, robot when it fires, projectile, ship) "
        f"between {min(focuses):.1f} and {max(focuses):.1f} m; circles of confusion up to {largest:.0f} px "
        f"at {small[0]}×{small[1]}; {count} frames at {fps:g} fps",
    )
