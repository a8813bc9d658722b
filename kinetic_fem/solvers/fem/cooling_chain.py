"""Several near-elastic cooling states from one continuation in the inelasticity.

``kf.solve_cooling(1 - eps)`` for hard rods below
:data:`~kinetic_fem.solvers.fem.cooling.HUMP_EPS` walks the continuation in
:math:`\\varepsilon` from 0.1 down to the target
(:func:`~kinetic_fem.solvers.fem.cooling.hump_chain`);
a figure or a study that needs the states at several inelasticities would walk it once per
state.  :func:`hump_states` walks it once, through every requested inelasticity (the
chain of steps of at most :data:`~kinetic_fem.solvers.fem.cooling.HUMP_RATIO` merged
with the requested values), with the same step control as the default path (a failed
step is retried through the geometric mean, on a log scale, down to a ratio of
:data:`~kinetic_fem.solvers.fem.cooling.HUMP_MIN_RATIO`), and returns the states reached.
A state below the frontier that the continuation cannot reach is left out and reported
in the log, so a figure shows what the solver reaches.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable

from ..continuation import StepRule, continuation
from . import cooling as fc
from .cooling_mesh import step_intorder
from .cooling_newton import CoolingState

__all__ = ["hump_states"]

logger = logging.getLogger(__name__)


def hump_states(eps_values: Iterable[float], *, resolution: float = fc.HUMP_STEP_RESOLUTION,
                tol: float = 1e-11, order: int = 2) -> dict[float, CoolingState]:
    """The hard-rod cooling states at the requested inelasticities, one continuation.

    Parameters
    ----------
    eps_values : iterable of float
        Inelasticities :math:`1 - \\alpha` in
        (0, :data:`~kinetic_fem.solvers.fem.cooling.HUMP_EPS`).
    resolution : float
        Element size of the returned states in the humps, in hump widths
        :math:`\\varepsilon^{1/3}`; the intermediate steps use
        :data:`~kinetic_fem.solvers.fem.cooling.HUMP_STEP_RESOLUTION` (or ``resolution``
        if coarser), and a finer state is re-solved from the intermediate one at the same
        inelasticity (mesh sequencing, as in the default path).
    tol : float
        Newton tolerance of the returned states (intermediates:
        :data:`~kinetic_fem.solvers.fem.cooling.HUMP_STEP_TOL`).
    order : int
        Lagrange degree.

    Returns
    -------
    dict of float to CoolingState
        The converged states, keyed by the requested inelasticities; the continuation
        stops at the first one it cannot reach (the smaller ones are missing).

    Raises
    ------
    ValueError
        For an inelasticity outside (0, HUMP_EPS).

    Examples
    --------
    >>> states = hump_states([0.05], resolution=0.14)  # doctest: +SKIP
    >>> sorted(states)  # doctest: +SKIP
    [0.05]
    """
    wanted = sorted({float(e) for e in eps_values}, reverse=True)
    for eps in wanted:
        if not 0.0 < eps < fc.HUMP_EPS:
            raise ValueError(f"inelasticities must lie in (0, {fc.HUMP_EPS}), got {eps!r}")
    out: dict[float, CoolingState] = {}
    if not wanted:
        return out
    step_res = max(resolution, fc.HUMP_STEP_RESOLUTION)
    chain = sorted(set(fc.hump_chain(wanted[-1])) | set(wanted), reverse=True)
    def solve(prev: CoolingState, eps_prev: float, step: float) -> CoolingState:
        return fc.continued_state(prev, eps_prev, step, resolution=step_res, order=order,
                                  intorder=step_intorder(step, order, step in wanted),
                                  tol=tol if step in wanted else fc.HUMP_STEP_TOL,
                                  max_iter=fc.HUMP_STEP_ITER
                                  if eps_prev / step > fc.HUMP_MIN_RATIO else 100)

    def keep(state: CoolingState, step: float) -> None:
        if step not in wanted:
            return
        if step_res > resolution:  # the continuation goes on from the coarser state
            fine = fc.continued_state(state, step, step, resolution=resolution,
                                      order=order, tol=tol)
            if fine.info.converged:
                state = fine
            else:
                logger.warning("hump_states: the state at eps = %.3g did not converge "
                               "at %g hump widths (%s); kept at %g", step, resolution,
                               fine.info.message, step_res)
        out[step] = state

    walk = continuation(fc.hump_start(order, None), fc.HUMP_EPS, chain, solve,
                        rule=StepRule(min_ratio=fc.HUMP_MIN_RATIO), on_converged=keep)
    if walk.failed is not None:
        logger.warning("hump_states: the continuation stops at eps = %.3g (from %.3g: "
                       "%s); the states below are left out", walk.failed_value, walk.value,
                       walk.failed.info.message)
    return out
