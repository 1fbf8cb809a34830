"""The relighting showcase: the office's photograph (path-traced by Mitsuba), the back lamps switched
off by each method beside Mitsuba's render of that edit (Loscos Figure 4.17b). Needs the photo
extra; without Mitsuba the section says so."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..core.context import Context
from ..core.images import write_image
from ..passes.mitsuba import mitsuba_available
from .html import Item, Section

__all__ = ["relight_showcase"]


def relight_showcase(ctx: Context, out_dir: Path, size: tuple[int, int], spp: int = 64) -> Section:
    section = Section("Relighting a photograph (Loscos 1999, ch. 4)",
                      "The office photographed (Mitsuba, four ceiling lamps), its model's reflectances and lamp powers "
                      "estimated from the photograph, then the two back lamps switched off: the truth (Mitsuba), the "
                      "baseline of 4.2 (B/D over the photograph), the textures of 4.3.2, and per pixel.")
    if not mitsuba_available():
        section.text += " Mitsuba is not installed (pip install 'illusio[photo]'): nothing to show."
        return section
    from ..radiosity.mitsuba import render_mitsuba, score
    from ..relight import METHODS, RelightParams, RelightSession, builtin_real_scene

    small = (max(64, size[0] // 2), max(48, size[1] // 2))
    real = builtin_real_scene("office", small, spp)
    edit = {"lamp-0": 0.0, "lamp-1": 0.0}
    p = real.polygons
    factor = np.array([edit.get(n, 1.0) for n in p.names])[p.group]
    truth = render_mitsuba(dataclasses.replace(p, exitance=p.exitance * factor[:, None]), real.view, small, spp, seed=5)
    panels, notes = [real.photograph, truth], []
    for method in METHODS:
        session = RelightSession(real, RelightParams(method=method), ctx)
        image = session.image(edit)
        lamp = np.isin(p.group, p.lamps)
        ids = session.pixel_polygon
        s = score(image, truth, (ids >= 0) & ~lamp[np.maximum(ids, 0)])
        notes.append(f"{method} {100 * s.mean_relative_error:.0f} % ({session.times['edit'] * 1000:.0f} ms)")
        panels.append(image)
        session.release()
    rel = "relight/office-back-lamps-off.png"
    write_image(out_dir / rel, np.clip(np.concatenate(panels, axis=1), 0, 1))
    section.items.append(Item(rel, "photograph | truth with the back lamps off | " + " | ".join(METHODS),
                              "mean relative error against the truth (both at "
                              f"{spp} paths a pixel, so noise included) and the time of the edit: " + ", ".join(notes)))
    return section
