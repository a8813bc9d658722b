"""Default meshes and starting guesses of the FEM homogeneous cooling state.

The scaled cooling state :math:`f(c)` (unit temperature) of
:mod:`kinetic_fem.solvers.fem.cooling` is resolved on a symmetric mesh: uniform P2
elements in the bulk, graded in the tail :math:`\\ln f \\simeq -c^\\gamma/(\\gamma\\zeta)`
out to the cut-off where it has fallen 33 decades (:func:`hcs_vertices`); the inelastic
Maxwell model's :math:`c^{-4}` tail on a geometric mesh out to :data:`MAXWELL_CUTOFF` when
a ``cutoff`` is given (the default ends at :math:`c = 200` with an analytic tail:
:mod:`kinetic_fem.solvers.fem.cooling_maxwell`).
Near elastic collisions the meshes of :mod:`kinetic_fem.operators.adaptive` follow the
two humps instead.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...model import CoolingProblem
from ...operators.mesher import ScaleGrading
from ..continuation import geometric_path
from .cooling_tail import POWER_TAIL_CUTOFF, POWER_TAIL_SPACING, power_tail_vertices

__all__ = ["hcs_bulk", "BULK_EPS", "hcs_cutoff", "hcs_spacing", "hcs_vertices", "initial_log_f",
           "MAXWELL_CUTOFF", "DECADES", "HUMP_INTORDER", "LOW_ORDER_EPS", "step_intorder",
           "log_chain"]

MAXWELL_CUTOFF = POWER_TAIL_CUTOFF
"""Cut-off of the Maxwell-model mesh: the energy beyond, 4/(pi V), is 1e-8."""
DECADES = 33.0
"""The default cut-off is where the tail estimate has fallen this many decades."""
HUMP_INTORDER = 9
"""Gauss degree (5 points per element) of the near-elastic hump meshes, instead of
``2 * order + 1`` (3 points for P2).

In the outer edge of the humps :math:`\\ln f \\simeq -|y|^3/3` falls up to one e-fold
per element, and the 3-point Gauss rule integrates :math:`e^{u_h}` there with a relative
error of about 1e-5.  The outer edge is a balance of the cooling drift against the net
collisional shift, each of relative size :math:`\\varepsilon^{2/3} y^2` against the gain
and the loss, so that error is amplified by :math:`\\varepsilon^{-2/3}` and accumulates
over the :math:`|\\ln f|` e-folds of the edge.  Measured at :math:`\\varepsilon = 10^{-4}`,
0.05 hump widths (``benchmarks/results/fem_cooling.md``): ln f where f > 1e-30 moves
by 8.7e-3 from degree 5 to 9 (the whole error of the old default), and by 3e-6 from
9 at 0.71 e-folds per edge element to 9 at 0.25; zeta by 4.6e-12.  With degree 5 the
linearised operator has a growing mode at the cut-off (+26 zeta at
:math:`\\varepsilon = 1.22\\cdot 10^{-5}`, the former frontier); with 9 none, and the
continuation converges down to :math:`\\varepsilon = 10^{-6}`."""
LOW_ORDER_EPS = 1e-4
"""Intermediate continuation states at or above this inelasticity keep the cheaper
``2 * order + 1`` rule (they only start the next step; the 3-point rule converged on
them down to 2.4e-5)."""


def step_intorder(eps: float, order: int, final: bool) -> int | None:
    """Gauss degree of a continuation step on the hump mesh.

    Parameters
    ----------
    eps : float
        Inelasticity of the step.
    order : int
        Lagrange degree.
    final : bool
        The state asked for (not an intermediate one).

    Returns
    -------
    int or None
        ``2 * order + 1`` for an intermediate state at ``eps >=`` :data:`LOW_ORDER_EPS`,
        else None (the default :data:`HUMP_INTORDER` of the hump meshes).
    """
    return 2 * order + 1 if not final and eps >= LOW_ORDER_EPS else None


def log_chain(eps: float, start: float, ratio: float) -> list[float]:
    """Inelasticities from ``start`` down to ``eps`` in equal steps on a log scale, each a
    ratio of at most ``ratio``, ending exactly at ``eps`` (``start`` left out).

    Parameters
    ----------
    eps : float
        The last inelasticity, below ``start``.
    start : float
        The inelasticity of the starting state.
    ratio : float
        Largest ratio of successive inelasticities, > 1.

    Returns
    -------
    list of float

    Examples
    --------
    >>> [round(e, 6) for e in log_chain(1e-3, 0.1, 8.0)]
    [0.021544, 0.004642, 0.001]
    """
    return geometric_path(start, eps, ratio)


def hcs_cutoff(problem: CoolingProblem) -> float:
    """Cut-off :math:`V` (thermal velocities) of the HCS mesh.

    The tail :math:`\\zeta c f' \\approx -c^\\gamma f` gives
    :math:`\\ln f \\approx -c^\\gamma/(\\gamma\\zeta)`; :math:`V` is where that reaches 33
    decades, at least the outer edge :math:`1 + 12\\varepsilon^{1/3}` of the near-elastic
    humps and, for :math:`\\gamma < 2`, 12 (a Gaussian's 1e-33), plus 1.5;
    :data:`MAXWELL_CUTOFF` for the Maxwell model's power law.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (kernel and restitution).

    Returns
    -------
    float
    """
    gamma = problem.gas.gamma
    if gamma == 0.0:
        return MAXWELL_CUTOFF
    zeta = problem.zeta_estimate()
    eps = problem.gas.epsilon
    tail = (DECADES * math.log(10.0) * gamma * zeta) ** (1.0 / gamma)
    # a Gaussian's 1e-33 (c = 12) bounds the cut-off from below for gamma < 2; for
    # gamma >= 2 the tail estimate is the steeper one (gamma = 2, alpha = 0.95: ln f ~ -5 c^2,
    # f underflows before c = 12 and the Newton system turned singular there)
    floor = 12.0 if gamma < 2.0 else 0.0
    return min(max(tail, 1.0 + 12.0 * eps ** (1.0 / 3.0), floor) + 1.5, MAXWELL_CUTOFF)


def hcs_spacing(problem: CoolingProblem) -> float:
    """Bulk P2 element size: :math:`\\min(0.05, \\varepsilon^{1/3}/10)` (0.02 for the
    Maxwell model), from ``benchmarks/convergence_fem_cooling.py`` (alpha = 0.85:
    zeta 1.8e-9, a2 8e-9 at 0.05; 3.1e-8, 1.4e-7 at 0.1; fourth order).

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (kernel and restitution).

    Returns
    -------
    float
    """
    if problem.gas.gamma == 0.0:
        return POWER_TAIL_SPACING
    return min(0.05, problem.gas.epsilon ** (1.0 / 3.0) / 10.0)


BULK_EPS = 0.2
"""Below this inelasticity the uniform bulk of the HCS mesh reaches the outer edge of the
near-elastic humps, :math:`1 + 12\\varepsilon^{1/3}`; above it, :math:`c = 3`."""


def hcs_bulk(eps: float) -> float:
    """Extent (thermal velocities) of the uniform bulk of the HCS mesh.

    :math:`c = 3` for :math:`\\varepsilon \\ge` :data:`BULK_EPS`, else
    :math:`\\max(3, 1 + 12\\varepsilon^{1/3})`.  Measured against a state at half the
    spacing (alpha = 0, 0.5, 0.7, 0.8: zeta, a2 and f where f > 1e-30 unchanged with the
    bulk to 3 instead of 13 .. 8, at half the vertices; alpha = 0.9: f error 1.2e-4 with
    3, 5.2e-5 with 5 or more).

    Parameters
    ----------
    eps : float
        Inelasticity :math:`1 - \\alpha`.

    Returns
    -------
    float
    """
    return 3.0 if eps >= BULK_EPS else max(3.0, 1.0 + 12.0 * eps ** (1.0 / 3.0))


def hcs_vertices(c_max: float, spacing: float, *, gamma: float,
                 bulk: float = 3.0) -> NDArray[np.float64]:
    """Symmetric HCS vertices: uniform ``spacing`` up to ``bulk``, then graded.

    Element size :math:`h(c) = h_0 \\max(1, c/c_b)^{\\kappa}` with
    :math:`\\kappa = (3 - \\gamma)/3` (P2 error :math:`h^3 (\\ln f)'''` constant in the
    tail :math:`\\ln f \\sim -c^\\gamma`); for the Maxwell model the geometric mesh of
    :func:`kinetic_fem.solvers.fem.cooling_tail.power_tail_vertices`.

    Parameters
    ----------
    c_max : float
        Half-width of the mesh (thermal velocities).
    spacing : float
        Bulk element size :math:`h_0`.
    gamma : float
        Kernel exponent (sets the grading).
    bulk : float
        Extent :math:`c_b` of the uniform bulk (:func:`hcs_bulk`).

    Returns
    -------
    ndarray
        Vertices symmetric about 0, including 0.

    Examples
    --------
    >>> v = hcs_vertices(20.0, 0.1, gamma=1.0)
    >>> bool(v[0] == -20.0 and v[-1] == 20.0 and np.all(np.diff(v) > 0))
    True
    """
    if gamma == 0.0:
        # --- the Maxwell model's c^-4 tail: kinetic_fem.solvers.fem.cooling_tail ---
        return power_tail_vertices(c_max, spacing)
    # the drop of ln f ~ -c^gamma spread evenly: h^3 (ln f)''' constant in the tail
    return ScaleGrading(spacing, (3.0 - gamma) / 3.0, bulk).marched(c_max)


def initial_log_f(c: NDArray, gamma: float, zeta: float) -> NDArray:
    """A starting :math:`\\ln f`: Gaussian bulk continued by the tail
    :math:`-c^\\gamma/(\\gamma\\zeta)` matched in value and slope (a :math:`c^{-4}` power
    law for the Maxwell model); normalised on a fine grid.

    Parameters
    ----------
    c : ndarray
        Scaled velocities.
    gamma : float
        Kernel exponent.
    zeta : float
        Estimate of the cooling rate.

    Returns
    -------
    ndarray
        :math:`\\ln f` at ``c``.
    """
    c = np.abs(np.asarray(c, dtype=float))
    fine = np.concatenate([np.linspace(0.0, 20.0, 20001)[:-1],
                           np.geomspace(20.0, max(float(c.max()), 21.0), 4000)])
    if gamma == 0.0:
        log_f = -2.0 * np.log1p(0.5 * fine**2)  # a c^-4 law at temperature 2
    elif gamma >= 2.0:
        log_f = -0.5 * fine**2
    else:
        # the tangent continuation: slopes -c and -c^(gamma-1)/zeta meet at c0
        c0 = zeta ** (-1.0 / (2.0 - gamma))
        log_f = np.where(fine < c0, -0.5 * fine**2,
                         -0.5 * c0**2 - (fine**gamma - c0**gamma) / (gamma * zeta))
    vals = np.exp(log_f)
    norm = 2.0 * float(np.sum(0.5 * (vals[1:] + vals[:-1]) * np.diff(fine)))
    return np.interp(c, fine, log_f) - math.log(norm)


