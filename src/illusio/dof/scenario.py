"""The scenario language of section 4.1: a time script of commands that move, show and hide objects
and put the focus on one of them. Parsed with a real grammar (scenario.lark, lark's LALR parser);
every error names the file, the line and the column.

    temps 0                                 // or: time 0 (milliseconds)
    positionne objet 1 vecteur [30, 30, -30] // position object 1 vector [...]
    affiche objet 1 / enleve objet 2         // show / hide
    nettete objet 1                          // focus object 1
    trajectoire objet 0 courbe 0             // trajectory object 0 curve 0
    vitesse objet 0 reel 100.0               // speed object 0 real 100.0 (scene units per second)
    bouge objet 0 / stoppe objet 2           // move / stop
    demarre action 1 objet 0                 // start action 1 object 0
    redemarre                                // restart: the script loops from here

Accents are optional (``démarré`` = ``demarre``), keywords are matched without case, and objects,
curves and actions are numbers (their order in the scene) or names.
"""

from __future__ import annotations

import os
import unicodedata
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from ..core.errors import InputError
from ..core.files import read_text

__all__ = ["Command", "Scenario", "ScenarioError", "parse_scenario", "load_scenario", "shipped_scenario", "KINDS"]

#: command kinds, as the grammar's rules name them
KINDS = ("time", "position", "show", "hide", "focus", "stop", "move", "trajectory", "speed", "start_action", "restart")


class ScenarioError(InputError):
    """A scenario that cannot be read or bound to its scene: ``FILE:LINE:COL: message``."""


@dataclass(frozen=True)
class Command:
    """One command at ``time`` milliseconds. ``object``: the object reference (int or name) of the
    commands that take one; ``ref``: the curve (trajectory) or action (start_action); ``value``: the
    vector (position) or the speed; ``line``, ``column``: where it stands in the file."""

    kind: str
    time: float
    line: int
    column: int
    object: int | str | None = None
    ref: int | str | None = None
    value: tuple[float, ...] | float | None = None


@dataclass(frozen=True)
class Scenario:
    """The commands in file order, each stamped with the time of the ``temps`` before it."""

    name: str
    commands: tuple[Command, ...]

    @property
    def duration_ms(self) -> float:
        """The time of the last command (or of the restart)."""
        return max((c.time for c in self.commands), default=0.0)


_COMMAND_NAMES = (
    "temps/time",
    "positionne/position",
    "affiche/show",
    "enleve/hide",
    "nettete/focus",
    "stoppe/stop",
    "bouge/move",
    "trajectoire/trajectory",
    "vitesse/speed",
    "demarre/start",
    "redemarre/restart",
)
_COMMANDS = {w.upper() for pair in _COMMAND_NAMES for w in pair.split("/")}


def _friendly(terminal: str) -> str:
    """A grammar terminal as a user reads it."""
    return {
        "INT": "a number",
        "NUMBER": "a number",
        "NAME": "a name",
        "COMMA": "','",
        "LSQB": "'['",
        "RSQB": "']'",
        "_NL": "the end of the line",
    }.get(terminal, terminal.lower())


def _strip_accents(text: str) -> str:
    """Each character without its accent (the text keeps its length, so columns stay right)."""
    return "".join(unicodedata.normalize("NFD", ch)[0] if ord(ch) > 127 else ch for ch in text)


@lru_cache(maxsize=1)
def _parser():
    from lark import Lark

    grammar = (Path(__file__).parent / "scenario.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", propagate_positions=True)


def _ref(tree):
    token = tree.children[0]
    return int(token) if token.type == "INT" else str(token)


def parse_scenario(text: str, name: str = "scenario") -> Scenario:
    """Commands of a scenario text; ScenarioError ``name:line:col: ...`` on a mistake."""
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    source = _strip_accents(unicodedata.normalize("NFC", text))
    try:
        tree = _parser().parse(source)
    except UnexpectedInput as exc:
        line, column = getattr(exc, "line", 0), getattr(exc, "column", 0)
        if isinstance(exc, UnexpectedToken):
            expected = sorted(_friendly(e) for e in exc.expected - {"$END"})
            if exc.token.type == "NAME" and any(e.upper() in _COMMANDS for e in exc.expected):
                message = f"unknown command {str(exc.token)!r} (commands: {', '.join(_COMMAND_NAMES)})"
            else:
                what = {"$END": "the end of the file", "_NL": "the end of the line"}.get(
                    exc.token.type, repr(str(exc.token))
                )
                message = f"unexpected {what}" + (f"; expected {' or '.join(expected[:6])}" if expected else "")
        elif isinstance(exc, UnexpectedCharacters):
            message = f"unexpected character {source[exc.pos_in_stream]!r}"
        elif isinstance(exc, UnexpectedEOF):
            message = "the file ends in the middle of a command"
        else:
            message = str(exc).splitlines()[0]
        if line in (None, -1, 0):  # at the end of the file
            line = source.count("\n") + 1
            column = len(source) - source.rfind("\n")
        raise ScenarioError(f"{name}:{line}:{column}: {message}") from None
    now = 0.0
    commands = []
    for st in tree.children:
        line, column = st.meta.line, st.meta.column
        kind = str(st.data)
        args = {}
        for child in st.children:
            if hasattr(child, "data") and child.data == "object":
                args["object"] = _ref(child.children[0])
            elif hasattr(child, "data") and child.data == "ref":
                args["ref"] = _ref(child)
            elif hasattr(child, "data") and child.data == "vector":
                args["value"] = tuple(float(t) for t in child.children)
            elif getattr(child, "type", None) == "NUMBER":
                args["value"] = float(child)
        if kind == "time":
            t = args["value"]
            if t < now:
                raise ScenarioError(f"{name}:{line}:{column}: time {t:g} ms goes back before {now:g} ms")
            now = t
        commands.append(Command(kind, now, line, column, **args))
    return Scenario(name, tuple(commands))


def shipped_scenario(name: str) -> Path | None:
    """The path of a scenario shipped with illusio (dof/scenarios/NAME.txt), or None."""
    path = Path(__file__).parent / "scenarios" / f"{name}.txt"
    return path if path.is_file() else None


def load_scenario(path: str | os.PathLike) -> Scenario:
    return parse_scenario(read_text(path, "scenario", ScenarioError), str(path))
