"""Newton's method for the FEM homogeneous cooling state and the converged state.

The equations are those of :mod:`kinetic_fem.solvers.fem.cooling` (its module docstring
derives them): on the even P2 dofs of :math:`u_h = \\ln f_h` and :math:`\\zeta`,

.. math::

    R_i = C_i[f_h] + \\zeta \\int \\varphi_i'\\, c\\, f_h \\,dc
          - \\zeta \\big[\\varphi_i\\, c f_h\\big]_{-V}^{V} = 0 ,\\qquad
    \\int f_h = 1,\\quad \\int c^2 f_h = 1,

the first replacing the equation at :math:`c = 0`.  Two globalisations: pseudo-transient
continuation from a Gaussian start, and Newton's method with Armijo backtracking (the
shared :func:`kinetic_fem.solvers.newton.newton`) from a close start (continuation in
:math:`\\varepsilon`).
"""

from __future__ import annotations

import functools
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from skfem import LinearForm, asm

from ...distribution import VelocityDistribution
from ...error import ErrorEstimate, ErrorRecipe, richardson_factor
from ...operators.adaptive import PSI_Y2, element_indicator
from ...operators.fem_transport import TransportArrays
from ...options import option_group
from ...run_info import RunInfo
from ..newton import PseudoTransient, newton
from .cooling_forms import cooling_forms
from .cooling_steps import SpeculativeSystem, newton_on_step
from .error import BISECTED_METHOD, bisected, interpolated_log
from .heated import (
    EquilibratedLU,
    FEMDiscretisation,
    bath_drift_jacobian,
    log_update,
    newton_info,
    stalled,
    weighted_mass,
)
from .newton import CHORD_LEVEL

__all__ = ["CoolingState", "CoolingNewtonOptions", "newton_cooling", "second_moment",
           "cooling_estimate", "cooling_recipe",
           "PSEUDO_TIME_STEP", "INCREASE_LIMIT", "MONITOR_LOG_F", "RESIDUAL_STALL", "LOG_STEP_ZETA",
           "CLOSE_DAMPING", "RESIDUAL_FLOOR", "RESIDUAL_FLOOR_REL"]

logger = logging.getLogger(__name__)

PSEUDO_TIME_STEP = 1.0
"""First pseudo-time step of the globalised Newton iteration (scaled collision times)."""
STALL_RATIO, MIN_GROWTH = 0.9, 1.3
"""Pseudo-time steps grow by at least MIN_GROWTH while the update shrinks by a ratio above
STALL_RATIO.  With the switched evolution relaxation alone the step stayed at 1.6 for
20 of the 40 steps from the Gaussian start at alpha = 0.9 (the tail relaxing 0.71 in ln f
per step): alpha = 0.9 1.71 -> 1.34 units, 0.95 4.8 -> 4.1; alpha 0 ... 0.8 and other
kernels unchanged in time, states equal to 1e-15
(benchmarks/archive/results/fem_cooling_speed.md)."""
INCREASE_LIMIT = 2.0
"""Largest increase of ln f in one Newton step (unbounded increases of the tail, where
the starting guess is many decades off, make the iteration diverge)."""


@LinearForm
def second_moment(v, w):
    """:math:`\\int c^2 \\varphi_i e^{u}` (the gradient of the temperature)."""
    return w.x[0] ** 2 * np.exp(w.u) * v


class CoolingState:
    """A converged HCS: discretisation, ``u_h = ln f_h``, ``zeta`` and run info.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation (scaled velocities).
    u : ndarray, shape (n_dofs,)
        Coefficients of :math:`u_h = \\ln f_h`.
    zeta : float
        Cooling rate.
    info : RunInfo
        Convergence report.
    """

    def __init__(self, disc: FEMDiscretisation, u: NDArray, zeta: float, info) -> None:
        self.disc = disc
        self.u = u
        self.zeta = zeta
        self.info = info

    def energy_identity(self) -> float:
        """:math:`\\tfrac18\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle` by the pair rule."""
        return 0.5 * self.disc.energy_loss(self.u, even=True)  # the HCS is even

    def log_f(self, c: NDArray) -> NDArray:
        """:math:`\\ln f_h` at ``c`` (clipped to the mesh; linear continuation beyond)."""
        verts = self.disc.vertices
        edge = 0.999 * verts[-1]
        c = np.asarray(c, dtype=float)
        c_in = np.clip(c, -edge, edge)
        order = np.argsort(c_in)
        out = np.empty_like(c)
        out[order] = np.log(self.disc.evaluate(self.u, c_in[order]))
        ends = np.log(self.disc.evaluate(self.u, np.array([0.97, 1.0]) * edge))
        slope = min((ends[1] - ends[0]) / (0.03 * edge), 0.0)
        return out + slope * (np.abs(c) - np.abs(c_in))


    def indicator(self) -> NDArray:
        """The a posteriori error estimate of :math:`\\ln f_h` per element
        (:func:`kinetic_fem.operators.adaptive.element_indicator`; P2 only)."""
        verts = self.disc.vertices
        mids = 0.5 * (verts[1:] + verts[:-1])
        u_v = np.log(self.disc.evaluate(self.u, verts))
        u_m = np.log(self.disc.evaluate(self.u, mids))
        return element_indicator(verts, u_v, u_m)

    def error_estimate(self) -> tuple[NDArray, float]:
        """Two-level estimate of the error of :math:`\\ln f_h` and :math:`\\zeta`.

        The state is interpolated (exactly: :math:`u_h` is in the finer space) onto the
        mesh with every element bisected, and one Newton step of the HCS equations is
        solved there: :math:`\\delta = -J_{h/2}^{-1} R_{h/2}(u_h, \\zeta_h)`
        approximates :math:`(u_{h/2} - u_h, \\zeta_{h/2} - \\zeta_h)`, the error of the
        state up to that of the finer one (a factor :math:`2^{-p}` smaller).  Unlike
        the local :meth:`indicator`, it solves the global linearised problem, so it
        carries the error the cooling drift transports outward.

        Returns
        -------
        eta : ndarray, shape (E,)
            Largest :math:`|\\delta_{\\ln f}|` over the finer dofs in each element.
        dzeta : float
            :math:`|\\delta_\\zeta|/\\zeta`.
        """
        verts = self.disc.vertices
        fine_verts = np.sort(np.concatenate([verts, 0.5 * (verts[1:] + verts[:-1])]))
        fine = FEMDiscretisation(self.disc.alpha, fine_verts, self.disc.order,
                                 self.disc.intorder, gamma=self.disc.gamma)
        loc = fine.dof_locations
        u_fine = np.log(self.disc.evaluate(self.u, np.sort(loc)))[np.argsort(np.argsort(loc))]
        system = _CoolingSystem(fine, u_fine)
        x = np.append(system.reduce(u_fine), self.zeta)
        r, j = system(x)
        assert j is not None
        delta = EquilibratedLU(j).solve(-r)
        du = np.abs(system.sym @ delta[:-1])
        eta = np.zeros(verts.size - 1)
        for side in ("left", "right"):  # a dof on a vertex counts for both its elements
            owner = np.clip(np.searchsorted(verts, loc, side=side) - 1, 0, verts.size - 2)
            np.maximum.at(eta, owner, du)
        return eta, abs(float(delta[-1])) / abs(self.zeta)

    def growth_rates(self, count: int = 5) -> tuple[NDArray, NDArray]:
        """The fastest-growing modes of the linearised discrete dynamics at fixed zeta.

        The eigenvalues of :math:`J v = \\lambda M v` on the even dofs, :math:`J` the
        Jacobian of the Galerkin residual :math:`C[f_h] + \\zeta D[f_h]` in
        :math:`\\ln f_h`, :math:`M_{ij} = \\int\\varphi_i\\varphi_j f_h` (the pencil
        scaled to a unit mass diagonal, as in :func:`kinetic_fem.relaxation_spectrum`).
        A stable discretisation has no eigenvalue with a real part large against
        :math:`\\zeta` (the scale mode, a time shift of the cooling, is of order
        :math:`\\zeta`); an unresolved outer edge shows eigenvalues of hundreds of
        :math:`\\zeta` localised at the cut-off (``benchmarks/results/fem_cooling.md``).

        Parameters
        ----------
        count : int
            Number of modes returned.

        Returns
        -------
        rates : ndarray, shape (count,)
            The largest real parts, in units of :math:`\\zeta`, decreasing.
        where : ndarray, shape (count,)
            The velocity :math:`c \\ge 0` where each mode's eigenvector is largest
            (in the scaled norm).
        """
        import scipy.linalg

        disc, sym = self.disc, self.disc.symmetry
        field = disc.field(self.u)
        _, cjac, _ = disc.collision(self.u, jacobian=True, even=True)
        edges = np.array([np.argmin(disc.dof_locations), np.argmax(disc.dof_locations)])
        djac = asm(bath_drift_jacobian, disc.basis, u=field).toarray()
        djac[edges, edges] -= np.abs(disc.dof_locations[edges]) * np.exp(self.u[edges])
        full = cjac + self.zeta * djac
        jac = sym.T @ (sym.T @ full.T).T
        weight = asm(weighted_mass, disc.basis, u=field).toarray()
        mass_red = sym.T @ (sym.T @ weight.T).T
        scale = 1.0 / np.sqrt(np.abs(np.diag(mass_red)))
        values, vectors = scipy.linalg.eig(jac * scale[:, None] * scale[None, :],
                                           mass_red * scale[:, None] * scale[None, :])
        ok = np.isfinite(values)
        values, vectors = values[ok], vectors[:, ok]
        order = np.argsort(-values.real)[:count]
        loc = np.zeros(sym.shape[1])
        loc[sym.indices] = np.abs(disc.dof_locations)
        where = loc[np.argmax(np.abs(vectors[:, order]), axis=0)]
        return values.real[order] / self.zeta, where

    def rescaled_log_f(self, eps_from: float, eps_to: float, c: NDArray) -> NDArray:
        """A starting :math:`\\ln f` at inelasticity ``eps_to`` from this state at
        ``eps_from``, by the hump scaling :math:`f(c) \\approx [\\psi((1-c)/w) +
        \\psi((1+c)/w)]/(2w)`, :math:`w = \\varepsilon^{1/3}`.

        The right hump :math:`U(y) = \\ln(2 w f(1 - w y))` of this state is kept for
        :math:`y \\le 1/(2w)` and continued beyond by the inner tail of :math:`\\psi`,
        :math:`e^{-\\langle y^2\\rangle_\\psi y}` (the state's own slope there is not yet
        asymptotic, and would be extrapolated over a range that grows as
        :math:`\\varepsilon^{-1/3}`);
        the other hump is added for :math:`|c| < 1/2`.
        """
        w_from = eps_from ** (1.0 / 3.0)
        w_to = eps_to ** (1.0 / 3.0)
        y_mid = 0.5 / w_from
        slope = -PSI_Y2  # the inner tail of psi, exp(-<y^2> y)

        def hump(y: NDArray) -> NDArray:
            inner = np.minimum(y, y_mid)
            return (self.log_f(1.0 - w_from * inner) + math.log(2.0 * w_from)
                    + slope * (y - inner))

        c = np.abs(np.asarray(c, dtype=float))
        right = hump((1.0 - c) / w_to)
        both = np.where(c < 0.5, np.logaddexp(right, hump((1.0 + c) / w_to)), right)
        return both - math.log(2.0 * w_to)


class _CoolingSystem:
    """The residual and Jacobian of the HCS equations on the even dofs, plus ``zeta``."""

    def __init__(self, disc: FEMDiscretisation, u0: NDArray | None = None) -> None:
        self.disc = disc
        self.sym = disc.symmetry
        self.n_red = self.sym.shape[1]
        if u0 is None:
            red_x = np.zeros(self.n_red)
            red_x[self.sym.indices] = np.abs(disc.dof_locations)
            self.row0 = int(np.argmin(red_x))
        else:
            # the normalisation replaces the equation where the start is largest: at a
            # node where f is tiny (c = 0 between the near-elastic humps, f ~ e^(-1.2/w))
            # the mass barely sees the node's value and the Jacobian is singular to
            # round-off there (smallest singular value 2e-12 at eps = 3.9e-4)
            self.row0 = int(np.argmax(self.reduce(u0)))
        self.edges = np.array([np.argmin(disc.dof_locations), np.argmax(disc.dof_locations)])
        self.arrays = TransportArrays(disc.basis)

    def __call__(self, x: NDArray, jacobian: bool = True) -> tuple[NDArray, NDArray | None]:
        disc, sym, n_red, row0 = self.disc, self.sym, self.n_red, self.row0
        u_red, zeta = x[:n_red], float(x[n_red])
        u = sym @ u_red
        coll, cjac, _ = disc.collision(u, jacobian=jacobian, even=True)  # u is even
        outflow = np.zeros(u.size)
        edges = self.edges
        outflow[edges] = np.abs(disc.dof_locations[edges]) * np.exp(u[edges])
        drift, grad_mass, grad_temp, djac = cooling_forms(self.arrays, u, jacobian)
        drift = drift - outflow
        full = coll + zeta * drift
        r = np.empty(n_red + 1)
        r[:n_red] = sym.T @ full
        r[row0] = grad_mass.sum() - 1.0
        r[n_red] = grad_temp.sum() - 1.0
        if not jacobian:
            return r, None
        assert djac is not None
        djac[edges, edges] -= outflow[edges]
        jac = cjac + zeta * djac
        j = np.zeros((n_red + 1, n_red + 1))
        j[:n_red, :n_red] = sym.T @ (sym.T @ jac.T).T
        j[:n_red, n_red] = sym.T @ drift
        j[row0, :n_red] = sym.T @ grad_mass
        j[row0, n_red] = 0.0
        j[n_red, :n_red] = sym.T @ grad_temp
        return r, j

    def row_scale(self, x: NDArray) -> NDArray:
        """Natural size of each equation: :math:`\\int\\varphi_i f_h` (1 for the constraints)."""
        u = self.sym @ x[:self.n_red]
        scale = np.empty(self.n_red + 1)
        scale[:self.n_red] = self.sym.T @ cooling_forms(self.arrays, u, False)[1]
        scale[self.row0] = scale[self.n_red] = 1.0
        return np.maximum(np.abs(scale), 1e-300)

    def reduce(self, u: NDArray) -> NDArray:
        """Even dofs of a full coefficient vector (averaged over the pairs)."""
        return (self.sym.T @ u) / np.asarray(self.sym.sum(axis=0)).ravel()


MONITOR_LOG_F = math.log(1e-40)
"""Newton's step is measured where :math:`f_h > 10^{-40}` (and on :math:`\\zeta`): near
elastic collisions the far outer edge carries a near-null mode of the Jacobian (the
drift dominates there), whose step stays above round-off at residuals of 1e-15 while
changing nothing where the accuracy is asked (f > 1e-30)."""


LOG_STEP_ZETA = 1e-5
"""Newton from a close start: once the relative update of :math:`\\zeta` is below this,
decreases of :math:`\\ln f` are mapped as the step on :math:`f` too
(:func:`kinetic_fem.solvers.fem.log_update`).  Before, the far tail (linear in :math:`f`,
many decades above its state after a continuation step) fell one e-fold per Newton step:
25 of the 34 steps from eps = 0.1 to 0.05 (8 with the map, zeta equal to 5e-16).  Used
by the near-elastic continuation at eps >= 1e-4 only: below, the predicted zeta is so
close (zeta/eps - 1 ~ 1e-7) that it counts as settled at the first step, and the step
2.44e-5 -> 1.22e-5 diverged (40 Newton steps, 114 of the 142 CPU s to eps = 1e-5)."""


CLOSE_DAMPING = 0.5
"""Smallest line-search damping of Newton's method from a start that differs from the state
only by the mesh (the same eps on a coarser mesh): there a failed search means the
residual has reached round-off (the default 1e-3 spent up to ten residuals, 40 % of the
solve at eps = 1e-3, before the stall rule stopped it)."""


RESIDUAL_STALL = 1e-7
"""A residual (relative to zeta) that stops decreasing below this is round-off: Newton
reports converged with the residual it reached."""


RESIDUAL_FLOOR, RESIDUAL_FLOOR_REL = 3e-14, 1e-10
"""Round-off floor of the row-scaled residual (a rate): absolute, and relative to zeta.
Newton from a close start stops, converged, once the residual is below either, even if
``tol * zeta`` is smaller.  The residual of a converged state stalls at 2.9e-13 = 1e-11
zeta at eps = 0.03, 4e-14 at 1e-3 (P3) and ~1e-14 at 1e-5 and 1e-6, at or above ``tol *
zeta`` with the default tol; the steps that tried to go below took a Jacobian and up to
ten residuals on the finest mesh (up to a third of the solve) and moved ln f by < 1e-10.
Measured against the floor 0 (eps = 1e-3 ... 1): the states move by <= 1.5e-14 in zeta,
2e-14 in a2, 8e-11 in ln f (benchmarks/archive/results/fem_cooling_speed.md)."""


def _residual_size(r: NDArray, x: NDArray, monitor: float = MONITOR_LOG_F) -> float:
    """Max of the row-scaled residual over the monitored dofs (ln f > ``monitor``) and the
    constraints: the deep tail below takes tens of Newton steps to settle from a
    rescaled start (its rows dominate the full norm meanwhile) and feeds nothing back."""
    watched = np.append(x[:-1] > monitor, True)
    watched[np.argmax(x[:-1])] = True  # keeps the normalisation row watched too
    return float(np.abs(r[watched]).max())


def _step_size(delta: NDArray, x: NDArray, monitor: float = MONITOR_LOG_F) -> float:
    watched = x[:-1] > monitor
    du = float(np.abs(delta[:-1][watched]).max()) if watched.any() else 0.0
    return max(du, abs(delta[-1]) / max(abs(x[-1]), 1e-3))


@option_group
@dataclass(frozen=True)
class CoolingNewtonOptions:
    """The options of :func:`newton_cooling` that travel together.

    Parameters
    ----------
    tol, max_iter, step_limit, pseudo_time, log_steps, settle_steps, min_damping, \
line_search, monitor, speculative, predict_iter
        As in :func:`newton_cooling`.

    Examples
    --------
    >>> CoolingNewtonOptions(tol=1e-9).max_iter
    40
    """

    tol: float = 1e-11
    max_iter: int = 40
    step_limit: float = 10.0
    pseudo_time: float = PSEUDO_TIME_STEP
    log_steps: bool | None = None
    settle_steps: bool = True
    min_damping: float = 1e-3
    line_search: bool = True
    monitor: float = MONITOR_LOG_F
    speculative: bool = False
    predict_iter: int = 0


def newton_cooling(disc: FEMDiscretisation, u0: NDArray, zeta0: float,
                   options: CoolingNewtonOptions | None = None,
                   **overrides: Any) -> CoolingState:
    """Newton's method for :math:`(u_h, \\zeta)` with unit mass and temperature.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation (symmetric mesh).
    u0 : ndarray, shape (n_dofs,)
        Starting :math:`\\ln f_h`.
    zeta0 : float
        Starting cooling rate.
    options : CoolingNewtonOptions, optional
        The options below as one object.
    **overrides
        Any option below by keyword, over ``options`` (an unknown name raises
        :class:`TypeError`).
    tol : float
        Stop when the update of :math:`\\ln f` and the relative update of
        :math:`\\zeta` are below ``tol`` (or stall at round-off: reported converged).
    max_iter : int
        Iteration limit.
    step_limit : float
        Largest decrease of :math:`\\ln f` in one step.
    pseudo_time : float
        First step of the pseudo-transient globalisation (scaled collision times), for a
        start far from the state; ``inf``: Newton's method with Armijo backtracking on
        the row-scaled residual (the shared :func:`kinetic_fem.solvers.newton.newton`),
        for a start close to it (continuation); it stops when the row-scaled residual
        (a rate) is below ``tol * zeta0``, or stalls below ``RESIDUAL_STALL * zeta0``
        (reported converged, with the residual reached).
    log_steps : bool, optional
        Map the Newton step on :math:`\\ln f` to the step on :math:`f`
        (:func:`kinetic_fem.solvers.fem.log_update`); default: with pseudo-time steps.
    settle_steps : bool
        Map the step once :math:`\\zeta` has settled (:data:`LOG_STEP_ZETA`).
    min_damping : float
        Smallest damping of the line search (``pseudo_time = inf``;
        :data:`CLOSE_DAMPING` for a start on a coarser mesh at the same eps).
    line_search : bool
        Backtrack (``pseudo_time = inf``); without, every full step is taken and its
        residual comes with the Jacobian (one residual less per step).
    monitor : float
        Steps and residuals are measured where :math:`\\ln f_h` > ``monitor`` (and on
        :math:`\\zeta`; :data:`MONITOR_LOG_F`).
    speculative : bool
        With the line search: each trial residual comes with its Jacobian, used if the
        trial is accepted (one collision call per accepted step instead of two).
    predict_iter : int
        If positive: up to this many steps stop on the Newton step instead (below
        ``tol``, or a chord step whose predicted successor is: no residual to confirm
        it; :data:`~kinetic_fem.solvers.fem.cooling_steps.PREDICT_ITER`), then on the
        residual as above.

    Returns
    -------
    CoolingState
    """
    o = CoolingNewtonOptions(**overrides) if options is None else replace(options, **overrides)
    tol, max_iter, step_limit, pseudo_time = o.tol, o.max_iter, o.step_limit, o.pseudo_time
    log_steps, settle_steps, min_damping = o.log_steps, o.settle_steps, o.min_damping
    line_search, monitor, speculative = o.line_search, o.monitor, o.speculative
    predict_iter = o.predict_iter
    start = time.perf_counter()
    system = _CoolingSystem(disc, u0)
    n_red, row0, sym = system.n_red, system.row0, system.sym

    def update(x: NDArray, delta: NDArray) -> NDArray:
        # the pseudo-transient start: the Newton step on f (log_update); Newton from a
        # close start: the step on ln f itself (a step below -1 on f would be cut to
        # e^-10, which throws the outer edge of the near-elastic humps 10 e-folds down)
        out = x.copy()
        # an increase is mapped as the step on f, ln(1 + delta): exact where the equations
        # are linear in f (between the near-elastic humps, c ~ 0, the softest mode: at
        # eps = 1.2e-5 the first step asks ln f += 322 there, f 320 times larger)
        du = delta[:n_red]
        # once zeta has settled, decreases too (the far tail, linear in f, falls to its
        # state in one step instead of one e-fold per step: issue 16)
        settled = settle_steps and abs(delta[n_red]) < LOG_STEP_ZETA * abs(x[n_red])
        step = log_update(du, step_limit) if log_steps or settled else \
            np.where(du > 0.0, np.log1p(np.maximum(du, 0.0)), np.maximum(du, -step_limit))
        out[:n_red] += np.minimum(step, INCREASE_LIMIT)
        out[n_red] += delta[n_red]
        return out

    if log_steps is None:
        log_steps = pseudo_time < np.inf
    x = np.append(system.reduce(u0), zeta0)
    if pseudo_time == np.inf:
        # the row-scaled residual is a rate; the balance it tests is zeta (c f)' = Q,
        # so tolerances scale with zeta (round-off of Q's gain-loss cancellation ~1e-15)
        scale = abs(zeta0)
        floor = max(RESIDUAL_FLOOR, RESIDUAL_FLOOR_REL * scale)
        fun = SpeculativeSystem(system) if speculative and line_search else system
        res, on_step = newton_on_step(
            fun, x, tol=tol, residual_tol=max(tol * scale, floor), max_iter=max_iter,
            predict_iter=predict_iter, stall_level=RESIDUAL_STALL * scale,
            norm=functools.partial(_residual_size, monitor=monitor),
            step_norm=functools.partial(_step_size, monitor=monitor), update=update,
            row_scale=system.row_scale, factorize=lambda j: EquilibratedLU(j).solve,
            chord=CHORD_LEVEL, min_damping=min_damping, line_search=line_search,
            name="FEM cooling Newton")
        message = res.message
        if not on_step and res.converged and res.residual >= tol * scale:  # the floor
            message = (f"FEM cooling Newton stalled at round-off: residual {res.residual:.2e} "
                       f"below the floor {floor:.1e} (tol {tol * scale:.1e})")
        info = RunInfo(converged=res.converged, iterations=res.iterations,
                       residual=res.residual / scale, wall_time=time.perf_counter() - start,
                       message=f"{message} (residual / zeta {res.residual / scale:.1e}, "
                               f"last step {res.step:.1e})")
        return CoolingState(disc, sym @ res.x[:n_red], float(res.x[n_red]), info)
    def mass(x: NDArray) -> NDArray:
        # pseudo-transient continuation: implicit Euler in the scaled time of
        # d f/d tau = Q[f] - zeta (c f)', whose attractor is the HCS
        weight = asm(weighted_mass, disc.basis, u=disc.field(sym @ x[:n_red])).toarray()
        m = sym.T @ (sym.T @ weight.T).T
        m[row0] = 0.0
        return np.asarray(m)

    res = newton(system, x, tol=tol, max_iter=max_iter,
                 step_norm=lambda delta, at: _step_size(delta, at, monitor), update=update,
                 factorize=lambda j: EquilibratedLU(j).solve, name="HCS newton",
                 pseudo_time=PseudoTransient(pseudo_time, mass, stall_ratio=STALL_RATIO,
                                             min_growth=MIN_GROWTH, stalled=stalled))
    return CoolingState(disc, sym @ res.x[:n_red], float(res.x[n_red]),
                        newton_info(list(res.history), tol, res.iterations, start))


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
