"""One class per technique shown by the viewer. A technique that lands adds its mode here."""

from .base import Mode
from .dof import DofMode
from .ibr import IbrMode
from .lines import LinesMode
from .plain import PlainMode
from .radiosity import RadiosityMode
from .relight import RelightMode
from .sis import SisMode

#: technique name -> mode class, in the order the viewer cycles through them
MODES: dict[str, type[Mode]] = {m.name: m for m in (PlainMode, SisMode, LinesMode, DofMode, IbrMode, RadiosityMode, RelightMode)}

__all__ = ["Mode", "MODES", "PlainMode", "SisMode", "LinesMode", "DofMode", "IbrMode", "RadiosityMode", "RelightMode"]
