"""Newton's method for the FEM steady states: equilibrated LU, the log update, chord steps.

The unknown is :math:`u_h = \\ln P_h`; a Newton step :math:`\\delta` on :math:`u` is applied
as :math:`\\ln(1 + \\delta)` (:func:`log_update`), the Newton step on :math:`P`.  The
dense Jacobian is factorised after row and column equilibration
(:class:`EquilibratedLU`); near convergence the factorisation is reused (chord steps,
:func:`newton_steady`, as a Jacobian in :math:`P`), and an update that stops decreasing at
round-off counts as converged (:func:`stalled`, :func:`newton_info`).  Used by
:mod:`kinetic_fem.solvers.fem` (heated), :mod:`~kinetic_fem.solvers.fem.cooling` and
:mod:`~kinetic_fem.solvers.fem.transient`.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
import weakref
from collections.abc import Callable
from dataclasses import replace

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ...distribution import RunInfo
from ...operators.fem_discretisation import FEMDiscretisation
from ...operators.fem_transport import TransportArrays
from ..newton import newton

__all__ = ["STALL_LEVEL", "CHORD_LEVEL", "CHORD_RATE", "PREDICT_MARGIN", "log_update",
           "EquilibratedLU", "EvenFold", "transport_arrays",
           "newton_steady", "stalled", "newton_info"]

logger = logging.getLogger(__name__)

STALL_LEVEL = 1e-8
"""A Newton update that stops decreasing below this is round-off: converged."""


def log_update(delta: NDArray, limit: float = 10.0) -> NDArray:
    """Map a Newton step on ``u`` to ``ln(1 + delta)``: the Newton step on ``P``.

    Exact for the linear tail equation and equal to ``delta`` to second order, so
    the iteration stays quadratic; decreases are limited to ``-limit``.

    Parameters
    ----------
    delta : ndarray
        Newton step on :math:`u = \\ln P`.
    limit : float
        Largest decrease of :math:`u` in one step.
    """
    return np.log1p(np.maximum(delta, math.expm1(-limit)))


class EquilibratedLU:
    """LU factors of ``J`` scaled to unit row and column maxima.

    Rows and columns of far-tail dofs scale with :math:`P \\sim 10^{-30}` (or much less
    in a first iterate), so the plain matrix is numerically singular; the scaled one
    is well conditioned.

    Parameters
    ----------
    jac : ndarray, shape (m, m)
        The dense Jacobian.
    """

    def __init__(self, jac: NDArray) -> None:
        tiny = np.finfo(float).tiny  # an all-zero row or column stays finite
        self.rows = np.maximum(np.abs(jac).max(axis=1), tiny)
        scaled = jac / self.rows[:, None]
        self.cols = np.maximum(np.abs(scaled).max(axis=0), tiny)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            self.lu = scipy.linalg.lu_factor(scaled / self.cols[None, :])

    def solve(self, rhs: NDArray) -> NDArray:
        """``J^{-1} rhs``."""
        return scipy.linalg.lu_solve(self.lu, rhs / self.rows) / self.cols


class EvenFold:
    """Sums over the mirror pairs of dofs: :math:`S^T r` and :math:`S^T J S` of the even
    reduction ``S`` (:attr:`FEMDiscretisation.symmetry
    <kinetic_fem.operators.fem_discretisation.FEMDiscretisation.symmetry>`, one 1 per row)
    by indexing instead of sparse products with dense blocks (those cost about 10 % of a
    heated state).  Every reduced entry is the sum of one or two entries, so the result
    equals the sparse products bit for bit.

    Parameters
    ----------
    sym : scipy.sparse.csr_matrix, shape (N, n)
        The reduction: row ``i`` has its single 1 in the column of dof ``i``'s pair.
    """

    def __init__(self, sym) -> None:
        cols = np.asarray(sym.indices, dtype=np.int64)
        n = int(sym.shape[1])
        order = np.argsort(cols, kind="stable")
        self.cols = cols
        self.counts = np.bincount(cols, minlength=n).astype(float)
        starts = np.searchsorted(cols[order], np.arange(n))
        self.first = order[starts]
        self.pairs = np.flatnonzero(self.counts == 2)
        self.second = order[starts[self.pairs] + 1]
        if np.any(self.counts < 1) or np.any(self.counts > 2):
            raise ValueError("every reduced dof must stand for one or two dofs")

    def expand(self, u_red: NDArray) -> NDArray:
        """``S u_red``: the full field of the reduced coefficients."""
        return u_red[self.cols]

    def vector(self, r: NDArray) -> NDArray:
        """``S^T r``."""
        out = r[self.first]
        out[self.pairs] += r[self.second]
        return out

    def matrix(self, jac: NDArray) -> NDArray:
        """``S^T J S`` (columns first, as ``S^T (S^T J^T)^T``)."""
        half = jac[:, self.first]
        half[:, self.pairs] += jac[:, self.second]
        out = half[self.first]
        out[self.pairs] += half[self.second]
        return out


_FORMS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def transport_arrays(disc: FEMDiscretisation) -> TransportArrays:
    """The :class:`~kinetic_fem.operators.fem_transport.TransportArrays` of a
    discretisation, made once and kept while the discretisation lives.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation.
    """
    forms = _FORMS.get(disc)
    if forms is None:
        forms = _FORMS[disc] = TransportArrays(disc.basis, disc.friction)
    return forms


def power_of_two_scales(jac: NDArray) -> NDArray:
    """Row scales of a Jacobian: for each row the power of two in
    :math:`(m, 2m]`, :math:`m = \\max_j |J_{ij}|` (dividing by it is exact).

    Parameters
    ----------
    jac : ndarray, shape (n, n)
        The Jacobian.
    """
    top = np.maximum(np.abs(jac).max(axis=1), np.finfo(float).tiny)
    return np.ldexp(1.0, np.frexp(top)[1])


CHORD_ROW_SCALES = True
"""Default of ``row_scales`` in :func:`newton_steady` (issue 16)."""
CHORD_IN_P = True
"""Default of ``p_chord`` in :func:`newton_steady` (issue 16: with the 2x coarse mesh of
P3, one fine Jacobian at most alphas; Maxwell 1.22x, saturating 1.13x, bath 1.12x)."""
CHORD_LEVEL = 1e-3
"""Below this Newton update the Jacobian's factorisation is reused (chord steps)."""
CHORD_RATE = 0.1
"""A chord step that shrinks the update by less than this factor refreshes the Jacobian."""
PREDICT_MARGIN = 0.01
"""Stop after a chord step when its rate times its size is below this times ``tol``."""


def newton_steady(disc: FEMDiscretisation, u0: NDArray[np.float64], *, tol: float = 1e-11,
                  max_iter: int = 40, step_limit: float = 10.0,
                  chord: bool = True, chord_level: float = CHORD_LEVEL
                  ) -> tuple[NDArray, RunInfo]:
    """Newton iteration for the even steady state with :math:`\\int P_h = 1`.

    The update of each dof is :math:`\\ln(1 + \\delta)` (see :func:`log_update`).

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation.
    u0 : ndarray, shape (N,)
        Starting :math:`\\ln P_h`.
    tol : float
        Stop when the largest update is below ``tol`` (or stalls at round-off).
    max_iter : int
        Iteration limit (Newton and chord steps together).
    step_limit : float
        Largest decrease of :math:`\\ln P` in one step.
    chord : bool
        Once the update is below :data:`CHORD_LEVEL`, reuse the last factorisation
        (residual only, about half the cost of the Jacobian) while each step shrinks
        the update by :data:`CHORD_RATE` or more; otherwise refresh it.  The chord
        error after a step is the step times its rate, so the stopping rule keeps its
        meaning (measured: T and a2 equal to plain Newton's to 1e-13); a chord step whose
        rate times size is below :data:`PREDICT_MARGIN` ``* tol`` ends the iteration
        without the residual that would confirm it.
    chord_level : float
        The update below which chord steps start (default :data:`CHORD_LEVEL`; larger
        from a start already near the state, e.g. a coarse mesh's solution).

    Returns
    -------
    ndarray, RunInfo
        :math:`\\ln P_h` and the run info.

    Notes
    -----
    With :data:`CHORD_ROW_SCALES` the residual of the chord test is measured row by row
    relative to the row's largest Jacobian entry (a power of two, so the Newton steps are
    unchanged bit for bit): the max-norm of the plain residual reaches round-off while
    the far tail's update is still 1e-9, and its chord steps then failed the decrease
    test and refreshed the Jacobian.  With :data:`CHORD_IN_P` chord steps use the
    factorised Jacobian as one in :math:`P`: the step of the factorisation point's
    :math:`\\delta P / P_J` times :math:`P_J / P = e^{u_J - u}` (exact for the
    equations linear in :math:`P`, the far tail; the contraction of a chord step from a
    coarse mesh's state goes from about 1e-2 to 1e-4).
    """
    start = time.perf_counter()
    row_scales, p_chord = CHORD_ROW_SCALES, CHORD_IN_P
    sym = disc.symmetry
    fold = EvenFold(sym)
    # the dof at v = 0 carries the normalisation instead of its (redundant) equation
    red_x = np.zeros(sym.shape[1])
    red_x[sym.indices] = np.abs(disc.dof_locations)
    row0 = int(np.argmin(red_x))

    # the thermostat forms from element arrays evaluated once (equal to disc.transport
    # and asm(mass) to round-off, without the per-call assembly)
    forms = transport_arrays(disc)

    def system(u_red: NDArray, jacobian: bool) -> tuple[NDArray, NDArray | None]:
        u = fold.expand(u_red)
        # u is even: the collision sums visit v > 0 only
        coll, cjac, _ = disc.collision(u, jacobian=jacobian, energy_power=None, even=True)
        heat, hjac, grad_mass = forms.transport(u, jacobian=jacobian)
        r = fold.vector(coll + heat)
        r[row0] = grad_mass.sum() - 1.0
        if not jacobian:
            return r, None
        cjac += hjac  # the kernel's own array (the same sums as cjac + hjac)
        j = fold.matrix(cjac)
        j[row0] = fold.vector(grad_mass)
        if row_scales:
            scales[0] = power_of_two_scales(j)
        return r, j

    u_red = fold.vector(u0) / fold.counts
    scales: list[NDArray] = [np.ones(fold.counts.size)]
    n_jac = 0

    # the points of the last Jacobian and of the last residual (the chord steps' iterate)
    at: dict[str, NDArray] = {}

    def fun(x: NDArray, jacobian: bool) -> tuple[NDArray, NDArray | None]:
        nonlocal n_jac
        n_jac += int(jacobian)
        at["r"] = x
        if jacobian:
            at["J"] = x
        return system(x, jacobian)

    def factorize(jac: NDArray) -> Callable[[NDArray], NDArray]:
        lu = EquilibratedLU(jac)
        if not p_chord:
            return lu.solve
        base = at["J"]

        def solve(rhs: NDArray) -> NDArray:
            step = lu.solve(rhs)
            here = at["r"]
            # a chord step: the step on P with the factorised dP-Jacobian, relative to
            # this iterate's P (exact for the equations linear in P: the tail)
            return step if here is base else step * np.exp(base - here)

        return solve

    out = newton(fun, u_red, tol=tol, max_iter=max_iter, criterion="step",
                 update=lambda x, d: x + log_update(d, step_limit), line_search=False,
                 stall_level=STALL_LEVEL, factorize=factorize,
                 chord=chord_level if chord else 0.0, chord_rate=CHORD_RATE,
                 predict=PREDICT_MARGIN, name="FEM Newton",
                 row_scale=(lambda x: scales[0]) if row_scales else None)
    history = list(out.history)
    predicted = "chord-predicted" in out.message
    text = f"Newton max|du| history {['%.1e' % h for h in history]}"
    if predicted:
        text += ", chord-predicted"
    elif not out.converged:
        text = f"{out.message}; {text}"
    info = RunInfo(converged=out.converged, iterations=out.iterations,
                   residual=history[-1] if history else math.inf,
                   wall_time=time.perf_counter() - start, message=text)
    return fold.expand(out.x), replace(info, message=f"{info.message}; {n_jac} Jacobians")


def stalled(history: list[float]) -> bool:
    """The update stopped decreasing below :data:`STALL_LEVEL`: round-off reached.

    Parameters
    ----------
    history : list of float
        Largest update of each iteration so far.
    """
    return len(history) >= 3 and history[-1] < STALL_LEVEL and \
        history[-1] > 0.25 * min(history[-3:-1])


def newton_info(history: list[float], tol: float, iterations: int, start: float) -> RunInfo:
    """Run info of a Newton iteration: converged below ``tol`` or stalled at round-off.

    Parameters
    ----------
    history : list of float
        Largest update of each iteration.
    tol : float
        The stopping tolerance.
    iterations : int
        Iterations made.
    start : float
        ``time.perf_counter()`` at the start.
    """
    step = history[-1]
    text = f"Newton max|du| history {['%.1e' % s for s in history]}"
    if step >= tol and stalled(history):
        text = (f"Newton stalled at round-off, max|du| = {step:.1e} (tol {tol:.0e}); "
                + text)
        logger.info("%s", text)
    return RunInfo(converged=step < tol or stalled(history), iterations=iterations,
                   residual=step, wall_time=time.perf_counter() - start, message=text)

