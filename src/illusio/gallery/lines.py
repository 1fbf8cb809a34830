"""The line-drawing showcase: the line types side by side, the test meshes with default settings
(when ../shared/data/models or $ILLUSIO_MODELS holds them), the τ × λ grid, and the comparison with
Canny edges with its scores."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..core.renderer import Frame
from ..lines import compare as cmp
from ..lines.drawing import LineRenderer, framing_view
from ..lines.params import LineParams
from ..lines.tuning import parameter_grid
from ..scene.builtin import shape, shapes
from ..scene.mesh import load_mesh
from .figures import pyplot, save_figure
from .html import Item, Section, Table

__all__ = ["lines_showcase"]

TEST_MESHES = (
    ("bunny", "stanford-bunny.obj", (30, 15)),
    ("armadillo", "armadillo.obj", (20, 10)),
    ("dragon", "dragon_vrip_res2.ply", (20, 15)),
    ("max-planck", "decimated-max.obj", (200, 10)),
    ("fandisk", "fandisk.off", (40, 30)),
)


def _models() -> Path | None:
    env = os.environ.get("ILLUSIO_MODELS")
    for p in ([Path(env)] if env else []) + [
        Path.cwd().parent / "shared" / "data" / "models",
        Path.cwd() / "shared" / "data" / "models",
    ]:
        if p.is_dir():
            return p
    return None


def lines_showcase(ctx: Context, out_dir: Path, size: tuple[int, int]) -> Section:
    section = Section(
        "Line drawings (Judd et al. 2007; Jardim & de Figueiredo)",
        "Apparent ridges by the hybrid GPU method beside the classic line types; defaults everywhere unless stated.",
    )
    side = min(size)
    tile = (side, side)
    renderer = LineRenderer(ctx)
    knot = shape("torus-knot")
    view = framing_view(knot, 20, 30)
    renderer.prepare(knot)
    for kinds, label in (
        (("apparent-ridges",), "apparent ridges (hybrid)"),
        (("silhouettes",), "silhouettes (object space)"),
        (("silhouettes", "suggestive"), "silhouettes + suggestive contours"),
        (("silhouettes", "ridges", "valleys"), "silhouettes + ridges (red) and valleys (green)"),
    ):
        img = renderer.render(Frame(view, tile), LineParams(lines=kinds))
        rel = f"lines/knot-{'-'.join(kinds)}.png"
        write_image(out_dir / rel, img)
        section.items.append(
            Item(
                rel,
                label,
                "built-in torus knot",
                figure="Judd et al. 2007 and the report, ch. 2",
                command="illusio lines torus-knot --view 20,30 -o knot.png",
                params=LineParams(lines=kinds),
            )
        )
    fat = shapes.torus(1.0, 0.7)  # R < 2r: it has H = 0 curves
    fat_view = framing_view(fat, 20, 35)
    renderer.prepare(fat)
    kinds = ("silhouettes", "k-zero", "h-zero", "isophotes")
    write_image(out_dir / "lines/rtsc-types.png", renderer.render(Frame(fat_view, tile), LineParams(lines=kinds)))
    section.items.append(
        Item(
            "lines/rtsc-types.png",
            "more of rtsc's line types on a fat torus",
            "K = 0 (brown: top and bottom circles), H = 0 (purple: inside the hole), isophote n·l = 0.5 "
            "(grey), silhouettes; the built-in torus of the command is thinner (R > 2r): no H = 0 curve",
            figure="rtsc, the tool the report compares against",
            command="illusio lines torus --view 20,35 -o torus.png",
            params=LineParams(lines=kinds),
        )
    )
    blob = shape("blob")
    blob_view = framing_view(blob, 30, 15)
    renderer.prepare(blob)
    for kinds, rel, label, caption in (
        (
            ("silhouettes", "suggestive", "suggestive-highlights", "principal-highlights"),
            "lines/highlights.png",
            "suggestive and principal highlights (DeCarlo & Rusinkiewicz 2007) on the blob",
            "suggestive contours (blue: n·v a minimum along the view), suggestive highlights (orange: a maximum), "
            "principal highlights (gold: the view across the strongest curvature), silhouettes",
        ),
        (
            ("silhouettes", "suggestive", "dwkr"),
            "lines/dwkr.png",
            "DwKr lines on the blob",
            "where D_w κ_r equals the suggestive contours' threshold (magenta): the edge of the region where "
            "the suggestive contours (blue) may run",
        ),
    ):
        write_image(out_dir / rel, renderer.render(Frame(blob_view, tile), LineParams(lines=kinds)))
        section.items.append(
            Item(
                rel,
                label,
                caption,
                figure="rtsc, the tool the report compares against",
                command="illusio lines blob -o blob.png",
                params=LineParams(lines=kinds),
            )
        )
    renderer.prepare(knot)
    models = _models()
    meshes = [("blob", shape("blob"), (30, 15), "blob")]
    if not models:
        note = (
            "the scanned test meshes were not found (../shared/data/models, or set ILLUSIO_MODELS to their folder): "
            "the line-drawing section shows built-in shapes only"
        )
        section.text += f" Note: {note}."
        warnings.warn(note, stacklevel=2)
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            meshes += [
                (name, load_mesh(models / f), v, f"../shared/data/models/{f}")
                for name, f, v in TEST_MESHES
                if (models / f).exists()
            ]
    for name, mesh, (az, el), source in meshes:
        v = framing_view(mesh, az, el)
        renderer.prepare(mesh)
        img = renderer.render(Frame(v, tile), LineParams())
        write_image(out_dir / f"lines/{name}.png", img)
        speed = (
            (
                "; the whole drawing runs at 0.8 of the hybrid passes' frame rate here at 1024² "
                "(benchmarks/RESULTS.md, lines)"
            )
            if name == "dragon"
            else ""
        )
        section.items.append(
            Item(
                f"lines/{name}.png",
                f"{name}: default drawing",
                "apparent ridges (hybrid) + silhouettes" + speed,
                command=f"illusio lines {source} --view {az},{el} -o {name}.png",
                params=LineParams(),
            )
        )
    # the τ × λ grid (Figure 4.2) and the comparison with Canny, on the last mesh shown
    name, mesh, (az, el), source = meshes[min(1, len(meshes) - 1)]
    v = framing_view(mesh, az, el)
    renderer.prepare(mesh)
    write_image(out_dir / "lines/grid.png", parameter_grid(renderer, v, (side // 3, side // 3)))
    section.items.append(
        Item(
            "lines/grid.png",
            f"τ × λ grid on the {name}",
            "rows τ = −3, −2, −1, 0; columns λ = 0, 0.5, 1, 2",
            figure="the apparent-ridges report, Figure 4.2",
            command=f"illusio lines {source} --view {az},{el} --grid -o grid.png",
        )
    )
    phong = cmp.phong_render(ctx, mesh, v, tile)
    write_image(out_dir / "lines/phong.png", phong)
    target = cmp.image_edges(phong, "canny")
    section.items.append(f1_map(renderer, v, tile, target, out_dir, "lines/grid-f1.png", name))
    ours = cmp.line_mask(renderer.render(Frame(v, tile), LineParams()))
    s = cmp.score(ours, target)
    write_image(out_dir / "lines/compare-canny.png", cmp.overlay(ours, target))
    section.items.append(
        Item(
            "lines/phong.png", "the shaded render the edge detectors see", "Lambert + Phong, lamps at and above the eye"
        )
    )
    section.tables.append(
        Table(
            f"Against image edges on the {name} (a pixel matches within {s.tolerance:g} px; 3 px between the "
            "two methods)",
            ["drawing", "against", "precision", "recall", "F1", "chamfer (px)"],
            [
                [
                    "apparent ridges + silhouettes",
                    "Canny edges of the shaded render",
                    f"{s.precision:.3f}",
                    f"{s.recall:.3f}",
                    f"{s.f1:.3f}",
                    f"{s.chamfer:.2f}",
                ]
            ],
        )
    )
    section.items.append(
        Item(
            "lines/compare-canny.png",
            "apparent ridges + silhouettes against Canny edges",
            "red ours only, blue Canny only, black both; scores in the table above",
            figure="the apparent-ridges report, ch. 4",
            command=f"illusio lines {source} --view {az},{el} --compare canny -o {name}.png",
            params=LineParams(),
        )
    )
    hybrid = renderer.render(Frame(v, tile), LineParams(lines=("apparent-ridges",)))
    judd_params = LineParams(lines=("apparent-ridges", "silhouettes"), method="object-space")
    judd = renderer.render(Frame(v, tile), judd_params)
    agree = cmp.score(cmp.line_mask(hybrid), cmp.line_mask(judd), 3.0)
    write_image(out_dir / "lines/methods.png", cmp.overlay(cmp.line_mask(hybrid), cmp.line_mask(judd)))
    section.tables[-1].rows.append(
        [
            "hybrid apparent ridges",
            "Judd's object-space ones + contours",
            f"{agree.precision:.3f}",
            f"{agree.recall:.3f}",
            f"{agree.f1:.3f}",
            f"{agree.chamfer:.2f}",
        ]
    )
    section.items.append(
        Item(
            "lines/methods.png",
            "hybrid (red) against Judd's object-space apparent ridges + contours (blue)",
            "agreement in the table above (tolerance 3 px)",
            figure="the apparent-ridges report, ch. 3",
            command=f"illusio lines {source} --view {az},{el} -o judd.png",
            params=judd_params,
        )
    )
    section.items.append(auto_pairs(renderer, meshes[:3], tile, out_dir))
    from ..passes.mitsuba import mitsuba_available

    if mitsuba_available():
        section.items.append(photo_comparison(renderer, meshes[min(1, len(meshes) - 1)], tile, out_dir))
    renderer.release()
    return section


def photo_comparison(renderer, case, tile, out_dir: Path) -> Item:
    """The report's Figure 4.4 with a path-traced stand-in for the photograph, taken 3 px right and
    2 px up of the drawing's camera: drawing, photograph, its Canny edges, and the overlay at the
    shift the registered score found."""
    from ..lines.photograph import exposed, photograph

    name, mesh, (az, el), source = case
    v = framing_view(mesh, az, el)
    renderer.prepare(mesh)
    drawing = renderer.render(Frame(v, tile), LineParams())
    photo = exposed(photograph(mesh, v, tile, samples=32, misregistration=(3, -2)))
    edges = cmp.image_edges(photo, "canny")
    ours = cmp.line_mask(drawing)
    plain = cmp.score(ours, edges)
    found, (dx, dy) = cmp.registered_score(ours, edges)
    gap = np.full((tile[1], 4, 3), 0.8, np.float32)
    write_image(
        out_dir / "lines/photo.png",
        np.hstack(
            [
                drawing,
                gap,
                photo,
                gap,
                1.0 - np.repeat(edges[..., None], 3, axis=2).astype(np.float32),
                gap,
                cmp.overlay(cmp.shift_mask(ours, dx, dy), edges),
            ]
        ),
    )
    return Item(
        "lines/photo.png",
        f"the {name}: drawing, a path-traced photograph, its Canny edges, the overlay",
        f"photograph taken 3 px right, 2 px up of the drawing's camera; F1 {plain.f1:.2f} as drawn, "
        f"{found.f1:.2f} registered (shift found {dx:+d}, {dy:+d} px)",
        figure="the apparent-ridges report, Figure 4.4",
        command=f"illusio lines {source} --view {az},{el} --compare photo -o {name}.png",
        params=LineParams(),
    )


def auto_pairs(renderer, meshes, tile, out_dir: Path) -> Item:
    """Default parameters (left) and the automatic choice (right, `--auto`) per mesh, one row each,
    with their F1 against the Canny edges of the shaded render."""
    from ..lines.tuning import auto_parameters, edge_target

    rows, scores = [], []
    for name, mesh, (az, el), _ in meshes:
        v = framing_view(mesh, az, el)
        renderer.prepare(mesh)
        chosen = auto_parameters(renderer, v, tile, edge_target(renderer, mesh, v, tile))
        rows.append(
            np.hstack(
                [
                    renderer.render(Frame(v, tile), LineParams()),
                    np.full((tile[1], 4, 3), 0.8, np.float32),
                    renderer.render(Frame(v, tile), chosen.params),
                ]
            )
        )
        p = chosen.params
        scores.append(
            f"{name} {chosen.start.f1:.2f} → {chosen.scores.f1:.2f} (τ {p.tau:g}, λ {p.lam:g}, threshold "
            f"{p.threshold:g})"
        )
    write_image(out_dir / "lines/auto.png", np.vstack(rows))
    return Item(
        "lines/auto.png",
        "defaults (left) and the automatic choice (right)",
        "F1 against Canny edges of the shaded render: " + "; ".join(scores) + ". Transfer over every test mesh: "
        "benchmarks/RESULTS.md",
        figure="the report's open problem (parameters per mesh)",
        command="illusio lines blob --auto -o blob.png",
    )


def f1_map(renderer, view, tile, target, out_dir: Path, rel: str, name: str) -> Item:
    """The τ × λ grid as a colour map: F1 of each hybrid drawing against the Canny edges of the shaded
    render (what "best parameters" means, one number per cell), with its colour scale."""
    from ..lines.tuning import LAMBDAS, TAUS

    plt = pyplot()

    f1 = np.array(
        [
            [
                cmp.score(cmp.line_mask(renderer.render(Frame(view, tile), LineParams(tau=t, lam=lam))), target).f1
                for lam in LAMBDAS
            ]
            for t in TAUS
        ]
    )
    fig, ax = plt.subplots(figsize=(4.8, 3.6), dpi=100)
    shown = ax.imshow(f1, cmap="viridis", vmin=0, vmax=max(float(f1.max()), 1e-3))
    ax.set_xticks(range(len(LAMBDAS)), [f"{v:g}" for v in LAMBDAS])
    ax.set_yticks(range(len(TAUS)), [f"{v:g}" for v in TAUS])
    ax.set_xlabel("λ (direction-adaptive filter)")
    ax.set_ylabel("τ")
    for (r, c), v in np.ndenumerate(f1):
        ax.text(
            c, r, f"{v:.2f}", ha="center", va="center", color="white" if v < 0.6 * f1.max() else "black", fontsize=8
        )
    fig.colorbar(shown, ax=ax, label="F1 against Canny edges")
    save_figure(fig, out_dir / rel)
    r, c = np.unravel_index(int(np.argmax(f1)), f1.shape)
    return Item(
        rel,
        f"τ × λ on the {name}: F1 of each cell against Canny edges",
        f"best τ = {TAUS[r]:g}, λ = {LAMBDAS[c]:g} (F1 {f1[r, c]:.2f})",
        figure="the apparent-ridges report, Figure 4.2",
    )
