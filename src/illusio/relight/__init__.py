"""Relighting a real scene from one photograph (Loscos 1999, chapter 4), on illusio.radiosity.

    from illusio.relight import RelightSession, builtin_real_scene
    session = RelightSession(builtin_real_scene("office"))
    image = session.set_lamp("lamp-0", 0.0)

This first landing is the initialisation of 4.2.1 and its limitation of 4.2.2 (the ``baseline``
method): reflectances and lamp exitances estimated from the photograph, the display factor, and
eq. (4.3). The texture corrections of 4.3 are the rest of issue 16.
"""

from .params import METHODS, RelightParams
from .photograph import RealScene, builtin_real_scene, polygon_ids
from .renderer import RelightRenderer
from .session import RelightSession

__all__ = ["RelightSession", "RelightRenderer", "RelightParams", "RealScene", "builtin_real_scene", "polygon_ids", "METHODS"]
