"""Adaptive implicit time integration of the Galerkin system (heated and cooling gas).

The semi-discrete system for :math:`u_h = \\ln P_h` (Lagrange basis
:math:`\\varphi_i`, weak forms of :mod:`kinetic_fem.operators.fem_thermostat`) is

.. math::

    \\frac{d}{dt} m_i(P_h) = R_i = n\\,C_i[P_h] - D(t)\\int\\varphi_i' P_h'
    - \\xi(t)\\int\\varphi_i'\\, v P_h, \\qquad m_i(P) = \\int\\varphi_i P,

(heated gas, physical velocities; :func:`kinetic_fem.evolve_cooling` runs it with
:math:`D = \\xi = 0` on segments of fixed velocity unit,
:mod:`kinetic_fem.solvers.fem.cooling_transient`, whose remaps are a hook of the
integrator).

:class:`TimeIntegrator` is the protocol (as SciPy's ``OdeSolver``): the public
:meth:`~TimeIntegrator.step` keeps the status and the counters and calls the scheme's
``_step_impl``; :class:`BDF2` is the scheme.  With ``TransientOptions.scheme`` ``"bdf3"``
or ``"bdf4"`` (the heated driver's default) it raises the order to variable-step
BDF3/BDF4 once enough levels are known (coefficients :func:`~.transient_setup.bdf_weights`,
the predictor through one level more; a level with no continuation is taken again by BDF2,
``BACKTRACK_FAILURES``); ``"bdf2"`` is the scheme described below.

Time stepping is variable-step BDF2 on :math:`m(P)`: with :math:`\\omega = h_k/h_{k-1}`

.. math::

    \\tfrac{1+2\\omega}{1+\\omega} m^{k+1} - (1+\\omega) m^k
    + \\tfrac{\\omega^2}{1+\\omega} m^{k-1} = h_k R^{k+1};

the coefficients sum to zero, so the mass is conserved (to round-off: a constant shift
of ln P removes the Newton residual's share after each step), and :math:`P = e^u > 0`.
The first two steps after a start or a discontinuity of the protocol are backward Euler.
Each step is solved by simplified Newton (log update; it stops once the update,
extrapolated by the observed contraction, changes no moment :math:`\\langle v^k\\rangle`,
:math:`k \\le` ``NEWTON_MOMENTS``, by more than ``newton_tol`` relative and no ln P by more
than ``TAIL_TOL``: about 2 iterations per step, where the largest update of ln P, in the
far tail, took 4-8) on the matrix
:math:`c M_u - h J` of the last Jacobian evaluation: the Jacobian (the collision
operator's costs :math:`O(N^2)`) is kept across steps and evaluated again only when an
iteration contracts slowly or fails; a change of the step or of the tail closure only
refactors (a dense LU of the even dofs, about a millisecond).  The forms
(:math:`\\int\\varphi_i e^u`, :math:`\\int\\varphi_i\\varphi_j e^u`, the thermostat's) are sums over
precomputed basis values (:class:`Forms`).
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
``benchmarks/archive/results/transient_integrator.md``).  A failed Newton iteration halves the
step; steps stay below 0.7 times a failed one and below the retried step after a
rejection (a cap growing by ``CAP_GROWTH`` per accepted step), below ``MAX_RATIO``
times the step before, and a further rejection of the same step uses the exponent
observed between the tries (:func:`~.transient_setup.retry_step`).
"""

from __future__ import annotations

import logging
import math
from typing import Callable

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import NDArray

from ...exceptions import ConvergenceError
from .heated import EquilibratedLU, FEMDiscretisation, log_update
from .transient_setup import (
    BDF3_MAX_RATIO,
    CAP_GROWTH,
    INITIAL_FLOOR,
    LOG_TAIL,
    MAX_RATIO,
    NOISE_FLOOR,
    SCHEMES,
    Level,
    TransientOptions,
    TransientStats,
    bdf_weights,
    build_mesh,
    floor_log,
    lagrange_weights,
    lte_ratio,
    make_discretisation,
    retry_step,
)

__all__ = ["TransientOptions", "TransientStats", "EquilibratedLU", "log_update", "build_mesh",
           "factor_with_tail", "make_discretisation", "TimeIntegrator", "MeshView", "BDF2",
           "Forms", "Level", "lagrange_weights", "lte_ratio", "INITIAL_FLOOR", "ConvergenceError",
           "floor_log"]

logger = logging.getLogger(__name__)

MAX_RETRIES = 60
"""Tries (Newton failures and rejected steps) for one step before a run is given up
(a rejection at the smallest step and a Newton failure just above it could alternate
until ``max_steps``: the Mpemba start past its tabulated range); runs need a few."""

SLOW_CONTRACTION = 0.5
"""Simplified Newton: an iteration whose update shrinks by less than this factor stops;
the step is retried with a fresh Jacobian (a stale one's contraction has decayed)."""

NEWTON_MOMENTS = 12
"""The step Newton measures its updates by the relative changes they make to the
moments :math:`\\langle v^k\\rangle`, ``k = 0, 2, ..., NEWTON_MOMENTS``
(:meth:`BDF2.newton_weights`), not by the largest change of ln P: that one sits in
the far tail (ln P 1e-30 below the peak), whose mass reaches no moment, and took
4-8 iterations per step to converge to ``newton_tol``."""

TAIL_TOL = 1e-2
"""The step Newton also converges every dof's ln P to this (absolute, extrapolated): the
far tail's updates reach no moment, but left unconverged they grew from step to step
until a Newton step of 1e24 in P (Maxwell transient, spacing 0.5, t = 1.03); 1e-3 cost
two more iterations per step (4 instead of 2 at 521 nodes) for the same errors."""

LOW_ORDER_STEPS = 10
"""After a Newton failure of a BDF3 step, this many accepted steps are BDF2: on a coarse
mesh (spacing 0.6, rtol 1e-3, hard rods from T = 0.8) BDF3's failures cascaded down to
steps of 1e-14, where BDF2 from the same levels went on."""

BACKTRACK_FAILURES = 4
"""After this many Newton failures of one step following a failure of a BDF3/BDF4 step,
the last accepted level is dropped once and taken again by BDF2 (:meth:`BDF2._step_impl`):
on a coarse mesh (spacing 0.6, cutoff 10, hard rods heated from T = 0.8, rtol 1e-3) a
BDF4 step accepted on its T and a2 error left ln P non-monotone at the outermost dofs
(-70, -71, -63 at 1e-27 of the peak), and no step from that level, down to 1e-14,
converged; BDF2 from the level before went on."""

HISTORY_FLOOR = 0.3
"""With ``positive_history``: a BDF2 history term below this fraction of ``c_new m^k``
is replaced by backward Euler's (:meth:`BDF2.history_target`)."""


def factor_with_tail(red: NDArray, tail: tuple) -> EquilibratedLU | None:
    """LU of a reduced step matrix whose far-tail rows are replaced by the tail closure
    ``u[idx] = (1 + coef) u[in1] - coef u[in2]`` (in place); None if it is not finite.

    Parameters
    ----------
    red : ndarray
        The reduced matrix ``c_new M - h J`` (overwritten in the tail rows).
    tail : tuple
        ``(idx, in1, in2, coef)`` of :meth:`BDF2.tail_closure`.
    """
    idx, in1, in2, coef = tail
    if idx.size:
        red[idx, :] = 0.0
        red[idx, idx] = 1.0
        red[idx, in1] = -(1.0 + coef)
        red[idx, in2] = coef
    if not np.all(np.isfinite(red)):
        return None
    return EquilibratedLU(red)


class Forms:
    """The local weak forms of the transient as sums over precomputed basis values.

    With :math:`B_{qi} = \\varphi_i(x_q)`, :math:`D_{qi} = \\varphi_i'(x_q)` at the
    quadrature points of the discretisation's basis (weights :math:`w_q`) and
    :math:`p_q = w_q e^{u_h(x_q)}`: :math:`\\int\\varphi_i e^u = B^T p`,
    :math:`\\int\\varphi_i\\varphi_j e^u = B^T \\mathrm{diag}(p) B`,
    :math:`\\int\\varphi_i' (e^u)' = D^T (p\\, u_h')`, :math:`\\int\\varphi_i' v e^u =
    D^T(p\\, x)`, and their derivatives (the forms of
    :mod:`kinetic_fem.operators.fem_thermostat`, equal to round-off, without the
    assembly's overhead per call).

    Parameters
    ----------
    disc : FEMDiscretisation
        Its scikit-fem basis gives the quadrature.
    """

    def __init__(self, disc: FEMDiscretisation) -> None:
        basis = disc.basis
        dofs = basis.element_dofs            # (n_local, n_el)
        n_el, n_qp = basis.dx.shape
        rows = np.arange(n_el * n_qp).reshape(n_el, n_qp)
        vals, ders, ri, ci = [], [], [], []
        for i, (phi,) in enumerate(basis.basis):
            ri.append(rows.ravel())
            ci.append(np.repeat(dofs[i], n_qp))
            vals.append(np.asarray(phi).ravel())
            ders.append(np.asarray(phi.grad)[0].ravel())
        shape = (n_el * n_qp, basis.N)
        r, c = np.concatenate(ri), np.concatenate(ci)
        self.b = scipy.sparse.csr_matrix((np.concatenate(vals), (r, c)), shape=shape)
        self.d = scipy.sparse.csr_matrix((np.concatenate(ders), (r, c)), shape=shape)
        self.b_abs = abs(self.b)
        self.w = np.asarray(basis.dx).ravel()
        self.x = np.asarray(basis.global_coordinates())[0].ravel()

    def weights(self, u: NDArray) -> NDArray:
        """:math:`p_q = w_q e^{u_h(x_q)}`."""
        return self.w * np.exp(self.b @ u)

    def mass(self, u: NDArray) -> NDArray:
        """:math:`\\int\\varphi_i e^u`."""
        return self.b.T @ self.weights(u)

    def abs_mass(self, u: NDArray) -> NDArray:
        """:math:`\\int|\\varphi_i| e^u`: the size of the terms of a dof's equation."""
        return self.b_abs.T @ self.weights(u)

    def weighted_mass(self, u: NDArray) -> scipy.sparse.csr_matrix:
        """:math:`\\int\\varphi_i\\varphi_j e^u` (sparse)."""
        return (self.b.T @ scipy.sparse.diags(self.weights(u)) @ self.b).tocsr()

    def thermostat(self, u: NDArray, diffusion: float, friction: float) -> NDArray:
        """:math:`D\\int\\varphi_i'(e^u)' + \\xi\\int\\varphi_i' v e^u`."""
        p = self.weights(u)
        return self.d.T @ (p * (diffusion * (self.d @ u) + friction * self.x))

    def thermostat_jacobian(self, u: NDArray, diffusion: float, friction: float
                            ) -> scipy.sparse.csr_matrix:
        """Derivative of :meth:`thermostat` (sparse)."""
        p = self.weights(u)
        dt = self.d.T
        first = dt @ scipy.sparse.diags(p * (diffusion * (self.d @ u) + friction * self.x))
        return (first @ self.b + diffusion * (dt @ scipy.sparse.diags(p) @ self.d)).tocsr()


class TimeIntegrator:
    """Protocol of the adaptive time integrators (as SciPy's ``OdeSolver``).

    The public :meth:`step` keeps the status and the counters and calls the scheme's
    ``_step_impl``; :meth:`advance_to` steps to a stop time, calling the ``remap`` hook
    after each accepted step (the cooling transient's change of velocity unit).

    Parameters
    ----------
    options : TransientOptions
        Tolerances and step limits.

    Attributes
    ----------
    status : str
        ``"running"`` or ``"failed"`` (``message`` says why).
    stats : TransientStats
        Counters of the run.
    hist : list of Level
        The last accepted levels (newest last).
    h : float
        The next step to try.
    remap : callable, optional
        ``remap(integrator)``, called after each accepted step; may :meth:`restart`.
    """

    def __init__(self, options: TransientOptions) -> None:
        self.opt = options
        self.stats = TransientStats()
        self.status = "running"
        self.message = ""
        self.hist: list[Level] = []
        self.h = 0.0
        self.remap: Callable[[TimeIntegrator], None] | None = None

    @property
    def t(self) -> float:
        """Time of the last accepted level."""
        return self.hist[-1].s

    def start(self, level: Level, h: float) -> None:
        """Start (or restart) from ``level`` with the first step ``h``.

        Parameters
        ----------
        level : Level
            The initial level.
        h : float
            First step (backward Euler).
        """
        self.hist = [level]
        self.h = h

    def restart(self, level: Level, h: float) -> None:
        """:meth:`start` after a discontinuity (counted in ``stats.restarts``)."""
        self.stats.restarts += 1
        self.start(level, h)

    def step(self, s_stop: float) -> bool:
        """Take one accepted step towards ``s_stop``; True once ``s_stop`` is reached.

        Parameters
        ----------
        s_stop : float
            Time not to step past (the step is shortened to end exactly there).

        Returns
        -------
        bool

        Raises
        ------
        ConvergenceError
            If the scheme cannot continue (``status`` becomes ``"failed"``).
        """
        if self.status != "running":
            raise RuntimeError(f"the integrator has stopped ({self.status}: {self.message})")
        try:
            reached = self._step_impl(s_stop)
        except ConvergenceError as err:
            self.status, self.message = "failed", str(err)
            raise
        if self.remap is not None:
            self.remap(self)
        return reached

    def advance_to(self, s_stop: float, progress: Callable[[float], None] | None = None
                   ) -> None:
        """Step until ``s_stop``; ``progress(t)`` after each step (a progress bar)."""
        while not self.step(s_stop):
            if progress is not None:
                progress(self.t)
        if progress is not None:
            progress(self.t)

    def _step_impl(self, s_stop: float) -> bool:
        raise NotImplementedError


class MeshView:
    """What :class:`BDF2`'s per-state methods (``moments``, ``moments_change``,
    ``newton_weights``, ``tail_closure``) read of one mesh: its discretisation, forms,
    symmetry, dof locations, outer quadrature, reduced dofs and their outward order.

    The attributes are declared here, so that :meth:`bind_mesh` sets them for the
    integrator and for each species of the mixture integrator alike.
    """

    disc: FEMDiscretisation
    forms: Forms
    sym: scipy.sparse.csr_matrix
    x: NDArray
    xq: NDArray
    wq: NDArray
    keep: NDArray
    outward: NDArray

    def bind_mesh(self, disc: FEMDiscretisation) -> None:
        """Set the attributes of ``disc``.

        Parameters
        ----------
        disc : FEMDiscretisation
            The mesh's discretisation.
        """
        self.disc = disc
        self.forms = Forms(disc)
        self.sym = disc.symmetry
        self.x = disc.dof_locations
        self.xq, self.wq, _ = disc.points
        self.keep = np.flatnonzero(self.x >= 0)   # the reduced dofs (u = sym @ u[keep])
        self.outward = self.keep[np.argsort(self.x[self.keep], kind="stable")]


class BDF2(TimeIntegrator, MeshView):
    """Adaptive BDF2 on the Galerkin masses (see the module docstring).

    Parameters
    ----------
    disc : FEMDiscretisation
        The collision operator's discretisation (replace with :meth:`set_disc`).
    coefficients : callable
        ``(t, left) -> (n, D, xi)``: density, noise strength and friction at time ``t``
        (left limits if ``left``).
    options : TransientOptions
    collision_time : callable, optional
        ``T -> t_c``: the time unit of the error per unit step (the mean free time at
        temperature ``T``); default 1.
    positive_history : bool
        Far-tail dofs whose BDF2 history term would fall below ``HISTORY_FLOOR`` take a
        backward Euler step (:meth:`history_target`; the cooling transient).
    """

    def __init__(self, disc: FEMDiscretisation, coefficients, *, options: TransientOptions,
                 collision_time: Callable[[float], float] | None = None,
                 positive_history: bool = False) -> None:
        super().__init__(options)
        self.coefficients = coefficients
        self.collision_time = collision_time
        self.positive_history = positive_history
        self.limited = 0
        self.mass_defect = 0.0
        self.step_cap = math.inf   # below the last step whose Newton iteration failed
        if options.scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got {options.scheme!r}")
        self.max_order = SCHEMES[options.scheme]
        self.low_order = 0   # accepted steps still to take at order <= 2 (after a failure)
        self.set_disc(disc)

    def set_disc(self, disc: FEMDiscretisation) -> None:
        """Use ``disc`` (a new mesh, or the same after a change of restitution)."""
        self.bind_mesh(disc)
        self._jacobian: tuple | None = None      # (collision, mass, thermostat parts)
        self._lu: tuple | None = None            # (key, EquilibratedLU)

    # ------------------------------------------------------------------ the system
    def masses(self, u: NDArray) -> NDArray:
        """:math:`m_i(e^u)`."""
        return self.forms.mass(u)

    def moments(self, u: NDArray) -> tuple[float, float, float]:
        """Mass, :math:`T` and :math:`a_2` of :math:`e^{u}` by the outer quadrature."""
        p = self.disc.values(u)
        m0, m2, m4 = (float(np.sum(self.wq * p * self.xq**k)) for k in (0, 2, 4))
        temp = m2 / m0
        return m0, temp, m4 / m0 / (3.0 * temp * temp) - 1.0

    def rhs(self, u: NDArray, t: float, left: bool = True) -> NDArray:
        """``R(u)`` at time ``t`` (protocol values as left limits if ``left``)."""
        n, d, xi = self.coefficients(t, left)
        coll = self.disc.collision(u, energy_power=None, even=True)[0]
        self.stats.residuals += 1
        return n * coll - self.forms.thermostat(u, d, xi)

    def observables(self, u: NDArray) -> NDArray:
        """What the error is measured on: ``(T, a2)``."""
        _, temp, a2 = self.moments(u)
        return np.array([temp, a2])

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

    def derivative(self, u: NDArray, t: float) -> NDArray:
        """:math:`\\dot u = M_u^{-1} R(u)` (M the weighted mass matrix), for predictors."""
        res = self.rhs(u, t, left=False)
        return scipy.sparse.linalg.spsolve(self.forms.weighted_mass(u).tocsc(), res)

    def _evaluate_jacobian(self, u: NDArray, t: float) -> None:
        """The Jacobian's parts at ``u`` (kept for the next steps)."""
        n, d, xi = self.coefficients(t, True)
        cjac = self.disc.collision(u, jacobian=True, energy_power=None, even=True)[1]
        self.stats.jacobians += 1
        therm = self.forms.thermostat_jacobian(u, d, xi).toarray()
        # kept as derivatives in P (columns over P_j at the dofs): a stale matrix is then
        # rescaled to the current state's P (the far tail changes P by decades)
        inv = np.exp(-u)[None, :]
        self._jacobian = ((n * cjac - therm) * inv, self.forms.weighted_mass(u).toarray() * inv,
                          (n, d, xi))
        self._lu = None

    def _factor(self, c_new: float, h: float, tail: tuple, u: NDArray
                ) -> EquilibratedLU | None:
        """LU of the reduced ``c_new M - h J`` at ``u`` with the tail rows (cached by its
        key: a new step or state refactors, the Jacobian in P is kept); None if the
        matrix is not finite (an iterate whose far tail overflows ``exp``: the step
        fails and is retried smaller, as any Newton failure)."""
        key = (c_new, h, tail[0].tobytes(), tail[1], tail[2], u.tobytes())
        if self._lu is not None and self._lu[0] == key:
            return self._lu[1]
        assert self._jacobian is not None
        jac, mw, _ = self._jacobian
        sym = self.sym
        with np.errstate(over="ignore", invalid="ignore"):
            red = sym.T @ (sym.T @ ((c_new * mw - h * jac) * np.exp(u)[None, :]).T).T
        lu = factor_with_tail(np.asarray(red), tail)
        if lu is not None:
            self.stats.factorisations += 1
            self._lu = (key, lu)
        return lu

    def solve_step(self, u0: NDArray, u_start: NDArray, c_new: float, c_old: NDArray,
                   h: float, t_new: float) -> NDArray | None:
        """Solve ``c_new m(u) - c_old = h R(u)`` for even ``u`` by simplified Newton.

        The matrix is ``c_new M - h J`` with the kept Jacobian; iterations stop once the
        update of ln P, extrapolated by the observed contraction, is below
        ``newton_tol``, and give up when it contracts by less than
        ``SLOW_CONTRACTION``; the step is then retried once with the Jacobian at ``u0``.
        The far tail follows :meth:`tail_closure`.  Returns None if it fails.

        Parameters
        ----------
        u0 : ndarray
            The last level (tail closure, and where a fresh Jacobian is evaluated).
        u_start : ndarray
            The first iterate (the predictor).
        c_new, c_old, h, t_new
            The step's coefficients, history term, size and end time.
        """
        tail = self.tail_closure(u0)
        idx, in1, in2, coef = tail
        sym, forms, stats, tol = self.sym, self.forms, self.stats, self.opt.newton_tol
        weights = self.newton_weights(u0) if self.opt.moment_norm else None

        def on_line(ur: NDArray) -> NDArray:
            if idx.size:   # the tail on its line (a linear update would miss it)
                ur[idx] = (1.0 + coef) * ur[in1] - coef * ur[in2]
            return ur

        for fresh in (self._jacobian is None, True):
            if fresh:
                self._evaluate_jacobian(u0, t_new)
            # the first iterate's far tail on the line of its inner dofs, also in the
            # stale matrix: an extrapolated tail is wild where the levels' tails differ
            # by decades (the first step closes the Gaussian start's floored tail, -691,
            # to -1022 and -1310: the quadratic extrapolation through 0, h and 3h reached
            # ln P = +1628 and +3644, exp overflowed; Maxwell mixture, rtol 1e-6, step 3)
            start = sym @ on_line(u_start[self.keep].copy())
            lu = self._factor(c_new, h, tail, u0 if fresh else start)
            if lu is None:
                continue
            u = start
            prev, converged = math.inf, False
            with np.errstate(over="ignore", invalid="ignore"):
                for _ in range(self.opt.max_newton):
                    stats.newton_iterations += 1
                    f = sym.T @ (c_new * forms.mass(u) - c_old - h * self.rhs(u, t_new))
                    if idx.size:
                        ur = u[self.keep]
                        f[idx] = ur[idx] - (1.0 + coef) * ur[in1] + coef * ur[in2]
                    if not np.all(np.isfinite(f)):
                        break
                    delta = -lu.solve(f)
                    # in units of the tolerances: moments (newton_tol), every dof (TAIL_TOL)
                    if weights is None:   # the largest update of ln P
                        size = float(np.abs(delta).max()) / tol
                    else:
                        size = max(float(np.max(weights @ np.abs(delta))) / tol,
                                   float(np.abs(delta).max()) / TAIL_TOL)
                    if not math.isfinite(size):
                        break
                    u = sym @ on_line(u[self.keep] + log_update(delta))
                    if prev == math.inf:
                        converged = size < 1.0
                    else:
                        rate = size / prev
                        if rate >= SLOW_CONTRACTION:
                            break
                        converged = rate / (1.0 - rate) * size < 1.0
                    if converged:
                        break
                    prev = size
            if converged:
                return u
            stats.slow_newton += 1
            if fresh:
                break
            u_start = u0
        logger.debug("step Newton failed (h=%.3e, t=%.6g)", h, t_new)
        return None

    def newton_weights(self, u: NDArray) -> NDArray:
        """Weights of the step Newton's norm: row k bounds the relative change of
        :math:`\\langle v^{2k}\\rangle` (``2k <= NEWTON_MOMENTS``) by a change of the
        reduced ln P, to first order.

        :math:`|\\delta M_k| / M_k \\le \\sum_j W_{kj} |\\delta u_j|` with
        :math:`W_{kj} = \\int|\\varphi_j| v^k e^u / \\int v^k e^u` (mirror dofs summed).

        Parameters
        ----------
        u : ndarray
            ln P at the dofs (the last level).

        Returns
        -------
        ndarray, shape (NEWTON_MOMENTS // 2 + 1, n_reduced)
        """
        scaled = self.x / self.x.max()
        powers = scaled[None, :] ** np.arange(0, NEWTON_MOMENTS + 1, 2)[:, None]
        rows = (self.sym.T @ (self.forms.abs_mass(u)[None, :] * powers).T).T
        moments = powers @ self.forms.mass(u)
        return rows / moments[:, None]

    def filtered(self, du: NDArray) -> NDArray:
        """``(c_new M - h J)^{-1} c_new M du`` with the step's factorisation (Shampine).

        Parameters
        ----------
        du : ndarray
            Corrector minus predictor.

        Returns
        -------
        ndarray
            The filtered difference (all dofs).
        """
        assert self._jacobian is not None and self._lu is not None
        key, lu = self._lu
        mw = self._jacobian[1] * np.exp(np.frombuffer(key[5]))[None, :]
        rhs = key[0] * (self.sym.T @ (mw @ du))
        idx = np.frombuffer(key[2], dtype=np.int64)
        rhs[idx] = 0.0
        return self.sym @ lu.solve(rhs)

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
        return red[k:].astype(np.int64), int(red[k - 1]), int(red[k - 2]), coef

    # ------------------------------------------------------------------ stepping
    def history_target(self, c_old: NDArray, m_last: NDArray, c_new: float,
                       force: bool = False) -> NDArray:
        """The BDF2 history term, kept positive with ``positive_history``.

        A far-tail dof decaying by more than a factor ~4 per step (the loss rate grows
        with the speed, :math:`\\nu(v) \\approx n|v|` for hard rods) gets a negative BDF2
        history term, ``c_old = (1+w) m^k - w^2/(1+w) m^{k-1} < 0``, and the step has no
        positive solution: measured, every Newton failure of a hard-rod cooling run
        (alpha 0.3, 123 of 123) had one (with the floor 0.3: 1 Newton failure in 322
        steps; 0.1: 45; 1e-3 and 0: the run stops at t = 2.66).  Such dofs
        (``c_old < HISTORY_FLOOR c_new m^k``) take a backward Euler step of length
        ``h/c_new`` instead (``c_old = c_new m^k``, positivity preserving).  The rest of
        the history term is scaled by ``1 - delta`` to keep its sum, so the mass stays
        conserved; :attr:`mass_defect` sums the mass moved.

        Parameters
        ----------
        c_old, m_last : ndarray
            History term of the step and the masses of the last level.
        c_new : float
            Coefficient of the new masses.

        Returns
        -------
        ndarray
        """
        if not (self.positive_history or force):
            return c_old
        low = c_old < HISTORY_FLOOR * c_new * m_last
        if not low.any():
            return c_old
        out = np.where(low, c_new * m_last, c_old)
        rest = ~low
        out[rest] *= 1.0 - float(np.sum(out[low] - c_old[low])) / float(np.sum(c_old[rest]))
        self.limited += int(low.sum())
        self.mass_defect += float(np.sum(out[low] - c_old[low])) / c_new
        return out

    def order_of(self, n_levels: int) -> int:
        """Order of the next step from ``n_levels`` known levels: backward Euler from
        one or two, BDF2 from three, BDF3 (scheme ``"bdf3"``) from four."""
        cap = 2 if self.low_order > 0 else self.max_order
        return 1 if n_levels < 3 else min(n_levels - 1, cap)

    def level(self, s: float, u: NDArray) -> Level:
        """The accepted level of ``u`` at time ``s``."""
        return Level(s, u, self.masses(u), 0.0, np.zeros(2), self.observables(u))

    def attempt(self, hist: list[Level], h: float) -> tuple[Level, float] | None:
        """One step of size ``h`` from ``hist[-1]``: the new level and its error norm."""
        last = hist[-1]
        s_new = last.s + h
        order = self.order_of(len(hist))
        if order >= 3:   # variable-step BDF3 (or higher)
            levels = hist[-1:-order - 2:-1]           # newest first, order + 1 levels
            ts = [lv.s for lv in levels]
            a = bdf_weights([s_new, *ts[:order]])
            c_new = h * a[0]
            c_old = -h * np.sum([aj * lv.m for aj, lv in zip(a[1:], levels, strict=False)],
                                axis=0)
            c_old = self.history_target(c_old, last.m, c_new, force=True)
            ratio = lte_ratio((h, *(t0 - t1 for t0, t1 in zip(ts, ts[1:], strict=False))),
                              order)
            weights = lagrange_weights(ts, s_new)
            u_pred = np.sum([c * lv.u for c, lv in zip(weights, levels, strict=True)], axis=0)
            # Newton starts from BDF2's quadratic extrapolation: the cubic one overshot
            # in the far tail (exp overflow, Maxwell transient at rtol 1e-4)
            weights = lagrange_weights(ts[:3], s_new)
            u_start = np.sum([c * lv.u for c, lv in zip(weights, levels[:3], strict=True)],
                             axis=0)
        elif len(hist) >= 3:   # BDF2
            h1, h2 = last.s - hist[-2].s, hist[-2].s - hist[-3].s
            w = h / h1
            c_new = (1.0 + 2.0 * w) / (1.0 + w)
            c_old = (1.0 + w) * last.m - w * w / (1.0 + w) * hist[-2].m
            c_old = self.history_target(c_old, last.m, c_new)
            ratio = lte_ratio((h, h1, h2), 2)
            weights = lagrange_weights([lv.s for lv in hist[-3:]], s_new)
            u_pred = np.sum([c * lv.u for c, lv in zip(weights, hist[-3:], strict=True)],
                            axis=0)
            u_start = u_pred
        elif len(hist) == 2 and self.max_order >= 3:
            # backward Euler estimated against the linear extrapolation of the two levels
            # (the explicit Euler predictor from the first level's derivative rejected
            # the second step of a Gaussian start by 1e2-1e3 and restarted at 1e-7)
            c_new, c_old = 1.0, last.m
            ratio = lte_ratio((h, last.s - hist[-2].s), 1)
            weights = lagrange_weights([lv.s for lv in hist], s_new)
            u_pred = weights[0] * hist[0].u + weights[1] * hist[1].u
            u_start = last.u
        else:                # backward Euler, from the last level
            c_new, c_old, ratio = 1.0, last.m, lte_ratio((h,), 1)
            if last.udot is None:
                last.udot = self.derivative(last.u, last.s)
            u_pred = last.u + h * last.udot
            u_start = last.u
        u = self.solve_step(last.u, u_start, c_new, c_old, h, s_new)
        if u is None:
            return None
        # the mass to round-off (the step conserves it to the Newton tolerance)
        u = self.renormalised(u, last.m)
        level = self.level(s_new, u)
        # the estimate filtered by the step's Newton matrix (Shampine): the stiff
        # tail modes, which the corrector damps, do not count
        err = self.error_norm(level, np.abs(self.moments_change(u, self.filtered(u - u_pred))))
        # error per unit step: the local error per collision time, so that the global
        # error (local errors relaxing over a few collision times) is proportional to rtol
        unit = self.time_unit(level)
        # below NOISE_FLOOR Newton tolerances a step's error is not resolved
        tol = max(self.opt.rtol * h / unit, NOISE_FLOOR * self.opt.newton_tol)
        return level, abs(ratio) * err / tol

    def renormalised(self, u: NDArray, m_last: NDArray) -> NDArray:
        """``u`` shifted so that its mass is that of the last level's masses ``m_last``
        (a hook: the mixture integrator shifts each species).

        Parameters
        ----------
        u : ndarray
            The step's solution.
        m_last : ndarray
            Masses of the last level.

        Returns
        -------
        ndarray
        """
        return u + math.log(float(m_last.sum()) / float(self.masses(u).sum()))

    def error_norm(self, level: Level, diff: NDArray) -> float:
        """The step's error from the filtered change of the observables (a hook):
        relative on T, absolute on a2.

        Parameters
        ----------
        level : Level
            The new level.
        diff : ndarray
            Absolute change of :meth:`moments_change`'s quantities.

        Returns
        -------
        float
        """
        return max(diff[0] / level.obs[0], diff[1])

    def time_unit(self, level: Level) -> float:
        """The time unit of the error per unit step at ``level`` (a hook): the collision
        time at its temperature, 1 without ``collision_time``.

        Parameters
        ----------
        level : Level
            The new level.

        Returns
        -------
        float
        """
        return 1.0 if self.collision_time is None else self.collision_time(float(level.obs[0]))

    def _step_impl(self, s_stop: float) -> bool:
        """Take one accepted step (retrying smaller ones) and set the next ``h``.

        The step is shortened to end exactly at ``s_stop``; returns whether it was
        reached.
        """
        hist, h = self.hist, self.h
        tries, rejected = 0, None
        failures, high_order_failed, backtracked = 0, self.low_order > 0, False
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
            order = self.order_of(len(hist))
            max_ratio = BDF3_MAX_RATIO if order >= 3 else MAX_RATIO
            ratio_cap = max_ratio * (hist[-1].s - hist[-2].s) if len(hist) >= 2 else math.inf
            h = h_wanted = min(h, self.opt.max_step, ratio_cap)
            rest = s_stop - hist[-1].s   # reached in one step, or two equal ones
            hit = hist[-1].s + h >= s_stop - 1e-12 * max(1.0, abs(s_stop))
            h = rest if hit else (0.5 * rest if h < rest < 2.0 * h else h)
            result = self.attempt(hist, h)
            if result is None:
                self.stats.newton_failures += 1
                failures += 1
                if order >= 3:   # BDF2 for a while (BDF3's failures cascaded to 1e-14)
                    self.low_order = LOW_ORDER_STEPS
                    high_order_failed = True
                if high_order_failed and failures >= BACKTRACK_FAILURES and len(hist) >= 4 \
                        and not backtracked:
                    # the last level, taken by BDF3/BDF4, has no continuation: take it
                    # again by BDF2 from the level before (a far-tail wiggle that T and
                    # a2 do not see; see BACKTRACK_FAILURES)
                    backtracked = True
                    self.stats.backtracks += 1
                    dropped = hist.pop()
                    h = 0.5 * (dropped.s - hist[-1].s)
                    self.step_cap = 0.7 * (dropped.s - hist[-1].s)
                    logger.debug("backtrack from s=%.6g to s=%.6g", dropped.s, hist[-1].s)
                    continue
                # steps stay below the failed one a while (alpha 0.9 Kovacs quench)
                self.step_cap = 0.7 * h
                h = 0.5 * h if h > self.opt.min_step else 2.0 * h
                if h < 1e-14 * max(1.0, abs(hist[-1].s)):
                    raise ConvergenceError(
                        f"Newton failed down to the step {h:.3g} at s={hist[-1].s:.6g}; "
                        "refine the mesh (spacing) or loosen newton_tol")
                continue
            level, err = result
            factor = 0.9 * max(err, 1e-10) ** (-1.0 / order)
            forced = err > 1.0 and h <= self.opt.min_step * 1.000001
            if err <= 1.0 or forced:
                self.stats.forced += int(forced)
                self.stats.accepted += 1
                self.low_order = max(self.low_order - 1, 0)
                hist.append(level)
                del hist[:-(self.max_order + 1)]
                h_next = min(h * min(2.0 if order < 3 else max_ratio, max(0.2, factor)),
                             self.step_cap)
                self.step_cap *= CAP_GROWTH
                self.h = max(h_next, min(h_wanted, self.step_cap)) if hit else h_next
                return hit
            self.stats.rejected += 1
            first = rejected is None
            h, rejected = max(retry_step(h, err, order, rejected), self.opt.min_step), (h, err)
            # the next steps stay below the retried one for a while (bdf3: not after the
            # first two steps of a run, whose rejections only correct the guessed first step)
            if first and not (self.max_order >= 3 and len(hist) <= 2):
                self.step_cap = min(self.step_cap, h)
