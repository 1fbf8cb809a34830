"""The display of eq. (4.3) stated plainly: the reference the session's GPU image is tested against.

B is gathered at every leaf corner directly (not through the session's per-lamp basis), divided by
the display factor kept at the corners, interpolated across each leaf by rays through the pixel
centres (``radiosity.reference_display``) and multiplied by the texture; a virtual object's pixels
show its own B/π."""

from __future__ import annotations

import numpy as np

from ..radiosity import leaf_mesh, reference_display

__all__ = ["displayed_image"]


def displayed_image(session, scales: dict) -> tuple[np.ndarray, np.ndarray]:
    """(image (H, W, 3) radiance × exposure, leaf element under each pixel or −1) of an element
    method's session under ``scales``."""
    sol = session.solution
    sol.set_lamps(scales)
    session.inherit_display_factor()
    h = sol.hierarchy
    now = leaf_mesh(h, sol.links, sol.exitance())
    leaves = h.leaves()
    d = session.corner_d[leaves].reshape(-1, 3).astype(np.float64)
    virtual = np.repeat(np.isin(sol.polygons.group[h.polygon[leaves]], list(session.virtual_groups)), 4)
    ratio = np.where(d > 0, now.radiance / np.where(d > 0, d, 1), 0.0)
    values = np.where(virtual[:, None], now.radiance, ratio)
    image, face = reference_display(now.positions, values, now.faces, session.real.view, session.real.size)
    element = np.where(face >= 0, now.face_element[np.maximum(face, 0)], -1)
    own = (element >= 0) & np.isin(sol.polygons.group[h.polygon[np.maximum(element, 0)]], list(session.virtual_groups))
    out = np.where(own[..., None], image, image * session.texture) * session.params.exposure
    return out.astype(np.float32), element
