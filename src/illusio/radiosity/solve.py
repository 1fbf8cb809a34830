"""The hierarchical solver: B = E + M(B), M the gather then push-pull of the reflected light.

- gather: H_i = Σ_{links j→i} F_ij·V_ij·B_j, for every element at every level, as one sparse product;
- push: each element's total irradiance is its own H plus its ancestors' (top down, level by level);
- at the leaves B = E + ρ·(H_lamps + s·H_reflected): the light from the lamps' exitance as the
  links carry it, and the light from reflecting surfaces times s, which keeps the gain ρ·Σ F·V at
  most 0.98 (and, where a reach is given, scales the leaf's links' Σ F·V to its reach as rays
  measure it: :func:`form_factor_scale`, :func:`lamp_light_kept`);
- pull: an inner element's B is the area-weighted mean of its children's, Σ A_c·B_c / A (bottom up).

The fixed point is found by GMRES on (I − M)·B = push-pull(E) (a few dozen products of M where a
bright room, ρ·Σ F near 0.97, takes plain gather iterations hundreds), then gather iterations from
there until the largest change of B is below the tolerance: the same stopping rule as iterating
alone, which is the reference (``solve(..., krylov=False)``).

Units: E, B and H in W/m², per RGB channel. Only the exitances change between interactive solves
(Loscos 4.4.2): the links, hence the sparse matrix, are kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

from .hierarchy import Hierarchy
from .links import LinkGather
from .refine import channel_max

__all__ = ["push_pull", "solve", "SolveResult", "form_factor_scale", "lamp_light_kept", "reflecting_sums"]


@dataclass(frozen=True)
class SolveResult:
    iterations: int
    change: float  # the last largest change of B, relative to the largest reflected B
    converged: bool
    #: no light reaches any surface (the reflected radiosity under 1e-9 of the largest exitance):
    #: the lamps face away from everything
    dark: bool = False
    #: (n,) the factor on each element's reflected light the solve used (form_factor_scale), which the
    #: display's corner gather applies too; None where nothing was solved
    scale: np.ndarray | None = field(default=None, compare=False, repr=False)


def push_pull(
    h: Hierarchy,
    irradiance: np.ndarray,
    exitance: np.ndarray,
    levels: list[np.ndarray],
    scale: np.ndarray | None = None,
) -> np.ndarray:
    """B for every element from the gathered H (n, 3) and the exitances E (n, 3) (``levels``: the
    active elements by level, ``h.by_level()``); ``scale`` (n,), optional, multiplies each element's
    pushed H (:func:`form_factor_scale`). One numba pass down and one up (radiosity.reference
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
        np.ones(len(h)) if scale is None else np.ascontiguousarray(scale, np.float64),
    )


#: the largest gain ρ·Σ F·V an element's gather may have (below 1: the iteration contracts)
MAX_GAIN = 0.98


def form_factor_scale(h: Hierarchy, matrix, levels: list[np.ndarray], reach: np.ndarray | None = None) -> np.ndarray:
    """(n,) the factor on the light each element gathers from reflecting surfaces (the lamps' own
    light is never scaled: :func:`lamp_light_kept`). Its links' Σ F·V to surfaces that reflect (ρ > 0;
    its own links' and its ancestors', K·1 pushed down) is scaled to its ``reach`` (n,; NaN where
    not measured: Visibility.reach, the share of its hemisphere that meets a reflecting surface;
    HierarchyParams.reach_rays says what it does on RenderPark's scenes). Then the gain ρ_max·Σ F·V
    is kept at most MAX_GAIN: surfaces nearly touching — AutoCAD's doubled walls, a two-sided face's
    twin across a thin slab — can pass 1/ρ, and the iteration would amplify light instead of
    converging (the Graz office's red walls at B = 678 W/m² under lamps of 2.7). The lamps are left
    out of the sum: a ceiling 8 cm above a lamp's top face has most of its hemisphere on the lamp,
    and counting it cut the lamp's direct light there too (the Graz office's ceiling 8 % dark)."""
    total = reflecting_sums(h, matrix, levels)
    scale = np.ones(len(h))
    if reach is not None:
        known = np.isfinite(reach) & (total > 1e-12)
        scale[known] = reach[known] / total[known]
    gain = total * scale * channel_max(h.reflectance)
    return np.where(gain > MAX_GAIN, scale * MAX_GAIN / np.maximum(gain, 1e-300), scale)


def reflecting_sums(h: Hierarchy, matrix, levels: list[np.ndarray]) -> np.ndarray:
    """(n,) each element's Σ F·V to the surfaces that reflect (ρ > 0), its own links' and its
    ancestors' (K·1 over them, pushed down): what form_factor_scale caps and scales to a reach."""
    reflects = (channel_max(h.reflectance) > 0).astype(np.float64)[:, None]
    if not isinstance(matrix, LinkGather):  # (a cluster gather takes RGB)
        reflects = np.repeat(reflects, 3, axis=1)
    total = np.asarray(matrix @ reflects, np.float64)[:, 0].copy()
    for level in levels[1:]:
        total[level] += total[h.parent[level]]
    return total


def lamp_light_kept(
    h: Hierarchy, matrix, exitance: np.ndarray, levels: list[np.ndarray], scale: np.ndarray
) -> np.ndarray:
    """(n, 3) what push_pull's ``scale`` takes from the lamps' light, given back: ρ·(1 − s)·(K·E
    pushed down), pulled up. The solve adds it to every gather step, so the scale acts on the
    reflected light alone: B = E + ρ·(K·E)↓ + ρ·s·(K·(B − E))↓, still linear in E."""
    if np.all(scale == 1.0) or not np.any(exitance):
        return np.zeros_like(exitance, dtype=np.float64)
    zero = np.zeros_like(exitance, dtype=np.float64)
    lamps = np.asarray(matrix @ push_pull(h, zero, exitance, levels), np.float64)
    return push_pull(h, lamps, zero, levels, 1.0 - scale)  # (push-pull is linear in the scale)


@numba.njit(cache=True)
def _push_pull(order, parent, child, area, reflectance, irradiance, exitance, scale):
    """``order``: the active elements, parents before children."""
    total = irradiance.copy()
    for e in order:  # push: an element's H plus its ancestors'
        if parent[e] >= 0:
            for c in range(3):
                total[e, c] += total[parent[e], c]
    b = exitance + reflectance * total * scale.reshape(-1, 1)
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


#: gather steps a solve takes before it decides on GMRES
PROBE_STEPS = 3
#: GMRES is used when the gather steps' contraction predicts more than this many steps still to go
GATHER_STEPS_LEFT = 12


def _steps_left(changes: list[float], tolerance: float) -> float:
    """Gather steps still needed to bring the last change under ``tolerance`` at the contraction the
    last two steps showed (infinite when they did not contract)."""
    if len(changes) < 2 or changes[-2] <= 0:
        return np.inf
    ratio = changes[-1] / changes[-2]
    if not 0 < ratio < 1:
        return np.inf
    return float(np.log(tolerance / changes[-1]) / np.log(ratio))


def _krylov(h, matrix, exitance, levels, scale, kept, b, tolerance, max_iterations):
    """B from GMRES on (I − M) B = push_pull(0, E), M the gather and push-pull of the light alone:
    a bright room (ρ·Σ F near 1) that gather iterations take hundreds of steps over is solved in a few
    dozen products. Returns (B, the products spent); the caller's iteration then checks it."""
    from scipy.sparse.linalg import LinearOperator, gmres

    budget = max_iterations - 1  # products GMRES may spend (one a cycle for its residual): one is left
    if budget < 4:
        return b, 0
    restart = min(30, budget - 1)
    zero = np.zeros_like(exitance)
    shape = b.shape
    count = [0]

    def product(v):
        count[0] += 1
        x = v.reshape(shape)
        return (x - push_pull(h, np.asarray(matrix @ x), zero, levels, scale)).ravel()

    rhs = (push_pull(h, zero, exitance, levels, scale) + kept).ravel()
    operator = LinearOperator((b.size, b.size), matvec=product, dtype=np.float64)
    x, _ = gmres(operator, rhs, x0=b.ravel(), rtol=0.1 * tolerance, restart=restart, maxiter=budget // (restart + 1))
    return x.reshape(shape), count[0]


def solve(
    h: Hierarchy,
    matrix,
    exitance: np.ndarray,
    tolerance: float = 1e-4,
    max_iterations: int = 200,
    start: np.ndarray | None = None,
    reach: np.ndarray | None = None,
    krylov: bool = True,
    scale: np.ndarray | None = None,
) -> SolveResult:
    """From ``start`` (default: the hierarchy's B), gather + push-pull iterations until the largest
    change of B is below ``tolerance`` × the largest reflected radiosity max(B − E); leaves B and H in
    the hierarchy. With ``krylov``, after PROBE_STEPS of them, GMRES when their contraction predicts
    more than GATHER_STEPS_LEFT more (a bright room from a cold start; an edit's warm start finishes
    with the gather steps: on the relighting drag, GMRES's set-up cost as much as the rest of a move).
    ``matrix``: K with H = K @ B (a scipy matrix or :class:`links.LinkGather`); ``reach``:
    form_factor_scale's; ``scale``: form_factor_scale(h, matrix, levels, reach) where the caller kept
    it. The iterations counted are the products of K, GMRES's included."""
    if not np.any(exitance):  # nothing emits: B = 0 (the relative change below would never settle)
        h.radiosity[:] = 0.0
        h.irradiance[:] = 0.0
        return SolveResult(0, 0.0, True)
    levels = h.by_level()
    gather_scale = form_factor_scale(h, matrix, levels, reach) if scale is None else scale
    kept = lamp_light_kept(h, matrix, exitance, levels, gather_scale)
    b = (h.radiosity if start is None else start).copy()
    k, changes, change, irradiance = 0, [], np.inf, None

    def gather(b):
        irradiance = np.asarray(matrix @ b)
        new = push_pull(h, irradiance, exitance, levels, gather_scale) + kept
        # the reflected light, not the lamps; where almost none is (a lamp facing away) the change
        # is measured against 1e-9 of the lamps' exitance, so a dark scene converges too
        scale = max(float(np.abs(new - exitance).max()), 1e-9 * float(np.abs(exitance).max()))
        return new, irradiance, float(np.abs(new - b).max()) / scale

    if krylov:
        # a few gather steps first: from a converged start (an edit) they finish the solve, and
        # their contraction says whether GMRES (whose set-up costs more than a few products) pays
        while k < PROBE_STEPS and k < max_iterations:
            k += 1
            b, irradiance, change = gather(b)
            changes.append(change)
            if change < tolerance:
                break
        if change >= tolerance and _steps_left(changes, tolerance) > GATHER_STEPS_LEFT:
            b, spent = _krylov(h, matrix, exitance, levels, gather_scale, kept, b, tolerance, max_iterations - k)
            k += spent
    while change >= tolerance and (k < max_iterations or irradiance is None):  # at least one
        k += 1
        b, irradiance, change = gather(b)
    h.radiosity[:] = b
    h.irradiance[:] = irradiance
    dark = float(np.abs(b - exitance).max()) < 1e-9 * float(np.abs(exitance).max())
    return SolveResult(k, change, change < tolerance, dark, gather_scale)
