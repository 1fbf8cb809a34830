"""Relighting a real scene from one photograph (Loscos 1999, chapter 4), on illusio.radiosity.

    from illusio.relight import RelightSession, builtin_real_scene
    session = RelightSession(builtin_real_scene("office"))
    image = session.set_lamp("lamp-0", 0.0)

Preparation estimates the reflectances and lamp exitances from the photograph (4.2.1) and solves;
then, by method: ``baseline`` displays the photograph modulated by B/D (eq. 4.3; its photographed
shadows stay when a lamp goes off, 4.2.2); ``loscos`` refines the mesh along the photographed
shadows (4.3.1, ``shadow_refine``) and makes textures free of them (4.3.2, ``textures``);
``per-pixel`` does the texture work per pixel (the chapter's conclusion). Edits: lamp scales, a
virtual lamp, a virtual object added and moved (4.4). ``tone`` fits the gain/γ step of Figure 4.21.
"""

from ..core.lazy import lazy_exports

_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(("METHODS", "RelightParams"), "params"),
    **dict.fromkeys(("RealScene", "builtin_real_scene", "load_real_scene", "polygon_ids"), "photograph"),
    "RelightRenderer": "renderer",
    "RelightSession": "session",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
