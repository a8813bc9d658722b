"""Stored starts of the near-elastic hard-rod cooling state (issue 16, ninth round).

``kf.solve_cooling(1 - eps)`` for hard rods at :math:`10^{-3} \\le \\varepsilon < 0.04`
walks a continuation in :math:`\\varepsilon` (:mod:`.cooling_links`).  It used to
start from a coarse state at :math:`\\varepsilon = 0.1` solved from a Gaussian (18
pseudo-transient steps) and take one or two links of ratio up to 16 (12-14 Newton steps
each: the start rescaled on the hump variable overestimates the outer edge by up to 36
e-folds, which Newton brings down ten e-folds per step).  Now it starts from the nearest
stored state at or above the target, :data:`SEED_EPS` = 0.04, 0.01, 0.0025 (a ratio of
at most 4): one link of 5-10 Newton steps, then the state asked for on its fine mesh as
before.  A seed is :math:`\\ln f` of a converged link state (P2 at 0.3 hump widths, cut
off 45 decades down, Newton tolerance 1e-7) at its vertices with :math:`c \\ge 1/2` (all
:meth:`~kinetic_fem.solvers.fem.cooling_newton.CoolingState.rescaled_log_f` reads),
rounded to 8 digits, and its :math:`\\zeta`, stored in ``data/hard_rod_seeds.json``
(:mod:`.cooling_stored`); ``python -m kinetic_fem.solvers.fem.cooling_generate seeds``
recomputes them (a slow test checks the stored table against it).  The seed only
starts Newton's method: the state returned solves the discrete equations on the default
mesh to the Newton tolerance, as before (the mesh is built from the link state, so the
states move within their discretisation error: ``benchmarks/archive/results/fem_cooling_speed.md``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from .cooling_newton import CoolingState
from .cooling_stored import hard_rod_seeds

__all__ = ["SEED_EPS", "SeedStart", "seed_start"]

SEED_EPS = (0.04, 0.01, 0.0025)
"""Inelasticities of the stored starts (decreasing)."""


class SeedStart(CoolingState):
    """A stored start: what a continuation step reads of a state.

    :meth:`log_f` is the cubic spline of the stored :math:`\\ln f` (even), continued
    linearly beyond the last node with the slope of the last interval; ``zeta``.

    Parameters
    ----------
    c : array_like, shape (K,)
        Increasing nodes, the first at or below :math:`c = 1/2`.
    log_f : array_like, shape (K,)
        :math:`\\ln f` there.
    zeta : float
        Cooling rate of the stored state.
    """

    def __init__(self, c, log_f, zeta: float) -> None:
        super().__init__(None, np.empty(0), zeta, None)  # type: ignore[arg-type]
        self.c = np.asarray(c, dtype=float)
        self.values = np.asarray(log_f, dtype=float)
        self.spline = CubicSpline(self.c, self.values)
        self.slope = min(float((self.values[-1] - self.values[-2])
                               / (self.c[-1] - self.c[-2])), 0.0)

    def log_f(self, c: NDArray) -> NDArray:
        """:math:`\\ln f` at ``c`` (:math:`|c| \\ge 1/2`; linear beyond the last node)."""
        c_abs = np.abs(np.asarray(c, dtype=float))
        c_in = np.clip(c_abs, self.c[0], self.c[-1])
        return self.spline(c_in) + self.slope * np.maximum(c_abs - self.c[-1], 0.0)


def seed_start(eps: float) -> tuple[SeedStart, float]:
    """The stored start for a state at ``eps``: the smallest seed at or above it.

    Parameters
    ----------
    eps : float
        Inelasticity asked for, in [1e-3, 0.04) for the default path (above the
        largest seed: the largest).

    Returns
    -------
    start : SeedStart
    eps_seed : float
        Its inelasticity.

    Examples
    --------
    >>> start, eps_seed = seed_start(1e-3)
    >>> eps_seed, round(start.zeta / eps_seed, 6)
    (0.0025, 1.000076)
    """
    above = [s for s in SEED_EPS if s >= eps * (1.0 - 1e-12)]
    eps_seed = min(above) if above else max(SEED_EPS)
    zeta, c, log_f = hard_rod_seeds()[eps_seed]
    return SeedStart(c, log_f, zeta), eps_seed
