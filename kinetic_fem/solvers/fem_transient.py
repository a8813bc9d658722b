"""Adaptive implicit time integration of the Galerkin system (heated and cooling gas).

The semi-discrete system for :math:`u_h = \\ln P_h` (Lagrange basis
:math:`\\varphi_i`, weak forms of :mod:`kinetic_fem.operators.fem_thermostat`) is

.. math::

    \\frac{d}{dt} m_i(P_h) = R_i = n\\,C_i[P_h] - D(t)\\int\\varphi_i' P_h'
    - \\xi(t)\\int\\varphi_i'\\, v P_h, \\qquad m_i(P) = \\int\\varphi_i P,

(heated gas, physical velocities; :func:`kinetic_fem.evolve_cooling` runs it with
:math:`D = \\xi = 0` on segments of fixed velocity unit,
:mod:`kinetic_fem.solvers.fem_cooling_transient`).  ``cooling=True`` is the scaled form
:math:`\\dot m_i(f_h) = C_i[f_h] + \\zeta\\int\\varphi_i' c f_h`, :math:`\\sum_i c_i^2 m_i = 1`,
with :math:`\\zeta` an unknown (kept for the record; its far tail fails, see there).

Time stepping is variable-step BDF2 on :math:`m(P)`: with :math:`\\omega = h_k/h_{k-1}`

.. math::

    \\tfrac{1+2\\omega}{1+\\omega} m^{k+1} - (1+\\omega) m^k
    + \\tfrac{\\omega^2}{1+\\omega} m^{k-1} = h_k R^{k+1};

the coefficients sum to zero, so the mass is conserved (to round-off: a constant shift
of ln P removes the Newton residual's share after each step), and :math:`P = e^u > 0`.
The first two steps after a start or a discontinuity of the protocol are backward Euler.
Each step is solved by the shared Newton driver :func:`kinetic_fem.solvers.newton.newton`
(log update, chord steps on the last factorisation, stopping on the update of ln P).
The far tail, ln P more than ``-LOG_TAIL`` below its peak, is continued linearly from
the two dofs inside (:meth:`Integrator.tail_closure`): there P2 Galerkin masses are not
positivity preserving and the step equations lose their positive solution, while the
tail's mass (below 1e-30) does not reach the moments.

**Error control, per unit step.**  The local error is estimated from the difference
between the corrector and an explicit predictor (quadratic extrapolation through the
last three levels for BDF2, explicit Euler for backward Euler), scaled by the ratio of
their error constants for the actual step sizes and, for the heated gas, filtered by the
step's Newton matrix (Shampine: :math:`(c M - hJ)^{-1} c M`, so that stiff tail modes
that the corrector damps do not count).  It is measured on :math:`T` (relative) and
:math:`a_2` (absolute) and compared with ``rtol`` times the step in collision times
(``collision_time``; the scaled time of a cooling run is already in collision times),
but not below ``NOISE_FLOOR`` Newton tolerances.  Local errors per unit time below
``rtol`` relax over a few collision times, so the global error of T and a2 is
proportional to ``rtol`` (``benchmarks/convergence_transient.py``: 0.3-0.9 rtol; after
a quench of the protocol 4-12 rtol, the estimate there misses part of the local error:
``benchmarks/results/transient_integrator.md``).  A failed Newton iteration halves the
step; steps stay below 0.7 times a failed one and below the retried step after a
rejection (a cap growing by ``CAP_GROWTH`` per accepted step), below ``MAX_RATIO``
times the step before, and a further rejection of the same step uses the exponent
observed between the tries (:func:`~.fem_transient_setup.retry_step`).
"""

from __future__ import annotations

import logging
import math
from typing import Callable

import numpy as np
import scipy.sparse.linalg
from numpy.typing import NDArray
from skfem import asm

from ..exceptions import ConvergenceError
from ..operators.fem_thermostat import (
    diffusion,
    diffusion_jacobian,
    drift,
    drift_jacobian,
    mass,
    weighted_mass,
)
from .fem import EquilibratedLU, FEMDiscretisation, log_update
from .fem_transient_setup import (
    CAP_GROWTH,
    CHORD_RATE,
    CHORD_STEP,
    INITIAL_FLOOR,
    LOG_TAIL,
    MAX_RATIO,
    NOISE_FLOOR,
    STEP_PREDICT,
    Level,
    TransientOptions,
    TransientStats,
    abs_mass,
    build_mesh,
    floor_log,
    lagrange_weights,
    lte_ratio,
    make_discretisation,
    retry_step,
)
from .newton import newton

__all__ = ["TransientOptions", "TransientStats", "EquilibratedLU", "log_update", "build_mesh",
           "make_discretisation", "Integrator", "Level", "lagrange_weights", "lte_ratio",
           "INITIAL_FLOOR", "ConvergenceError", "floor_log"]

logger = logging.getLogger(__name__)

MAX_RETRIES = 60
"""Tries (Newton failures and rejected steps) for one step before a run is given up
(a rejection at the smallest step and a Newton failure just above it could alternate
until ``max_steps``: the Mpemba start past its tabulated range); runs need a few."""


class Integrator:
    """Adaptive BDF2 for one discretisation (see the module docstring).

    Parameters
    ----------
    disc : FEMDiscretisation
        The collision operator's discretisation (replace with :meth:`set_disc`).
    coefficients : callable
        ``(t, left) -> (n, D, xi)``: density, noise strength and friction at time ``t``
        (left limits if ``left``); only ``n`` is used when ``cooling``.
    cooling : bool
        Scaled free cooling with the drift coefficient :math:`\\zeta` as an unknown.
    options : TransientOptions
    gamma : float
        Kernel exponent (the time scale of a cooling run).
    collision_time : callable, optional
        ``T -> t_c``: the time unit of the error per unit step (heated gas: the mean
        free time at temperature ``T``); default 1 (the scaled time of a cooling run is
        already in collision times).
    """

    def __init__(self, disc: FEMDiscretisation, coefficients, *, cooling: bool,
                 options: TransientOptions, gamma: float = 1.0,
                 collision_time: Callable[[float], float] | None = None) -> None:
        self.coefficients = coefficients
        self.collision_time = collision_time
        self.gamma = gamma
        self.cooling = cooling
        self.opt = options
        self.stats = TransientStats()
        self.step_cap = math.inf   # below the last step whose Newton iteration failed
        self.set_disc(disc)

    def set_disc(self, disc: FEMDiscretisation) -> None:
        """Use ``disc`` (same mesh, e.g. after a change of restitution)."""
        self.disc = disc
        self.sym = disc.symmetry
        self.x = disc.dof_locations
        self.xq, self.wq, _ = disc.points
        self.keep = np.flatnonzero(self.x >= 0)   # the reduced dofs (u = sym @ u[keep])
        self.outward = self.keep[np.argsort(self.x[self.keep], kind="stable")]

    # ------------------------------------------------------------------ the system
    def masses(self, u: NDArray) -> NDArray:
        """:math:`m_i(e^u)`."""
        return asm(mass, self.disc.basis, u=self.disc.field(u))

    def moments(self, u: NDArray) -> tuple[float, float, float]:
        """Mass, :math:`T` and :math:`a_2` of :math:`e^{u}` by the outer quadrature."""
        p = self.disc.values(u)
        m0, m2, m4 = (float(np.sum(self.wq * p * self.xq**k)) for k in (0, 2, 4))
        temp = m2 / m0
        return m0, temp, m4 / m0 / (3.0 * temp * temp) - 1.0

    def rhs(self, u: NDArray, zeta: float, t: float, jacobian: bool, left: bool = True
            ) -> tuple[NDArray, NDArray | None, NDArray | None]:
        """``R(u)``, ``dR/du`` (dense) and ``dR/dzeta`` (cooling) at time ``t``.

        ``left``: protocol values as left limits (an implicit step ending at ``t``).
        """
        disc = self.disc
        field = disc.field(u)
        coll, cjac = disc.collision(u, jacobian=jacobian)[:2]
        drift_vec = asm(drift, disc.basis, u=field)
        if self.cooling:
            res = coll + zeta * drift_vec
            if not jacobian:
                return res, None, drift_vec
            jac = cjac + zeta * asm(drift_jacobian, disc.basis, u=field).toarray()
            return res, jac, drift_vec
        n, d, xi = self.coefficients(t, left)
        res = n * coll - d * asm(diffusion, disc.basis, u=field) - xi * drift_vec
        if not jacobian:
            return res, None, None
        jac = n * cjac - d * asm(diffusion_jacobian, disc.basis, u=field).toarray()
        if xi != 0.0:
            jac -= xi * asm(drift_jacobian, disc.basis, u=field).toarray()
        return res, jac, None

    def observables(self, u: NDArray, y: NDArray) -> NDArray:
        """What the error is measured on: ``(T, a2)`` or, cooling, ``(ln T, t, a2)``."""
        _, temp, a2 = self.moments(u)
        return np.array([y[0], y[1], a2]) if self.cooling else np.array([temp, a2])

    def observables_rate(self, level: Level) -> NDArray:
        """Time derivative of :meth:`observables` at ``level`` (from :math:`\\dot u`)."""
        if level.udot is None:
            level.udot = self.derivative(level.u, level.zeta, level.s)
        rates = self.moments_change(level.u, level.udot)
        if self.cooling:
            return np.append(self.aux_rate(level.zeta, level.y[0]), rates[1])
        return rates

    def moments_change(self, u: NDArray, du: NDArray) -> NDArray:
        """Change of ``(T, a2)`` of :math:`e^u` to first order in a change ``du`` of u."""
        p = self.disc.values(u)
        pdot = p * np.asarray(self.disc.field(du)).ravel()
        m = [float(np.sum(self.wq * p * self.xq**k)) for k in (0, 2, 4)]
        dm = [float(np.sum(self.wq * pdot * self.xq**k)) for k in (0, 2, 4)]
        m2, m4 = m[1] / m[0], m[2] / m[0]
        dm2 = dm[1] / m[0] - m[1] * dm[0] / m[0] ** 2
        dm4 = dm[2] / m[0] - m[2] * dm[0] / m[0] ** 2
        da2 = dm4 / (3.0 * m2 * m2) - 2.0 * m4 * dm2 / (3.0 * m2**3)
        return np.array([dm2, da2])

    def zeta_of(self, u: NDArray) -> float:
        """The drift coefficient keeping :math:`\\sum_i c_i^2 \\dot m_i = 0` (cooling)."""
        coll = self.disc.collision(u)[0]
        drift_vec = asm(drift, self.disc.basis, u=self.disc.field(u))
        x2 = self.x**2
        return float(-(x2 @ coll) / (x2 @ drift_vec))

    def derivative(self, u: NDArray, zeta: float, t: float) -> NDArray:
        """:math:`\\dot u = M_u^{-1} R(u)` (M the weighted mass matrix), for predictors."""
        res = self.rhs(u, zeta, t, False, left=False)[0]
        mw = asm(weighted_mass, self.disc.basis, u=self.disc.field(u)).tocsc()
        return scipy.sparse.linalg.spsolve(mw, res)

    def solve_step(self, u0: NDArray, zeta0: float, c_new: float, c_old: NDArray, h: float,
                   t_new: float) -> tuple[NDArray, float] | None:
        """Solve ``c_new m(u) - c_old = h R(u)`` (even ``u``; ``x^2.m = 1`` if cooling).

        By the shared driver :func:`kinetic_fem.solvers.newton.newton`: full Newton steps
        in ln P (:func:`log_update`), chord steps on the last factorisation below
        ``CHORD_STEP`` while each update shrinks by ``CHORD_RATE`` and the residual
        (each equation relative to the size of its terms) decreases, stopping on the
        max-norm of the update of ln P; the far tail follows :meth:`tail_closure`.
        Returns ``(u, zeta)`` or None if it fails.
        """
        sym, x2, n_u, cooling = self.sym, self.x**2, u0.size, self.cooling
        basis, stats = self.disc.basis, self.stats
        tail, in1, in2, coef = self.tail_closure(u0)

        def fun(x: NDArray, jacobian: bool) -> tuple[NDArray, NDArray | None]:
            u, zeta = (x[:n_u], float(x[n_u])) if cooling else (x, 0.0)
            stats.residuals += 1
            stats.jacobians += int(jacobian)
            field = self.disc.field(u)
            res, jac, dz = self.rhs(u, zeta, t_new, jacobian)
            m = asm(mass, basis, u=field)
            f = sym.T @ (c_new * m - c_old - h * res)
            if tail.size:
                ur = u[self.keep]
                f[tail] = ur[tail] - (1.0 + coef) * ur[in1] + coef * ur[in2]
            if cooling:
                f = np.append(f, x2 @ m - 1.0)
            if not jacobian:
                return f, None
            assert jac is not None  # rhs returns the Jacobian when asked
            mw = asm(weighted_mass, basis, u=field).toarray()
            red = sym.T @ (sym.T @ (c_new * mw - h * jac).T).T
            if cooling:
                assert dz is not None  # the cooling rhs returns dR/dzeta
                col = -(h * (sym.T @ dz))[:, None]
                row = (x2 @ mw) @ sym
                red = np.block([[red, col], [row[None, :], np.zeros((1, 1))]])
            if tail.size:
                red[tail, :] = 0.0
                red[tail, tail] = 1.0
                red[tail, in1] = -(1.0 + coef)
                red[tail, in2] = coef
            return f, red

        def factorize(jac: NDArray):
            self.step_lu = EquilibratedLU(jac)
            self.step_tail = tail
            return self.step_lu.solve

        def update(x: NDArray, delta: NDArray) -> NDArray:
            ur = x[self.keep] + log_update(delta[:-1] if cooling else delta)
            if tail.size:   # the tail on its line (a linear update would miss it)
                ur[tail] = (1.0 + coef) * ur[in1] - coef * ur[in2]
            u = sym @ ur
            return np.append(u, x[n_u] + delta[-1]) if cooling else u

        def step_norm(delta: NDArray, x: NDArray) -> float:
            size = float(np.abs(delta[:-1] if cooling else delta).max())
            return size if size < 1e100 else math.inf

        scale_old = sym.T @ np.abs(c_old)

        def norm(r: NDArray, x: NDArray) -> float:
            # each equation relative to the size of its terms: the tail's count too
            field = self.disc.field(x[:n_u])
            scale = c_new * (sym.T @ asm(abs_mass, basis, u=field)) + scale_old
            scale[tail] = 1.0
            rel = np.abs(r[:-1] if cooling else r) / scale
            return float(max(rel.max(), abs(r[-1]) if cooling else 0.0))

        x0 = np.append(u0, zeta0) if cooling else u0
        with np.errstate(over="ignore", invalid="ignore"):
            result = newton(fun, x0, tol=self.opt.newton_tol, max_iter=self.opt.max_newton,
                            criterion="step", norm=norm, step_norm=step_norm, update=update,
                            factorize=factorize, chord=CHORD_STEP, chord_rate=CHORD_RATE,
                            line_search=False, predict=STEP_PREDICT, name="step Newton")
        stats.newton_iterations += result.iterations
        if not result.converged:
            logger.debug("%s (h=%.3e, t=%.6g)", result.message, h, t_new)
            return None
        x = result.x
        return (x[:n_u].copy(), float(x[n_u])) if cooling else (x, zeta0)

    def filtered(self, u: NDArray, du: NDArray, c_new: float) -> NDArray:
        """``(c_new M_u - h J)^{-1} c_new M_u du`` with the last step's factorisation.

        Parameters
        ----------
        u : ndarray
            The new level.
        du : ndarray
            Corrector minus predictor.
        c_new : float
            Leading coefficient of the step.

        Returns
        -------
        ndarray
            The filtered difference (all dofs).
        """
        mw = asm(weighted_mass, self.disc.basis, u=self.disc.field(u))
        rhs = c_new * (self.sym.T @ (mw @ du))
        rhs[self.step_tail] = 0.0
        return self.sym @ self.step_lu.solve(rhs)

    def tail_closure(self, u: NDArray) -> tuple[NDArray, int, int, NDArray]:
        """The far tail of ``u`` and its linear extrapolation (reduced dof indices).

        Dofs beyond the first speed where ``u`` falls ``-LOG_TAIL`` below its peak lie on
        the straight line (in ln P) through the last two dofs inside: there P2 Galerkin
        masses are not positivity preserving (ln P falls by more than 2.7 per element)
        and the step equations can lose their positive solution, while the tail's mass,
        below ``exp(LOG_TAIL)`` of the peak, does not reach the moments.

        Parameters
        ----------
        u : ndarray
            ln P at the dofs.

        Returns
        -------
        tail : ndarray of int
            Reduced indices of the tail dofs (empty: no tail).
        inner1, inner2 : int
            Reduced indices of the last and the second-last dof inside.
        coef : ndarray
            ``u_tail = (1 + coef) u_inner1 - coef u_inner2``.
        """
        out = self.outward
        ur = u[out]
        below = np.flatnonzero(ur < float(ur.max()) + LOG_TAIL)
        if below.size == 0 or below[0] < 2:
            return np.zeros(0, dtype=np.int64), 0, 0, np.zeros(0)
        k = int(below[0])
        xs = self.x[out]
        coef = (xs[k:] - xs[k - 1]) / (xs[k - 1] - xs[k - 2])
        red = np.searchsorted(self.keep, out)   # position of each outward dof in keep
        return red[k:], int(red[k - 1]), int(red[k - 2]), coef

    # ------------------------------------------------------------------ stepping
    def history_target(self, c_old: NDArray, m_last: NDArray, c_new: float) -> NDArray:
        """The BDF2 history term ``c_old`` (a hook: a subclass may keep it positive).

        Parameters
        ----------
        c_old, m_last : ndarray
            History term of the step (``c_new m(u_new) - c_old = h R(u_new)``) and the
            masses of the last level.
        c_new : float
            Coefficient of the new masses.
        """
        return c_old

    def aux_rate(self, zeta: float, log_t: float) -> NDArray:
        """Rates of ``(ln T, t)`` in the scaled time of a cooling run."""
        n, gamma = self.coefficients(0.0)[0], self.gamma
        return np.array([-2.0 * zeta, math.exp(-0.5 * gamma * log_t) / n])

    def attempt(self, hist: list[Level], h: float) -> tuple[Level, float] | None:
        """One step of size ``h`` from ``hist[-1]``: the new level and its error norm."""
        last = hist[-1]
        s_new = last.s + h
        bdf2 = len(hist) >= 3
        if bdf2:
            h1, h2 = last.s - hist[-2].s, hist[-2].s - hist[-3].s
            w = h / h1
            c_new = (1.0 + 2.0 * w) / (1.0 + w)
            c_old = (1.0 + w) * last.m - w * w / (1.0 + w) * hist[-2].m
            c_old = self.history_target(c_old, last.m, c_new)
            ratio = lte_ratio((h, h1, h2), 2)
            nodes = [lv.s for lv in hist[-3:]]
            weights = lagrange_weights(nodes, s_new)
            obs_pred = sum(c * lv.obs for c, lv in zip(weights, hist[-3:], strict=True))
            if not self.cooling:
                u_pred = sum(c * lv.u for c, lv in zip(weights, hist[-3:], strict=True))
        else:
            c_new, c_old, ratio = 1.0, last.m, lte_ratio((h,), 1)
            obs_pred = last.obs + h * self.observables_rate(last)
            if not self.cooling:
                assert last.udot is not None  # set by observables_rate
                u_pred = last.u + h * last.udot
        solved = self.solve_step(last.u, last.zeta, c_new, c_old, h, s_new)
        if solved is None:
            return None
        u, zeta = solved
        if not self.cooling:
            # the mass to round-off (the step conserves it to the Newton tolerance)
            u = u + math.log(float(last.m.sum()) / float(self.masses(u).sum()))
        y = last.y
        if self.cooling:
            if bdf2:
                y_old = (1.0 + w) * last.y - w * w / (1.0 + w) * hist[-2].y
            else:
                y_old = last.y
            log_t = (y_old[0] - 2.0 * h * zeta) / c_new
            n = self.coefficients(0.0)[0]
            t_phys = (y_old[1] + h * math.exp(-0.5 * self.gamma * log_t) / n) / c_new
            y = np.array([log_t, t_phys])
        obs = self.observables(u, y)
        level = Level(s_new, u, self.masses(u), zeta, y, obs)
        diff = np.abs(obs - obs_pred)
        if self.cooling:
            rate = 2.0 * abs(zeta) * self.coefficients(0.0)[0] * math.exp(0.5 * self.gamma * y[0])
            err = max(diff[0], diff[1] * rate, diff[2])
        else:
            # the estimate filtered by the step's Newton matrix (Shampine): the stiff
            # tail modes, which the corrector damps, do not count
            diff = np.abs(self.moments_change(u, self.filtered(u, u - u_pred, c_new)))
            err = max(diff[0] / obs[0], diff[1])
        # error per unit step: the local error per collision time, so that the global
        # error (local errors relaxing over a few collision times) is proportional to rtol
        unit = 1.0 if self.collision_time is None or self.cooling else \
            self.collision_time(float(obs[0]))
        # below NOISE_FLOOR Newton tolerances a step's error is not resolved
        tol = max(self.opt.rtol * h / unit, NOISE_FLOOR * self.opt.newton_tol)
        return level, abs(ratio) * err / tol

    def advance(self, hist: list[Level], h: float, s_stop: float
                ) -> tuple[float, bool]:
        """Take one accepted step (retrying smaller ones); returns the next ``h``.

        The step is shortened to end exactly at ``s_stop``; the second value says
        whether ``s_stop`` was reached.
        """
        tries, rejected = 0, None
        while True:
            tries += 1
            if tries > MAX_RETRIES:
                raise ConvergenceError(
                    f"no step accepted after {MAX_RETRIES} tries at s={hist[-1].s:.6g} (last "
                    f"step {h:.3g}, smallest step {self.opt.min_step:.3g}): the state cannot "
                    "be continued on this mesh; refine the mesh (spacing), or check that the "
                    "cutoff does not reach past where the initial state is known")
            if self.stats.accepted + self.stats.rejected + self.stats.newton_failures \
                    >= self.opt.max_steps:
                raise ConvergenceError(
                    f"{self.opt.max_steps} steps taken before s={s_stop:.4g} (reached "
                    f"{hist[-1].s:.4g}); increase max_steps or rtol={self.opt.rtol:g}")
            # variable-step BDF2 is zero-stable for step ratios below 1 + sqrt(2)
            ratio_cap = MAX_RATIO * (hist[-1].s - hist[-2].s) if len(hist) >= 2 else math.inf
            h = h_wanted = min(h, self.opt.max_step, ratio_cap)
            rest = s_stop - hist[-1].s   # reached in one step, or two equal ones
            hit = hist[-1].s + h >= s_stop - 1e-12 * max(1.0, abs(s_stop))
            h = rest if hit else (0.5 * rest if h < rest < 2.0 * h else h)
            result = self.attempt(hist, h)
            if result is None:
                self.stats.newton_failures += 1
                # steps stay below the failed one a while (alpha 0.9 Kovacs quench)
                self.step_cap = 0.7 * h
                h = 0.5 * h if h > self.opt.min_step else 2.0 * h
                if h < 1e-14 * max(1.0, abs(hist[-1].s)):
                    raise ConvergenceError(
                        f"Newton failed down to the step {h:.3g} at s={hist[-1].s:.6g}; "
                        "refine the mesh (spacing) or loosen newton_tol")
                continue
            level, err = result
            order = 2 if len(hist) >= 3 else 1
            factor = 0.9 * max(err, 1e-10) ** (-1.0 / order)
            forced = err > 1.0 and h <= self.opt.min_step * 1.000001
            if err <= 1.0 or forced:
                self.stats.forced += int(forced)
                self.stats.accepted += 1
                hist.append(level)
                del hist[:-3]
                h_next = min(h * min(2.0, max(0.2, factor)), self.step_cap)
                self.step_cap *= CAP_GROWTH
                return (max(h_next, min(h_wanted, self.step_cap)) if hit else h_next), hit
            self.stats.rejected += 1
            first = rejected is None
            h, rejected = max(retry_step(h, err, order, rejected), self.opt.min_step), (h, err)
            if first:   # the next steps stay below the retried one for a while
                self.step_cap = min(self.step_cap, h)
