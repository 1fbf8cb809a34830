"""Reading small text inputs (scenarios, camera paths) with the errors a user can act on."""

from __future__ import annotations

import os
from pathlib import Path

from .errors import InputError

__all__ = ["read_text"]


def read_text(path: str | os.PathLike, what: str, error: type[InputError] = InputError) -> str:
    """The UTF-8 text of ``path``; ``error`` (an InputError) naming the file and ``what`` it should
    have been when it is missing or unreadable."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{p}: no such {what} file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{p}: cannot read the {what} ({exc})") from None
