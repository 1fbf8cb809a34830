"""Line-drawing parameters across meshes (issue 20; the apparent-ridges report's main open problem:
no (τ, λ) suits every mesh). Quality, not speed.

For every mesh of the test models, seen from (30°, 15°) at 512²: F1 of the whole default drawing
(apparent ridges by the hybrid method, and silhouettes) against the Canny edges of the shaded mesh
(lines.tuning.edge_target), with (a) the default parameters, (b) the τ, λ and threshold the
automatic choice found on another mesh (each other mesh's in turn: their mean and worst, and the one
set that transfers best), (c) the automatic choice on the mesh itself (lines.tuning.auto_parameters,
`illusio lines --auto`). Written as ratios; --quick uses built-in shapes at 192².

Then against photographs (the report's registration problem), for the small meshes: the path-traced
stand-in (lines.photograph: painted albedo, soft shadows, noise, 32 paths a pixel) taken with the
camera turned by (3, −2) px; F1 of the default and the `--auto` drawing (tuned on the shaded mesh,
and tuned on the photograph's own edges) against its Canny edges, as drawn and registered
(lines.compare.registered_score, ±5 px), and the shift found.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from illusio.core import Context
from illusio.core.renderer import Frame
from illusio.lines.compare import image_edges, line_mask, registered_score, score
from illusio.lines.drawing import LineRenderer, framing_view
from illusio.lines.params import LineParams
from illusio.lines.tuning import auto_parameters, edge_target
from illusio.scene.builtin import shape
from illusio.scene.mesh import load_mesh

from .lines import MODELS

SUFFIXES = (".obj", ".off", ".ply")
#: the meshes photographed (path tracing the 100k+ triangle scans would take minutes each)
PHOTOGRAPHED = ("bunny", "cow", "decimated-max", "fandisk", "spot")
MISREGISTRATION = (3, -2)


def meshes(quick: bool) -> dict:
    if quick or not MODELS.is_dir():
        return {name: shape(name) for name in ("torus-knot", "blob", "gear", "superquadric")}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {p.stem: load_mesh(p) for p in sorted(MODELS.iterdir()) if p.suffix in SUFFIXES}


def run(ctx: Context, repeat: int, quick: bool = False):
    size = (192, 192) if quick else (512, 512)
    defaults = LineParams()
    renderer = LineRenderer(ctx)
    cases, chosen, results = {}, {}, {}
    for name, mesh in meshes(quick).items():
        renderer.prepare(mesh)
        view = framing_view(mesh, 30, 15)
        target = edge_target(renderer, mesh, view, size)
        cases[name] = (mesh, view, target)
        auto = auto_parameters(renderer, view, size, target, defaults)
        chosen[name] = auto.params
        results[f"{name}: F1 defaults"] = round(auto.start.f1, 3)
        results[f"{name}: F1 auto"] = round(auto.scores.f1, 3)
        results[f"{name}: auto tau"] = auto.params.tau
        results[f"{name}: auto lambda"] = auto.params.lam
        results[f"{name}: auto threshold"] = auto.params.threshold
    # (b): every mesh drawn with every other mesh's choice
    names = list(cases)
    transfer = np.full((len(names), len(names)), np.nan)  # [source, target]
    for t, name in enumerate(names):
        mesh, view, target = cases[name]
        renderer.prepare(mesh)
        for s, source in enumerate(names):
            p = chosen[source]
            params = replace(defaults, tau=p.tau, lam=p.lam, threshold=p.threshold)
            transfer[s, t] = score(line_mask(renderer.render(Frame(view, size), params)), target).f1
    renderer.release()
    others = ~np.eye(len(names), dtype=bool)
    best_source = int(np.argmax([transfer[s][others[s]].mean() for s in range(len(names))]))
    for t, name in enumerate(names):
        column = transfer[others[:, t], t]
        results[f"{name}: F1 with another mesh's choice, mean"] = round(float(column.mean()), 3)
        results[f"{name}: F1 with another mesh's choice, worst"] = round(float(column.min()), 3)
        results[f"{name}: F1 with {names[best_source]}'s choice"] = round(float(transfer[best_source, t]), 3)
    for label, key in (
        ("defaults", "F1 defaults"),
        ("auto", "F1 auto"),
        ("another mesh's choice", "F1 with another mesh's choice, mean"),
    ):
        results[f"mean over meshes: F1 {label}"] = round(float(np.mean([results[f"{n}: {key}"] for n in names])), 3)
    results[f"the choice that transfers best, {names[best_source]}'s: its mean F1 on the other meshes"] = round(
        float(transfer[best_source][others[best_source]].mean()), 3
    )
    results["mean over meshes: F1 with the best-transferring choice"] = round(
        float(np.mean([transfer[best_source, t] for t in range(len(names))])), 3
    )
    results.update(photographs(ctx, cases, chosen, size, quick))
    return [], results


def photographs(ctx: Context, cases: dict, chosen: dict, size, quick: bool) -> dict[str, float]:
    from illusio.lines.photograph import exposed, photograph
    from illusio.passes.mitsuba import mitsuba_available

    if not mitsuba_available():
        return {}
    names = list(cases)[:2] if quick else [n for n in PHOTOGRAPHED if n in cases]
    renderer = LineRenderer(ctx)
    results: dict[str, float] = {}
    for name in names:
        mesh, view, _ = cases[name]
        renderer.prepare(mesh)
        photo = photograph(mesh, view, size, samples=8 if quick else 32, misregistration=MISREGISTRATION)
        edges = image_edges(exposed(photo), "canny")
        on_photo = auto_parameters(renderer, view, size, edges).params
        for label, params in (
            ("defaults", LineParams()),
            ("auto on the shaded mesh", chosen[name]),
            ("auto on the photograph", on_photo),
        ):
            ours = line_mask(renderer.render(Frame(view, size), params))
            registered, (dx, dy) = registered_score(ours, edges, max_shift=5)
            results[f"photo {name}, {label}: F1 as drawn"] = round(score(ours, edges).f1, 3)
            results[f"photo {name}, {label}: F1 registered"] = round(registered.f1, 3)
            if label == "defaults":
                results[f"photo {name}: shift found dx"] = dx
                results[f"photo {name}: shift found dy"] = dy
    renderer.release()
    return results
