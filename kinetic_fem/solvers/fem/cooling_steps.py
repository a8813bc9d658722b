"""Cheaper Newton steps for the FEM cooling state (issue 16, ninth round).

Two pieces of :func:`~kinetic_fem.solvers.fem.cooling_newton.newton_cooling` from a close
start, both with the same iterates as before (``benchmarks/archive/results/fem_cooling_speed.md``):

* :class:`SpeculativeSystem`: the line search's trial residual comes with its Jacobian,
  kept for the next call at the same point.  In the continuation links the first trial
  was accepted at damping 1 in nearly every step, and a residual costs 0.6 of a Jacobian
  there: one collision call per step instead of two.
* :func:`newton_on_step`: Newton's method that first stops on the step (the shared
  driver's chord prediction: a chord step whose successor is predicted below ``tol``
  ends it without the residual that would confirm it), then, if that has not converged
  within ``predict_iter`` steps (a step stalling at round-off), on the residual from
  where it stopped.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ..newton import NewtonResult, newton

__all__ = ["PREDICT_ITER", "SpeculativeSystem", "newton_on_step"]

PREDICT_ITER = 8
"""Steps of the default P3 state's Newton that stop on the step (``predict_iter``): from
the link state it converges in three or four (two Jacobians, then residuals and chord
steps; the last chord step's successor is predicted at 1e-18 ... 6e-12), so the residual
that confirmed the last chord step (a third of a Jacobian on the finest mesh) is saved,
with the same iterates; with 4 the residual rule took over at 2 of 24 inelasticities in
[1e-3, 0.035] (a Jacobian more), with 8 at none."""


class SpeculativeSystem:
    """A system whose residual calls bring their Jacobian, handed out at the next call
    at the same ``x`` (once).

    Parameters
    ----------
    system : callable
        ``system(x, jacobian) -> (r, J)`` (:func:`kinetic_fem.solvers.newton.newton`).
    """

    def __init__(self, system: Callable[[NDArray, bool], tuple[NDArray, Any]]) -> None:
        self.system = system
        self.cache: tuple[NDArray, NDArray, Any] | None = None

    def __call__(self, x: NDArray, jacobian: bool = True) -> tuple[NDArray, Any]:
        """``(r, J)`` at ``x`` (``J`` None unless asked for)."""
        if self.cache is not None and np.array_equal(self.cache[0], x):
            _, r, j = self.cache
            if not jacobian or j is not None:
                self.cache = (x, r, None if jacobian else j)
                return r, j if jacobian else None
        r, j = self.system(x, True)
        self.cache = (x.copy(), r, None if jacobian else j)
        return r, j if jacobian else None


def newton_on_step(fun, x: NDArray, *, tol: float, residual_tol: float, max_iter: int,
                   predict_iter: int, stall_level: float, **options) -> tuple[NewtonResult,
                                                                             bool]:
    """Newton's method stopping on the step first, then on the residual.

    Parameters
    ----------
    fun : callable
        The system (:func:`kinetic_fem.solvers.newton.newton`).
    x : ndarray
        Start.
    tol : float
        Tolerance of the step (first phase).
    residual_tol : float
        Tolerance of the residual (second phase).
    max_iter : int
        Steps in all.
    predict_iter : int
        Steps of the first phase (0: none).
    stall_level : float
        Stall rule of the second phase.
    **options
        Passed to :func:`~kinetic_fem.solvers.newton.newton` (``norm``, ``step_norm``,
        ``update``, ``factorize``, ``chord``, ...).

    Returns
    -------
    result : NewtonResult
        ``iterations`` counts both phases.
    on_step : bool
        The first phase converged.
    """
    done = 0
    if predict_iter > 0:
        res = newton(fun, x, tol=tol, max_iter=min(predict_iter, max_iter),
                     criterion="step", predict=1.0, **options)
        if res.converged:
            return res, True
        done, x = res.iterations, res.x
    res = newton(fun, x, tol=residual_tol, max_iter=max_iter - done, criterion="residual",
                 stall_level=stall_level, **options)
    return replace(res, iterations=res.iterations + done), False
