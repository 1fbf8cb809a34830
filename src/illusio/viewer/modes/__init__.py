"""One class per technique shown by the viewer, named by the technique's descriptor
(core.technique: ``viewer_mode``); MODES is built from the registry, in its order."""

from ...core.technique import techniques
from .base import Mode
from .dof import DofMode
from .ibr import IbrMode
from .lines import LinesMode
from .plain import PlainMode
from .radiosity import RadiosityMode
from .relight import RelightMode
from .sis import SisMode


def _modes() -> dict[str, type[Mode]]:
    modes: dict[str, type[Mode]] = {}
    for t in techniques().values():
        mode = t.mode_class()
        if mode is not None:
            modes.setdefault(mode.name, mode)  # sis and sis-scene share one mode (its views)
    return modes


#: technique name -> mode class, in the order the viewer cycles through them
MODES: dict[str, type[Mode]] = _modes()

__all__ = ["Mode", "MODES", "PlainMode", "SisMode", "LinesMode", "DofMode", "IbrMode", "RadiosityMode", "RelightMode"]
