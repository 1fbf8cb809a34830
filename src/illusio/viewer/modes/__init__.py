"""One class per technique shown by the viewer, named by the technique's descriptor
(core.technique: ``viewer_mode``). MODES is built from the registry, in its order; a mode's module is
imported when the viewer first asks for that mode (a window showing the plain scene never loads
radiosity's kernels)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from ...core.lazy import load
from ...core.technique import techniques
from .base import Mode


class _Modes(Mapping):
    """technique name -> mode class, loaded on first access. Techniques that name one mode class
    (sis and sis-scene share SisMode, whose views are both) appear once, under the first's name."""

    def __init__(self) -> None:
        self._paths: dict[str, str] = {}
        self._loaded: dict[str, type[Mode]] = {}

    def _names(self) -> dict[str, str]:
        if not self._paths:
            seen = set()
            for t in techniques().values():
                if t.viewer_mode and t.viewer_mode not in seen:
                    seen.add(t.viewer_mode)
                    self._paths[t.name] = t.viewer_mode
        return self._paths

    def __getitem__(self, name: str) -> type[Mode]:
        if name not in self._loaded:
            self._loaded[name] = load(self._names()[name])
        return self._loaded[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())


#: technique name -> mode class, in the order the viewer cycles through them
MODES: Mapping[str, type[Mode]] = _Modes()

__all__ = ["Mode", "MODES"]


def __getattr__(name: str):
    # the mode classes by name (``from illusio.viewer.modes import SisMode``), loaded when asked for
    for path in _Modes()._names().values():
        if path.rpartition(":")[2] == name:
            return load(path)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
