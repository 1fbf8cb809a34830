"""The hierarchical solver: gather then push-pull, repeated until B stops changing.

- gather: H_i = Σ_{links j→i} F_ij·V_ij·B_j, for every element at every level, as one sparse product;
- push: each element's total irradiance is its own H plus its ancestors' (top down, level by level);
- at the leaves B = E + ρ·H_total;
- pull: an inner element's B is the area-weighted mean of its children's, Σ A_c·B_c / A (bottom up).

Units: E, B and H in W/m², per RGB channel. Only the exitances change between interactive solves
(Loscos 4.4.2): the links, hence the sparse matrix, are kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from .hierarchy import Hierarchy

__all__ = ["push_pull", "solve", "SolveResult"]


@dataclass(frozen=True)
class SolveResult:
    iterations: int
    change: float  # the last largest change of B, relative to the largest reflected B
    converged: bool
    #: no light reaches any surface (the reflected radiosity under 1e-9 of the largest exitance):
    #: the lamps face away from everything
    dark: bool = False


def push_pull(h: Hierarchy, irradiance: np.ndarray, exitance: np.ndarray, levels: list[np.ndarray]) -> np.ndarray:
    """B for every element from the gathered H (n, 3) and the exitances E (n, 3) (``levels``: the
    active elements by level, ``h.by_level()``). One numba pass down and one up (radiosity.reference
    .push_pull states it as loops; a NumPy pass per level cost 4× as much)."""
    order = np.concatenate(levels) if levels else np.zeros(0, np.int64)
    return _push_pull(
        order,
        h.parent,
        h.child,
        h.area,
        np.ascontiguousarray(h.reflectance, np.float64),
        np.ascontiguousarray(irradiance, np.float64),
        np.ascontiguousarray(exitance, np.float64),
    )


@numba.njit(cache=True)
def _push_pull(order, parent, child, area, reflectance, irradiance, exitance):
    """``order``: the active elements, parents before children."""
    total = irradiance.copy()
    for e in order:  # push: an element's H plus its ancestors'
        if parent[e] >= 0:
            for c in range(3):
                total[e, c] += total[parent[e], c]
    b = exitance + reflectance * total
    for k in range(len(order) - 1, -1, -1):  # pull: the area-weighted mean of the children
        e = order[k]
        first = child[e]
        if first >= 0:
            for c in range(3):
                s = area[first] * b[first, c]
                for q in range(1, 4):
                    s += area[first + q] * b[first + q, c]
                b[e, c] = s / area[e]
    return b


def solve(
    h: Hierarchy,
    matrix,
    exitance: np.ndarray,
    tolerance: float = 1e-4,
    max_iterations: int = 200,
    start: np.ndarray | None = None,
) -> SolveResult:
    """Iterate gather + push-pull from ``start`` (default: the hierarchy's B) until the largest change
    of B is below ``tolerance`` × the largest reflected radiosity max(B − E); leaves B and H in the
    hierarchy. ``matrix``: K with H = K @ B (a scipy matrix or :class:`links.LinkGather`)."""
    if not np.any(exitance):  # nothing emits: B = 0 (the relative change below would never settle)
        h.radiosity[:] = 0.0
        h.irradiance[:] = 0.0
        return SolveResult(0, 0.0, True)
    levels = h.by_level()
    b = (h.radiosity if start is None else start).copy()
    change, k = np.inf, 0
    while k < max_iterations:
        k += 1
        irradiance = np.asarray(matrix @ b)
        new = push_pull(h, irradiance, exitance, levels)
        # the reflected light, not the lamps; where almost none is (a lamp facing away) the change
        # is measured against 1e-9 of the lamps' exitance, so a dark scene converges too
        scale = max(float(np.abs(new - exitance).max()), 1e-9 * float(np.abs(exitance).max()))
        change = float(np.abs(new - b).max()) / scale
        b = new
        if change < tolerance:
            break
    h.radiosity[:] = b
    h.irradiance[:] = irradiance
    dark = float(np.abs(b - exitance).max()) < 1e-9 * float(np.abs(exitance).max())
    return SolveResult(k, change, change < tolerance, dark)
