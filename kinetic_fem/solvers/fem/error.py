"""A posteriori error estimates of the FEM steady states: one Newton step on the bisected mesh.

The state :math:`u_h = \\ln P_h` is interpolated exactly onto the mesh with every element
bisected (:math:`u_h` lies in the finer Lagrange space) and one Newton step of the same
equations is taken there from it:

.. math::

    \\delta = -J_{h/2}(u_h)^{-1} R_{h/2}(u_h) \\approx u_{h/2} - u_h ,

the change the finer mesh makes, which is the error of :math:`u_h` up to the share
:math:`2^{-(k+1)}` the finer state keeps (degree :math:`k`;
:func:`kinetic_fem.error.richardson_factor`).  The estimate is the difference of the
result from the distribution of :math:`u_h + \\delta` on the finer mesh (moments by its
quadrature, so the outer quadrature error of the result is included).  It solves the
global linearised problem, so it carries the error the collision operator transports
from the bulk to the tail (unlike a local indicator).  Cost: one Jacobian on twice the
dofs, paid when ``dist.error`` is first read.

Heated states: :func:`heated_estimate` (the Newton of
:func:`kinetic_fem.solvers.fem.newton.newton_steady`, one iteration); cooling states:
:func:`cooling_estimate` (:func:`kinetic_fem.solvers.fem.cooling_newton.newton_cooling`,
one undamped Newton step, with :math:`\\zeta`).
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...error import ErrorEstimate, ErrorRecipe, richardson_factor
from ...operators.fem_discretisation import FEMDiscretisation
from .newton import newton_steady

__all__ = ["bisected", "interpolated_log", "heated_estimate", "heated_recipe",
           "cooling_estimate", "cooling_recipe", "BISECTED_METHOD"]

logger = logging.getLogger(__name__)

BISECTED_METHOD = "one Newton step on the bisected mesh"


def bisected(disc: FEMDiscretisation) -> FEMDiscretisation:
    """The same discretisation with every element bisected.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation.

    Returns
    -------
    FEMDiscretisation
    """
    verts = disc.vertices
    fine = np.sort(np.concatenate([verts, 0.5 * (verts[1:] + verts[:-1])]))
    return replace(disc, vertices=fine)


def interpolated_log(disc: FEMDiscretisation, u: NDArray, fine: FEMDiscretisation) -> NDArray:
    """Coefficients of :math:`u_h` in the finer space of ``fine`` (exact interpolation).

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation of ``u``.
    u : ndarray
        Coefficients of :math:`u_h = \\ln P_h`.
    fine : FEMDiscretisation
        A discretisation whose mesh refines ``disc``'s, of the same degree.

    Returns
    -------
    ndarray
    """
    loc = fine.dof_locations
    order = np.argsort(loc)
    out = np.empty_like(loc)
    out[order] = np.log(disc.evaluate(u, loc[order]))
    return out


def heated_estimate(disc: FEMDiscretisation, u: NDArray,
                    dist: VelocityDistribution) -> ErrorEstimate:
    """The bisected-mesh estimate of a heated steady state.

    Parameters
    ----------
    disc : FEMDiscretisation
        The state's discretisation (``n = D = 1``).
    u : ndarray
        Its :math:`u_h = \\ln P_h`.
    dist : VelocityDistribution
        The result (any units).

    Returns
    -------
    ErrorEstimate
    """
    fine = bisected(disc)
    u_fine = interpolated_log(disc, u, fine)
    u_step, _ = newton_steady(fine, u_fine, max_iter=1, tol=1e-300, chord=False)
    better = fine.distribution(u_step)
    base = disc.distribution(u)
    return ErrorEstimate.from_comparison(base, better, method=BISECTED_METHOD,
                                         factor=richardson_factor(disc.order))


def heated_recipe(disc: FEMDiscretisation, u: NDArray) -> ErrorRecipe:
    """The :class:`~kinetic_fem.error.ErrorRecipe` of a heated state (see
    :func:`heated_estimate`).

    Parameters
    ----------
    disc : FEMDiscretisation
        The state's discretisation.
    u : ndarray
        Its :math:`u_h = \\ln P_h`.
    """
    return ErrorRecipe(lambda dist: heated_estimate(disc, u, dist), BISECTED_METHOD)


def cooling_estimate(disc: FEMDiscretisation, u: NDArray, zeta: float,
                     build: Callable[..., VelocityDistribution]) -> ErrorEstimate:
    """The bisected-mesh estimate of a cooling state, with :math:`\\zeta`.

    Parameters
    ----------
    disc : FEMDiscretisation
        The state's discretisation (scaled velocities).
    u : ndarray
        Its :math:`u_h = \\ln f_h`.
    zeta : float
        Its cooling rate.
    build : callable
        ``build(disc, u) -> VelocityDistribution``: how the result is made from a state
        (the plain quadrature-point values, or the recovered tail of the Maxwell model).

    Returns
    -------
    ErrorEstimate
    """
    from .cooling_newton import newton_cooling  # (imports fem: not at module level)

    fine = bisected(disc)
    u_fine = interpolated_log(disc, u, fine)
    step = newton_cooling(fine, u_fine, zeta, max_iter=1, tol=1e-300, pseudo_time=math.inf,
                          line_search=False)
    better = build(fine, step.u)
    base = build(disc, u)
    est = ErrorEstimate.from_comparison(base, better, method=BISECTED_METHOD,
                                        factor=richardson_factor(disc.order),
                                        zeta=(zeta, step.zeta))
    # the scaled state has unit temperature by construction (a constraint of Newton's
    # system): its error is the constraint's residual, not the step's second-order one
    return replace(est, temperature=abs(base.temperature - 1.0))


def cooling_recipe(disc: FEMDiscretisation, u: NDArray, zeta: float,
                   build: Callable[..., VelocityDistribution]) -> ErrorRecipe:
    """The :class:`~kinetic_fem.error.ErrorRecipe` of a cooling state (see
    :func:`cooling_estimate`).

    Parameters
    ----------
    disc, u, zeta, build
        As in :func:`cooling_estimate`.
    """
    def compute(dist: Any) -> ErrorEstimate:
        return cooling_estimate(disc, u, zeta, build)

    return ErrorRecipe(compute, BISECTED_METHOD)
