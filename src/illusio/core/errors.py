"""Errors illusio raises on purpose.

Every error a user can cause (bad file, bad parameter, missing driver) is an :class:`IllusioError`
whose message says what was wrong and what to do. The CLI prints the message on one line and exits
with status 2; library users catch the subclass they care about.
"""

from __future__ import annotations

__all__ = [
    "IllusioError",
    "InputError",
    "GLUnavailable",
    "ShaderError",
    "OutputError",
    "did_you_mean",
]

APT_HINT = "apt-get install -y --no-install-recommends libegl1 libgl1 libgl1-mesa-dri"


def did_you_mean(name, choices) -> str:
    """ " (did you mean X?)" with the closest of ``choices`` to ``name``, or "" when none is close."""
    import difflib

    close = difflib.get_close_matches(str(name), [str(c) for c in choices], n=2, cutoff=0.6)
    return f" (did you mean {' or '.join(close)}?)" if close else ""


class IllusioError(Exception):
    """Base of every error illusio raises for a reason the user can act on."""

    def one_line(self) -> str:
        """The message folded onto one line, as the CLI prints it."""
        return " ".join(str(self).split())


class InputError(IllusioError, ValueError):
    """An input file or parameter is missing, unreadable, or out of range."""


class OutputError(IllusioError):
    """An output cannot be written (refused path, unsupported format, I/O failure)."""


class GLUnavailable(IllusioError, RuntimeError):
    """No usable OpenGL 4.3 context: driver or libraries missing, or version too old."""


class ShaderError(IllusioError, RuntimeError):
    """A GLSL program failed to compile or link; the message maps lines back to .glsl files."""
