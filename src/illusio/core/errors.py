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
]

APT_HINT = "apt-get install -y --no-install-recommends libegl1 libgl1 libgl1-mesa-dri"


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
