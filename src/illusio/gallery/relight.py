"""The relighting showcase: the office's photograph (path-traced by Mitsuba), the loscos mesh and
textures (Figures 4.8b, 4.12), and the edits of Loscos' Figure 4.17 by each method beside Mitsuba's
render of each edit. Needs the photo extra; without Mitsuba the section says so."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..passes.denoise import denoiser_available
from ..passes.mitsuba import mitsuba_available
from .html import Item, Section, Table
from .traced import DEMO_SAMPLES, path_traced

__all__ = ["relight_showcase"]

#: Loscos' Figure 4.17: the edits shown beside their truth
EDITS = {
    "back lamps off": {"lamp-0": 0.0, "lamp-1": 0.0},
    "left off, right doubled": {"lamp-0": 0.0, "lamp-2": 0.0, "lamp-1": 2.0, "lamp-3": 2.0},
    "right off, left doubled": {"lamp-1": 0.0, "lamp-3": 0.0, "lamp-0": 2.0, "lamp-2": 2.0},
}


def relight_showcase(ctx: Context, out_dir: Path, size: tuple[int, int], spp: int = DEMO_SAMPLES) -> Section:
    section = Section(
        "Relighting a photograph (Loscos 1999, ch. 4)",
        "The office photographed (Mitsuba, four ceiling lamps), its model's reflectances and lamp powers "
        "estimated from the photograph, then the lamps changed as in Figure 4.17: the truth (Mitsuba), the "
        "baseline of 4.2 (B/D over the photograph), the refined mesh and textures of 4.3, and per pixel.",
    )
    if not mitsuba_available():
        section.text += " Mitsuba is not installed (pip install 'illusio[photo]'): nothing to show."
        return section
    from ..radiosity.mitsuba import score
    from ..radiosity.polygons import scene_polygons
    from ..relight import METHODS, RealScene, RelightParams, RelightSession
    from ..scene.builtin import builtin_scene

    # the photograph is radiosity's path-traced reference of the office (same polygons, camera,
    # size and seed): made once a run (gallery.traced)
    small = (max(64, size[0] // 2), max(48, size[1] // 2))
    office = builtin_scene("office")
    polygons, view = scene_polygons(office), office.camera("main")
    real = RealScene(polygons, view, np.array(path_traced(polygons, view, small, spp)))
    p = real.polygons
    lamp = np.isin(p.group, p.lamps)
    sessions = {method: RelightSession(real, RelightParams(method=method), ctx) for method in METHODS}
    loscos = sessions["loscos"]
    loscos.image({})
    shown = [loscos.show(what, scale=3) for what in ("image", "mesh", "textures")]
    rel = "relight/office-loscos-mesh-and-textures.png"
    write_image(out_dir / rel, np.clip(np.concatenate(shown, axis=1), 0, 1))
    stats = loscos.refine_stats
    section.items.append(
        Item(
            rel,
            "photograph | the mesh after the texture-based refinement (4.3.1) | the "
            "textures without the photographed shadows (4.3.2)",
            f"{loscos.solution.stats.leaves} leaves: {stats.split} splits kept, {stats.undone} "
            "undone (no change of visibility under them, Figure 4.8a)",
            figure="Loscos 1999, Figures 4.8b and 4.12",
            command=f"illusio relight office --show mesh --size {small[0]}x{small[1]} -o mesh.png",
            params=loscos.params,
        )
    )
    noise = "denoised" if denoiser_available() else "noise included"
    table = Table(
        f"Mean relative error against Mitsuba's render of each edit ({spp} paths a pixel, {noise}) "
        "and the time of the edit",
        ["edit"] + list(METHODS),
        [],
    )
    for name, edit in EDITS.items():
        factor = np.array([edit.get(n, 1.0) for n in p.names])[p.group]
        truth = path_traced(
            dataclasses.replace(p, exitance=p.exitance * factor[:, None]), real.view, small, spp, seed=5
        )
        panels, notes = [real.photograph, truth], []
        for _method, session in sessions.items():
            image = session.image(edit)
            ids = session.pixel_polygon
            s = score(image, truth, (ids >= 0) & ~lamp[np.maximum(ids, 0)])
            notes.append(f"{100 * s.mean_relative_error:.0f} % ({session.times['edit'] * 1000:.0f} ms)")
            panels.append(image)
        rel = f"relight/office-{name.replace(' ', '-').replace(',', '')}.png"
        write_image(out_dir / rel, np.clip(np.concatenate(panels, axis=1), 0, 1))
        sets = " ".join(f"--set {k}={v:g}" for k, v in edit.items())
        section.items.append(
            Item(
                rel,
                f"{name}: photograph | truth | " + " | ".join(METHODS),
                "scores in the table above",
                figure="Loscos 1999, Figure 4.17",
                command=f"illusio relight office {sets} -o relit.png",
                params=sessions["per-pixel"].params,
            )
        )
        table.rows.append([name] + notes)
    section.tables.append(table)
    for session in sessions.values():
        session.release()
    return section
