"""Reading small text inputs (scenarios, camera paths) with the errors a user can act on."""

from __future__ import annotations

import os
from pathlib import Path

from .errors import InputError

__all__ = ["read_text", "read_yaml", "load_npy", "load_npz"]


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


def load_npy(path: str | os.PathLike, what: str):
    """The numeric array in the ``.npy`` file ``path`` (no pickles); InputError naming the file and
    ``what`` it should have been when it is missing, cut short, not an array or not numeric."""
    import numpy as np

    array = _numpy_read(path, what, lambda p: np.load(p, allow_pickle=False))
    if not isinstance(array, np.ndarray) or not np.issubdtype(array.dtype, np.number):
        raise InputError(f"{path}: the {what} is not a numeric array (dtype {getattr(array, 'dtype', '?')})")
    return array


def read_yaml(path: str | os.PathLike, what: str, error: type[InputError] = InputError):
    """The parsed YAML document in ``path`` (safe loader); ``error`` naming the file and, for a
    syntax error, its line and column."""
    import yaml

    text = read_text(path, what, error)
    try:
        return yaml.safe_load(text)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark
        where = f"line {mark.line + 1}, column {mark.column + 1}" if mark else "an unknown place"
        raise error(f"{path}: not valid YAML at {where}: {exc.problem}") from None
    except yaml.YAMLError as exc:
        raise error(f"{path}: not valid YAML ({' '.join(str(exc).split())})") from None


def load_npz(path: str | os.PathLike, what: str) -> dict:
    """Every array of the ``.npz`` archive ``path`` (no pickles), read at once: name → array.
    InputError naming the file and ``what`` it should have been when it is missing or damaged."""
    import numpy as np

    def read(p):
        with np.load(p, allow_pickle=False) as archive:
            return {name: archive[name] for name in archive.files}

    return _numpy_read(path, what, read)


def _numpy_read(path, what: str, read):
    """``read(path)``, numpy's many errors on bad bytes turned into one InputError."""
    p = Path(path)
    try:
        return read(p)
    except FileNotFoundError:
        raise InputError(f"{p}: no such {what} file") from None
    except MemoryError:
        raise InputError(f"{p}: the {what} declares an array too large for memory") from None
    except Exception as exc:  # headers and zips raise EOFError, SyntaxError, TokenError, BadZipFile, zlib.error…
        reason = " ".join(str(exc).split())[:200] or f"{type(exc).__name__}, an empty or cut file"
        raise InputError(f"{p}: not a {what} ({reason})") from None
