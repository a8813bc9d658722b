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
:func:`kinetic_fem.solvers.fem.cooling_newton.cooling_estimate` (beside the Newton it
steps, one undamped step of :func:`~kinetic_fem.solvers.fem.cooling_newton.newton_cooling`,
with :math:`\\zeta`).
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...error import ErrorEstimate, ErrorRecipe, richardson_factor
from ...operators.fem_discretisation import FEMDiscretisation
from .newton import newton_steady

__all__ = ["bisected", "interpolated_log", "heated_estimate", "heated_recipe",
           "BISECTED_METHOD"]

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
