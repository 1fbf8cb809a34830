"""The autostereogram showcase: Figure 20 (separation against depth, exact and linear), Figure 28
(depth, random-dot and texture stereograms), the four algorithms with their self-check scores, the
multi-scene TV of Figure 23 (still and animated), the textured wall of Figure 24 and the interaction
mode of Figure 25."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image, write_video
from ..core.renderer import Frame
from ..scene import builtin_scene
from ..scene.builtin import shape, textures
from ..sis.decode import check
from ..sis.depth import depth_from_scene, hidden_scene
from ..sis.multiscene import MultiSceneParams, MultiSceneRenderer, MultiSceneSubject
from ..sis.params import ALGORITHMS, StereogramParams
from ..sis.physics import Screen, depth_range, linear_depth_error, separation_px
from ..sis.reference import separation
from ..sis.stereogram import StereogramRenderer
from .figures import pyplot, save_figure
from .html import Item, Section, Table

#: the paper every figure below is from
PAPER = "Dehos et al. 2014, "

__all__ = ["sis_showcase"]


def sis_showcase(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    section = Section(
        "Autostereograms (Dehos et al. 2014)",
        "Focus behind the screen (wall-eyed) until the two guide dots fuse into one: the hidden shape appears.",
    )
    w, h = size
    scale = w / 1920
    section.items.append(separation_plot(out_dir, "sis/figure-20.png"))
    item, table = linear_error_plot(out_dir, "sis/linear-error.png")
    section.items.append(item)
    section.tables.append(table)
    sis = StereogramRenderer(ctx)
    depth = depth_from_scene(ctx, hidden_scene(shape("torus-knot")), (w, h))
    sis.prepare(depth)
    write_image(out_dir / "sis/depth.png", 1.0 - depth)
    section.items.append(
        Item("sis/depth.png", "depth map", "rendered torus knot, white = near", figure=PAPER + "Figure 28")
    )
    # rounded so that the caption's options are the values themselves
    base = StereogramParams(
        strip_width=round(max(2.0, 100 * scale), 1), depth_factor=round(max(1.0, 50 * scale), 1), guides=True
    )
    texture_path = out_dir / "sis/planks-texture.png"
    write_image(texture_path, textures.planks(256, 3, 5))  # the wallpaper stripes are too faint to fuse
    section.items.append(Item("sis/planks-texture.png", "the pattern the texture stereogram repeats", "planks, 256 px"))
    for name, params in (
        ("random-dot", base),
        ("texture", StereogramParams(**{**base.__dict__, "pattern": str(texture_path)})),
    ):
        img = sis.render(Frame(size=(w, h)), params)
        rel = f"sis/{name}.png"
        write_image(out_dir / rel, img)
        pattern = " --pattern planks-texture.png" if name == "texture" else ""
        section.items.append(
            Item(
                rel,
                f"{name} stereogram",
                f"fast GPU pass, W_s = {params.strip_width:.0f}, β = {params.depth_factor:.0f} px",
                figure=PAPER + "Figure 28",
                command=f"illusio sis torus-knot -o {name}.png --size {w}x{h}{pattern}",
                params=params,
                derived=("pattern",),
            )
        )
    sep = separation(depth, base.strip_width, base.depth_factor)
    checks = Table(
        "Self-check: each algorithm's stereogram decoded back (window matching) against the separations "
        "it was made from",
        ["algorithm", "within 1 px", "pixels checked", "mean error (px)"],
        [],
    )
    section.tables.append(checks)
    halves = {}
    for algorithm in ALGORITHMS:
        params = StereogramParams(**{**base.__dict__, "algorithm": algorithm, "guides": False})
        img = sis.render(Frame(size=(w, h)), params)
        anchor = "centre" if algorithm == "symmetric" else "left"
        report = check(img, sep, int(params.far_separation + 0.5), anchor)
        halves[algorithm] = [
            check(img, sep, int(params.far_separation + 0.5), anchor, columns=columns).matched
            for columns in ((0, w // 2), (w // 2, w))
        ]
        rel = f"sis/algorithm-{algorithm}.png"
        write_image(out_dir / rel, img)
        section.items.append(
            Item(
                rel,
                f"{algorithm} algorithm",
                "self-check in the table above",
                figure=PAPER + "Algorithm 1",
                command=f"illusio sis torus-knot -o {algorithm}.png --size {w}x{h}",
                params=params,
            )
        )
        checks.rows.append([algorithm, f"{report.matched:.1%}", f"{report.checked:,}", f"{report.mean_error:.3f}"])
    section.items.append(bias_plot(out_dir, "sis/left-right.png", halves, sep, base.strip_width, base.depth_factor))
    scene = builtin_scene("living-room")
    multi = MultiSceneRenderer(ctx)
    hidden = hidden_scene(shape("torus-knot"))
    multi.prepare(MultiSceneSubject(scene, hidden))
    for camera in ("tv", "main"):
        img = multi.render(Frame(scene.camera(camera), (w, h), index=1), MultiSceneParams())
        rel = f"sis/tv-{camera}.png"
        write_image(out_dir / rel, img)
        section.items.append(
            Item(
                rel,
                f"TV snow hiding a torus knot ('{camera}' camera)",
                "stereogram computed in screen space, shown as the TV's glow",
                figure=PAPER + "Figure 23",
                command=f"illusio sis-scene living-room --camera {camera} -o tv.png --size {w}x{h}",
                params=MultiSceneParams(),
            )
        )
        d = ctx.readback(multi.maps()["depth"])[..., 0]
        write_image(out_dir / f"sis/tv-{camera}-depth.png", np.where(d >= 0, 1.0 - d, 0.0))
        section.items.append(
            Item(
                f"sis/tv-{camera}-depth.png",
                "its screen-space depth",
                "white = near, black = off the TV",
                figure=PAPER + "Figure 22, step 2",
            )
        )
    frames = []
    spinning = MultiSceneParams(spin=15.0)
    for f in range(24):  # the snow changes and the hidden knot turns every frame
        frames.append(multi.render(Frame(scene.camera("tv"), (w // 2, h // 2), f / 24, f), spinning))
    write_video(out_dir / "sis/tv-animated.gif", frames)
    section.items.append(
        Item(
            "sis/tv-animated.gif",
            "animated snow and a turning hidden knot",
            figure=PAPER + "section 4.3",
            command="illusio sis-scene living-room --camera tv --frames 24 --video tv.gif -o tv.png "
            f"--size {w // 2}x{h // 2}",
            params=spinning,
            details="24 frames, 15° per frame; each frame's stereogram is recomputed from the new depth and snow",
        )
    )
    wall_texture = out_dir / "sis/wall-texture.png"
    write_image(
        wall_texture,
        textures.value_noise(256, 32, seed=4)[..., None] * np.array([0.55, 0.45, 0.35]) + np.array([0.35, 0.3, 0.25]),
    )
    section.items.append(
        Item("sis/wall-texture.png", "the wall's own texture, the pattern of its stereogram", "value noise, 256 px")
    )
    wall = MultiSceneParams(
        host="back-wall",
        stereogram=StereogramParams(pattern=str(wall_texture), strip_width=100, depth_factor=40),
        emission=0.0,
    )
    multi.prepare(MultiSceneSubject(scene, hidden_scene(shape("torus"))))
    img = multi.render(Frame(scene.camera("main"), (w, h), index=1), wall)
    write_image(out_dir / "sis/wall.png", img)
    section.items.append(
        Item(
            "sis/wall.png",
            "a texture stereogram as the wall behind the sofa",
            figure=PAPER + "Figure 24",
            command="illusio sis-scene living-room --camera main --hidden torus --pattern wall-texture.png "
            f"-o wall.png --size {w}x{h}",
            params=wall,
            derived=("stereogram.pattern",),
            details="the wall's mottled texture hides a torus; lit like any wall (no glow)",
        )
    )
    d = ctx.readback(multi.maps()["depth"])[..., 0]
    for name, host_shadows, what in (
        ("wall-shadowed", True, "shadows fall on the wall: their hard edges cut the repeats"),
        ("wall-unshadowed", False, "the room keeps its shadows, the wall is lit unshadowed"),
    ):
        lit = replace(wall, settings=replace(wall.settings, shadows=True), host_shadows=host_shadows)
        write_image(out_dir / f"sis/{name}.png", multi.render(Frame(scene.camera("main"), (w, h), index=1), lit))
        section.items.append(
            Item(
                f"sis/{name}.png",
                f"shadows {'on' if host_shadows else 'off'} the host",
                what,
                figure=PAPER + "section 6",
                command=f"illusio sis-scene living-room --camera main --hidden torus --pattern wall-texture.png "
                f"-o {name}.png --size {w}x{h}",
                params=lit,
                derived=("stereogram.pattern",),
            )
        )
    write_image(out_dir / "sis/wall-depth.png", np.where(d >= 0, 1.0 - d, 0.0))
    section.items.append(
        Item(
            "sis/wall-depth.png",
            "the wall's screen-space depth",
            "white = near, black = off the wall",
            figure=PAPER + "Figure 24 (bottom)",
        )
    )
    section.items.append(oblique_wall(ctx, multi, scene, out_dir, (w, h)))
    interactive = MultiSceneParams(
        host="rug",
        stereogram=StereogramParams(pattern="random-dot", strip_width=100, depth_factor=40),
        emission=0.0,
        interactive=True,
    )
    multi.prepare(MultiSceneSubject(scene, hidden))
    img = multi.render(Frame(scene.camera("main"), (w, h), index=1), interactive)
    write_image(out_dir / "sis/interactive-rug.png", img)
    section.items.append(
        Item(
            "sis/interactive-rug.png",
            "interaction mode on the rug",
            figure=PAPER + "Figure 25",
            command=f"illusio sis-scene living-room --camera main -o rug.png --size {w}x{h}",
            params=interactive,
            details="the hidden knot is seen from where the viewer stands relative to the rug",
        )
    )
    return section


#: a camera seeing the back wall at 45°: 3 m from the wall point (0.5, 1.35, −2.5)
OBLIQUE_CAMERA = "2.62,1.35,-0.38:0.5,1.35,-2.5"


def oblique_wall(ctx: Context, multi: MultiSceneRenderer, scene, out_dir: Path, size) -> Item:
    """The back wall seen at 45° hiding a sphere, through its uvs (left) and laid out in the
    viewer's image of the wall (right): the frames, and under them their screen-space depth."""
    from ..scene.camera import Pose, View

    eye, target = ([float(v) for v in part.split(",")] for part in OBLIQUE_CAMERA.split(":"))
    view = View(Pose(tuple(eye), tuple(target)), scene.camera("main").camera)
    multi.prepare(MultiSceneSubject(scene, hidden_scene(shape("sphere"))))
    frames, depths = [], []
    for layout in ("uv", "viewer"):
        params = MultiSceneParams(host="back-wall", emission=0.0, host_layout=layout)
        frames.append(np.clip(multi.render(Frame(view, size, index=1), params), 0, 1))
        d = ctx.readback(multi.maps()["depth"])[..., 0]
        depths.append(np.repeat(np.where(d >= 0, 1.0 - d, 0.3)[..., None], 3, axis=2))  # grey: off the wall
    gap = np.full((size[1], 6, 3), 0.5, np.float32)
    write_image(
        out_dir / "sis/oblique-wall.png",
        np.vstack(
            [
                np.hstack([frames[0], gap, frames[1]]),
                np.full((6, 2 * size[0] + 6, 3), 0.5, np.float32),
                np.hstack([depths[0], gap, depths[1]]).astype(np.float32),
            ]
        ),
    )
    w, h = size
    return Item(
        "sis/oblique-wall.png",
        "a wall seen at 45°: the hidden sphere through the wall's uvs (left) and laid "
        "out in the viewer's image of the wall (right)",
        "under each frame its screen-space depth (white = near, grey = off the wall): through the uvs the "
        "sphere is squeezed to "
        "cos 45° of its width; the viewer layout keeps it round (benchmarks/RESULTS.md: oblique hosts)",
        figure=PAPER + "Figure 27",
        command=f"illusio sis-scene living-room --camera {OBLIQUE_CAMERA} --hidden sphere -o wall45.png --size {w}x{h}",
        params=params,  # the viewer layout's, the right half
    )


def bias_plot(out_dir: Path, rel: str, halves: dict, sep: np.ndarray, strip_width: float, depth_factor: float) -> Item:
    """The sequential family's left-to-right bias (issue 20): each algorithm's fraction decoded in the
    left and the right half of the image, and where the hidden scene is seen (a fused pair at its
    middle: left-anchored stereograms show the near part half a separation left of the depth map)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 3.2), dpi=100)
    names = list(halves)
    x = np.arange(len(names))
    for k, (label, colour) in enumerate((("left half", "#4477aa"), ("right half", "#ee6677"))):
        values = [halves[n][k] for n in names]
        ax.bar(x + (k - 0.5) * 0.38, values, 0.36, label=label, color=colour)
        for xi, v in zip(x + (k - 0.5) * 0.38, values):
            ax.text(xi, v, f"{v:.4f}", ha="center", va="bottom", fontsize=7)
    ax.set_xticks(x, names)
    lowest = min(min(v) for v in halves.values())
    ax.set_ylim(max(0.0, lowest - 3 * (1.0 - lowest) - 0.002), 1.0 + 0.4 * (1.0 - lowest) + 0.001)
    ax.set_ylabel("decoded within 1 px")
    ax.legend(loc="lower left", fontsize=8)
    save_figure(fig, out_dir / rel)
    near = sep < strip_width + depth_factor / 2
    shift = float(sep[near].mean()) / 2 if near.any() else 0.0
    return Item(
        rel,
        "left-to-right bias: decoded per half, per algorithm",
        f"no accuracy bias between halves; the bias is where the scene is seen: sequential, fast and strip "
        f"show the near part {shift:.0f} px left of the depth map (half a separation), symmetric centred "
        f"(docs/decisions/0008: which to choose when; RESULTS: sis_quality)",
        figure=PAPER + "section 3.3",
    )


def separation_plot(out_dir: Path, rel: str, strip_width: float = 100.0, depth_factor: float = 50.0) -> Item:
    """Figure 20: separation e'_p against simulated depth f' (equation 3) for the default screen, with
    the linear map W_s + β·D over the depth range that (W_s, β) simulates, dashed."""
    plt = pyplot()

    screen = Screen()
    near, far = depth_range(strip_width, depth_factor, screen)
    depth = np.linspace(0.0, 400.0, 400)
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    ax.plot(depth, separation_px(depth, screen), label="equation (3), exact")
    ax.plot(
        [near, far],
        [strip_width, strip_width + depth_factor],
        "--",
        label=f"linear, W_s = {strip_width:g}, β = {depth_factor:g}",
    )
    ax.axhline(float(separation_px(1e9, screen)), color="grey", lw=0.8, label="e_p (f' → ∞)")
    ax.set_xlabel("simulated depth f' behind the screen (cm)")
    ax.set_ylabel("separation e'_p (px)")
    ax.set_title(f"{screen.diagonal_cm:g} cm screen, {screen.width_px} px wide, {screen.viewing_distance_cm:g} cm away")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    save_figure(fig, out_dir / rel)
    return Item(
        rel,
        "separation against depth",
        f"[W_s, W_s + β] = [{strip_width:g}, {strip_width + depth_factor:g}] px simulates f' ∈ [{near:.0f}, "
        f"{far:.0f}] cm",
        figure="Dehos et al. 2014, Figure 20",
    )


#: (W_s, β) pairs of the linear-approximation figure: the paper's example first
LINEAR_CASES = ((100.0, 50.0), (80.0, 40.0), (150.0, 50.0), (100.0, 100.0), (60.0, 120.0))


def linear_error_plot(out_dir: Path, rel: str) -> tuple[Item, Table]:
    """Beside Figure 20: how far the linear approximation (section 3.4) puts each depth, in cm,
    against D, for a few (W_s, β) on the default screen; and the worst error of each as a table."""
    plt = pyplot()

    screen = Screen()
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    rows = []
    for strip_width, depth_factor in LINEAR_CASES:
        d, error = linear_depth_error(strip_width, depth_factor, screen)
        near, far = depth_range(strip_width, depth_factor, screen)
        ax.plot(d, error, label=f"W_s = {strip_width:g}, β = {depth_factor:g} (f' {near:.0f}–{far:.0f} cm)")
        worst = int(np.argmin(error))
        rows.append(
            [
                f"{strip_width:g}",
                f"{depth_factor:g}",
                f"{near:.1f} – {far:.1f}",
                f"{-error[worst]:.1f}",
                f"{d[worst]:.2f}",
                f"{-error[worst] / (far - near) * 100:.1f} %",
            ]
        )
    ax.axhline(0, color="grey", lw=0.8)
    ax.set_xlabel("depth value D (0 = near)")
    ax.set_ylabel("f' linear − f' exact (cm)")
    ax.set_title("the linear approximation shows every point nearer")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    save_figure(fig, out_dir / rel)
    table = Table(
        f"The linear approximation's depth error (section 3.4) on the default screen ({screen.diagonal_cm:g} cm, "
        f"{screen.width_px} px, viewer {screen.viewing_distance_cm:g} cm away)",
        ["W_s (px)", "β (px)", "depth range f' (cm)", "worst error (cm nearer)", "at D", "of the range"],
        rows,
    )
    item = Item(
        rel,
        "the linear approximation's depth error",
        "f' seen with separations W_s + β·D against the depth D stands for (exact mode); table below",
        figure="Dehos et al. 2014, section 3.4 (beside Figure 20)",
        command="illusio sis torus-knot --exact -o exact.png",
    )
    return item, table
