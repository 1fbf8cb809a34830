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

import numpy as np
import scipy.sparse as sp

from .hierarchy import Hierarchy

__all__ = ["push_pull", "solve", "SolveResult"]


@dataclass(frozen=True)
class SolveResult:
    iterations: int
    change: float      # the last largest change of B, relative to the largest B
    converged: bool


def push_pull(h: Hierarchy, irradiance: np.ndarray, exitance: np.ndarray, levels: list[np.ndarray]) -> np.ndarray:
    """B for every element from the gathered H (n, 3) and the exitances E (n, 3)."""
    total = irradiance.copy()
    parent = h.parent
    for lv in levels[1:]:
        total[lv] += total[parent[lv]]
    b = exitance + h.reflectance * total
    child, area = h.child, h.area
    for lv in levels[-2::-1]:
        inner = lv[child[lv] >= 0]
        if len(inner):
            c = child[inner][:, None] + np.arange(4)
            b[inner] = (area[c][..., None] * b[c]).sum(axis=1) / area[inner][:, None]
    return b


def solve(h: Hierarchy, matrix: sp.csr_matrix, exitance: np.ndarray, tolerance: float = 1e-4,
          max_iterations: int = 200, start: np.ndarray | None = None) -> SolveResult:
    """Iterate gather + push-pull from ``start`` (default: the hierarchy's B) until the largest change
    of B is below ``tolerance`` × the largest reflected radiosity max(B − E); leaves B and H in the
    hierarchy."""
    levels = h.by_level()
    b = (h.radiosity if start is None else start).copy()
    change, k = np.inf, 0
    for k in range(1, max_iterations + 1):
        irradiance = np.asarray(matrix @ b)
        new = push_pull(h, irradiance, exitance, levels)
        scale = max(float(np.abs(new - exitance).max()), 1e-300)   # the reflected light, not the lamps
        change = float(np.abs(new - b).max()) / scale
        b = new
        if change < tolerance:
            break
    h.radiosity[:] = b
    h.irradiance[:] = irradiance
    return SolveResult(k, change, change < tolerance)
