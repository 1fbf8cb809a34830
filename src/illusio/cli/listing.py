"""illusio list: the names the other commands take — built-in scenes (with their cameras, the surfaces
tagged to host a stereogram and their lamps), shapes, stereogram patterns and algorithms, line
types, viewer techniques."""

from __future__ import annotations

import typer

from ..core.errors import InputError, did_you_mean

#: what ``illusio list`` can list
WHAT = ("scenes", "shapes", "patterns", "algorithms", "lines", "techniques")


def _scenes() -> list[str]:
    from ..scene.builtin import SCENES, builtin_scene

    rows = []
    for name in SCENES:
        scene = builtin_scene(name)
        hosts = [n.name for n in scene.nodes if "host" in n.tags]
        rows.append(
            f"{name}: cameras {', '.join(scene.cameras)}; hosts {', '.join(hosts) or '—'}; "
            f"lamps {', '.join(light.name for light in scene.lights) or '—'}"
        )
    return rows


def _names(what: str) -> list[str]:
    if what == "scenes":
        return _scenes()
    if what == "shapes":
        from ..scene.builtin import SHAPES

        return list(SHAPES)
    if what in ("patterns", "algorithms"):
        from ..sis.params import ALGORITHMS, PATTERNS

        return list(PATTERNS if what == "patterns" else ALGORITHMS)
    if what == "lines":
        from ..lines.params import LINE_TYPES

        return list(LINE_TYPES)
    from ..core.technique import techniques

    return [
        f"{t.name}: {t.title}; source: {t.source_kind} (default {t.default_source})"
        + (f"; views {', '.join(t.presets)}" if t.presets else "")
        + (f"; needs {t.needs}" if t.needs else "")
        for t in techniques().values()
    ]


def listing(what: str = typer.Argument(None, help=f"one of {', '.join(WHAT)} (default: all)")) -> None:
    """List the built-in names the commands take: scenes (cameras, stereogram hosts, lamps), shapes,
    stereogram patterns and algorithms, line types, viewer techniques."""
    if what is not None and what not in WHAT:
        raise InputError(f"illusio list takes one of {', '.join(WHAT)}, got {what!r}{did_you_mean(what, WHAT)}")
    for kind in WHAT if what is None else (what,):
        typer.echo(f"{kind}:")
        for line in _names(kind):
            typer.echo(f"  {line}")
