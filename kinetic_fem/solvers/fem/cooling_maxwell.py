"""The inelastic Maxwell model's cooling state on a short mesh with an analytic tail.

The cooling state of the Maxwell kernel (:math:`\\gamma = 0`) has a :math:`c^{-4}` tail
whose energy beyond :math:`V` is :math:`4/(\\pi V)`, and the outer mesh is fed from
:math:`c/a` (:math:`a = (1-\\alpha)/2`); a truncated mesh therefore had to reach
:math:`V = 10^8` (3925 P2 dofs, 31-46 yardstick units per state).  Here the mesh ends
at :data:`MAXWELL_TAIL_CUTOFF` and the state beyond is the tail closure of
:mod:`kinetic_fem.operators.maxwell_tail`, :math:`f = A c^{-4}(1 - 2/c^2)` with
:math:`A` matched to :math:`f_h(V)`; its mass, energy, loss and gain terms enter the
Galerkin equations of :mod:`kinetic_fem.solvers.fem.cooling` (same weak form, same
outflow term at :math:`\\pm V`, same unit mass and temperature, now of mesh plus tail).
The FEM state is still a genuine solve: the closed form :math:`2/(\\pi(1+c^2)^2)`
only starts Newton's method, which is within the discretisation error of the state,
so one Jacobian suffices: a Newton step (and chord steps on its factorisation, if the
residual is not yet at its round-off floor; :func:`kinetic_fem.solvers.newton.newton`).

The result carries :math:`f` recovered from the superconvergent points on the mesh
(:func:`kinetic_fem.solvers.fem.cooling_tail.recovered_distribution`) and the tail
closure on the nodes of :func:`~kinetic_fem.operators.maxwell_tail.tail_quadrature`
beyond :math:`V` (exact for the tail's mass and energy), so its temperature is one to
the Newton tolerance.  Accuracy and speed:
``benchmarks/archive/results/fem_cooling_models_speed.md``.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import replace

import numpy as np
import scipy.sparse
from numpy.typing import NDArray
from skfem import asm

from ...distribution import VelocityDistribution
from ...error import ErrorEstimate, ErrorRecipe, richardson_factor
from ...operators.maxwell_tail import (
    tail_gain_matrix,
    tail_moments,
    tail_quadrature,
    tail_shape,
)
from ...run_info import RunInfo
from ..newton import newton
from .cooling_newton import (
    RESIDUAL_FLOOR,
    RESIDUAL_FLOOR_REL,
    RESIDUAL_STALL,
    CoolingState,
    second_moment,
)
from .cooling_tail import maxwell_hcs, power_tail_vertices, recovered_log_f
from .error import BISECTED_METHOD, bisected, interpolated_log
from .heated import (
    ConvergenceError,
    EquilibratedLU,
    FEMDiscretisation,
    bath_drift,
    bath_drift_jacobian,
    mass,
    weighted_mass,
)
from .newton import CHORD_LEVEL

__all__ = ["MAXWELL_TAIL_CUTOFF", "MAXWELL_TAIL_SPACING", "MAXWELL_TAIL_ORDER",
           "MaxwellTailSystem", "MaxwellTailState", "maxwell_tail_state",
           "maxwell_tail_vertices", "maxwell_cooling_state", "maxwell_tail_estimate",
           "maxwell_tail_recipe", "NEAR_FACTOR", "FAR_FACTOR"]

logger = logging.getLogger(__name__)

MAXWELL_TAIL_CUTOFF = 200.0
"""Cut-off of the mesh with the tail closure (thermal velocities)."""
MAXWELL_TAIL_ORDER = 3
"""Element degree of the default."""
MAXWELL_TAIL_SPACING = 0.04
"""Bulk element size of the P3 default (P2: half of it)."""
NEAR_FACTOR = 1.0
"""Geometric ratio :math:`1 +` this :math:`\\times h_0` from :math:`c = 2` to 30."""
FAR_FACTOR = 0.625
"""Geometric ratio :math:`1 +` this :math:`\\times h_0` beyond :math:`c = 30` (P3 at
:math:`h_0 = 0.04`: 1.025; at 1.04 and 1.05 the f error at alpha = 0 was 5e-7 and 1.4e-7
against 4e-8; benchmarks/archive/results/fem_cooling_models_speed.md)."""


def maxwell_tail_vertices(spacing: float, cutoff: float = MAXWELL_TAIL_CUTOFF
                          ) -> NDArray[np.float64]:
    """The mesh of the tail closure: uniform ``spacing`` up to :math:`c = 2`, geometric
    with ratio :math:`1 + h_0` up to :math:`c = 30` and :math:`1 +` :data:`FAR_FACTOR`
    :math:`h_0` beyond, up to ``cutoff``.

    Parameters
    ----------
    spacing : float
        Bulk element size :math:`h_0`.
    cutoff : float
        :math:`V`.

    Returns
    -------
    ndarray
        Vertices symmetric about 0, including 0.
    """
    return power_tail_vertices(cutoff, spacing, near_factor=NEAR_FACTOR, far_factor=FAR_FACTOR)


class MaxwellTailSystem:
    """Residual and Jacobian of the HCS equations with the tail closure.

    Unknowns: the even dofs of :math:`u_h = \\ln f_h` and :math:`\\zeta`.

    Parameters
    ----------
    disc : FEMDiscretisation
        Maxwell kernel, symmetric mesh on :math:`[-V, V]` with a vertex at 0.
    """

    def __init__(self, disc: FEMDiscretisation) -> None:
        self.disc = disc
        self.sym = disc.symmetry
        self.n_red = self.sym.shape[1]
        self.cutoff = float(disc.vertices[-1])
        loc = disc.dof_locations
        self.edges = np.array([np.argmin(loc), np.argmax(loc)])
        red_x = np.zeros(self.n_red)
        red_x[self.sym.indices] = np.abs(loc)
        self.row0 = int(np.argmin(red_x))
        self.g_edge = float(tail_shape(self.cutoff))
        mass_t, energy_t = tail_moments(self.cutoff)
        self.mass_t, self.energy_t = 2.0 * mass_t, 2.0 * energy_t  # both sides, per unit A
        verts, dofs = disc.mesh_arrays
        xq, wq, eq = disc.points
        self.wq = wq
        self.gain = tail_gain_matrix(verts, dofs, disc.order, xq, disc.alpha, self.cutoff)
        # basis values at the outer points: phi[q, j]
        ref = disc.basis.quadrature[0][0]
        shapes = np.array([disc.basis.elem.lbasis(ref[None, :], i)[0]
                           for i in range(dofs.shape[1])])  # (k, n_ref)
        rows = np.arange(xq.size).repeat(dofs.shape[1])
        cols = dofs[eq].ravel()
        vals = shapes.T[np.arange(xq.size) % ref.size].ravel()
        self.phi = scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(xq.size, loc.size))
        # A from the mean of ln f_h - ln g over the last element (the Galerkin oscillation
        # of ln f_h, +2s at the vertices, has zero mean over every element)
        last = int(np.argmax(verts[:-1]))
        ref_w = disc.basis.quadrature[1]
        self.match_dofs = dofs[last]
        self.match_weights = shapes @ ref_w / ref_w.sum()  # mean of each shape function
        xl = verts[last] + (verts[last + 1] - verts[last]) * ref
        self.match_log_g = float(ref_w @ np.log(tail_shape(xl)) / ref_w.sum())

    def amplitude(self, u: NDArray) -> float:
        """:math:`A`: :math:`\\ln A` the mean of :math:`\\ln f_h - \\ln g` over the last
        element."""
        return math.exp(float(self.match_weights @ u[self.match_dofs]) - self.match_log_g)

    def __call__(self, x: NDArray, jacobian: bool = True) -> tuple[NDArray, NDArray | None]:
        disc, sym, basis, n_red, row0 = self.disc, self.sym, self.disc.basis, self.n_red, \
            self.row0
        u = sym @ x[:n_red]
        zeta = float(x[n_red])
        field = disc.field(u)
        coll, cjac, _ = disc.collision(u, jacobian=jacobian, energy_power=None, even=True)
        amp = self.amplitude(u)
        edges = self.edges
        outflow = np.zeros(u.size)
        outflow[edges] = np.abs(disc.dof_locations[edges]) * np.exp(u[edges])
        drift = asm(bath_drift, basis, u=field) - outflow
        grad_mass = asm(mass, basis, u=field)
        grad_temp = asm(second_moment, basis, u=field)
        pw = self.wq * disc.values(u)
        tail_gain = amp * (self.gain @ pw)
        m_t, e_t = amp * self.mass_t, amp * self.energy_t
        full = coll + zeta * drift + tail_gain - m_t * grad_mass
        r = np.empty(n_red + 1)
        r[:n_red] = sym.T @ full
        r[row0] = grad_mass.sum() + m_t - 1.0
        r[n_red] = grad_temp.sum() + e_t - 1.0
        if not jacobian:
            return r, None
        djac = asm(bath_drift_jacobian, basis, u=field).toarray()
        djac[edges, edges] -= outflow[edges]
        jac = cjac + zeta * djac - m_t * asm(weighted_mass, basis, u=field).toarray()
        jac += amp * (self.gain * pw[None, :]) @ self.phi
        # A depends on the dof at +V: d(A X)/du_edge = A X
        match, mw = self.match_dofs, self.match_weights
        jac[:, match] += np.outer(tail_gain - m_t * grad_mass, mw)
        j = np.zeros((n_red + 1, n_red + 1))
        j[:n_red, :n_red] = sym.T @ (sym.T @ jac.T).T
        j[:n_red, n_red] = sym.T @ drift
        dmass = grad_mass.copy()
        dmass[match] += m_t * mw
        dtemp = grad_temp.copy()
        dtemp[match] += e_t * mw
        j[row0, :n_red] = sym.T @ dmass
        j[row0, n_red] = 0.0
        j[n_red, :n_red] = sym.T @ dtemp
        return r, j

    def row_scale(self, x: NDArray) -> NDArray:
        """Natural size of each equation: :math:`\\int\\varphi_i f_h` (1 for the constraints)."""
        u = self.sym @ x[:self.n_red]
        scale = np.empty(self.n_red + 1)
        scale[:self.n_red] = self.sym.T @ asm(mass, self.disc.basis, u=self.disc.field(u))
        scale[self.row0] = scale[self.n_red] = 1.0
        return np.maximum(np.abs(scale), 1e-300)

    def reduce(self, u: NDArray) -> NDArray:
        """Even dofs of a full coefficient vector (averaged over the pairs)."""
        return (self.sym.T @ u) / np.asarray(self.sym.sum(axis=0)).ravel()

    def moments(self, u: NDArray) -> tuple[float, float]:
        """Mass and energy of mesh plus tail."""
        field = self.disc.field(u)
        amp = self.amplitude(u)
        return (float(asm(mass, self.disc.basis, u=field).sum()) + amp * self.mass_t,
                float(asm(second_moment, self.disc.basis, u=field).sum()) + amp * self.energy_t)


def _step_size(delta: NDArray, x: NDArray) -> float:
    return max(float(np.abs(delta[:-1]).max()), abs(delta[-1]) / max(abs(x[-1]), 1e-3))


def _residual_size(r: NDArray, x: NDArray) -> float:
    return float(np.abs(r).max())


class MaxwellTailState(CoolingState):
    """A converged Maxwell-model HCS on the short mesh with its tail closure.

    Parameters
    ----------
    system : MaxwellTailSystem
        The equations it solves (mesh, tail terms).
    u, zeta, info
        As for :class:`~kinetic_fem.solvers.fem.cooling_newton.CoolingState`.
    """

    def __init__(self, system: MaxwellTailSystem, u: NDArray, zeta: float, info) -> None:
        super().__init__(system.disc, u, zeta, info)
        self.system = system

    @property
    def amplitude(self) -> float:
        """:math:`A` of the tail :math:`A c^{-4}(1 - 2c^{-2} + 3c^{-4})` beyond the mesh."""
        return self.system.amplitude(self.u)

    def log_f(self, c: NDArray) -> NDArray:
        """:math:`\\ln f_h` at ``c`` on the mesh, the tail closure beyond it."""
        c = np.asarray(c, dtype=float)
        out = np.empty_like(c)
        inside = np.abs(c) < self.system.cutoff
        out[inside] = super().log_f(c[inside])
        out[~inside] = math.log(self.amplitude) + np.log(tail_shape(np.abs(c[~inside])))
        return out

    def energy_identity(self) -> float:
        """:math:`\\tfrac18(1-\\alpha^2)\\langle g^2\\rangle` of mesh plus tail: for the
        Maxwell kernel :math:`\\langle g^2\\rangle = 2(M_0 M_2 - M_1^2)` (:math:`M_1 = 0`,
        the state is even), with the moments of the Galerkin state and its tail (the
        pair rule over the mesh alone would miss the pairs with a tail partner)."""
        m0, m2 = self.system.moments(self.u)
        return 0.25 * (1.0 - self.disc.alpha**2) * m0 * m2

    def distribution(self, **kwargs) -> VelocityDistribution:
        """The recovered :math:`f` on the mesh's quadrature points and the tail closure
        on the nodes of :func:`~kinetic_fem.operators.maxwell_tail.tail_quadrature`.

        Parameters
        ----------
        **kwargs
            Passed to :meth:`VelocityDistribution.from_values`.

        Returns
        -------
        VelocityDistribution
        """
        disc = self.disc
        xq, wq, _ = disc.points
        ct, wt = tail_quadrature(self.system.cutoff)
        ft = self.amplitude * tail_shape(ct)
        v = np.concatenate([-ct[::-1], xq, ct])
        values = np.concatenate([ft[::-1], np.exp(recovered_log_f(disc, self.u, xq)), ft])
        weights = np.concatenate([wt[::-1], wq, wt])
        dist = VelocityDistribution.from_values(v, values, weights=weights, **kwargs)
        return replace(dist, raw_moments=heavy_tail_moments(dist.raw_moments))


def maxwell_tail_estimate(state: MaxwellTailState) -> ErrorEstimate:
    """The bisected-mesh estimate of a Maxwell-model state with its tail closure.

    As :func:`~kinetic_fem.solvers.fem.cooling_newton.cooling_estimate`: :math:`\\ln f_h`
    interpolated exactly onto the mesh with every element bisected (the same cut-off
    :math:`V` and tail closure), one undamped Newton step of
    :class:`MaxwellTailSystem` there (with :math:`\\zeta` and the tail amplitude), and the
    result compared with the distribution of the step, times
    :func:`~kinetic_fem.error.richardson_factor`.  The closure at :math:`V` carries an
    error of its own that no mesh changes and the bisection does not see (measured at
    alpha 0.9, P3 h 0.08: the tail amplitude off by 3.9e-6, 5.8e-7, 7.1e-8 at
    :math:`V` = 100, 200, 400, i.e. :math:`V^{-3}`, whatever the spacing): the f error
    adds the change of f when the state is solved again on the mesh cut at the last
    vertex :math:`V' \\le V/2`, times :math:`1/((V/V')^3 - 1)`.  The :math:`\\zeta`
    error is the larger of the step's change and the defect of the energy identity
    :math:`|\\zeta_h/\\zeta_{id} - 1|` (:meth:`MaxwellTailState.energy_identity`, exact
    for the exact state; the solve's :math:`\\zeta_h` carries the closure's
    :math:`V^{-4}` error, 1e-11 to 2e-10 at alpha 0 to 0.9, while the identity of the
    same state holds to 1e-15).  The temperature error is the residual of the
    constraint :math:`T = 1`; :math:`a_2` is infinite (the :math:`c^{-4}` tail), exactly
    as for the exact state, so its error is NaN with a note.  Cost: one Jacobian on
    twice the dofs and a solve on the shorter mesh (0.3 - 5 times the solve).

    Parameters
    ----------
    state : MaxwellTailState
        A converged state.

    Returns
    -------
    ErrorEstimate
    """
    disc = state.disc
    fine = bisected(disc)
    system = MaxwellTailSystem(fine)
    x = np.append(system.reduce(interpolated_log(disc, state.u, fine)), state.zeta)
    res, jac = system(x, True)
    assert jac is not None
    x = x - EquilibratedLU(jac).solve(res)
    better = MaxwellTailState(system, system.sym @ x[:system.n_red], float(x[-1]),
                              state.info).distribution()
    base = state.distribution()
    est = ErrorEstimate.from_comparison(
        base, better, method=BISECTED_METHOD, factor=richardson_factor(disc.order),
        zeta=(state.zeta, float(x[-1])),
        note="a2 is infinite (the c^-4 tail), as for the exact state: no a2 error")
    identity = abs(state.zeta / state.energy_identity() - 1.0)
    # the closure's error: the state on the mesh cut at V' <= V/2 (V^-3 in f)
    verts = disc.vertices
    short_cut = float(verts[verts <= 0.5 * verts[-1]].max())
    short = maxwell_tail_state(replace(disc, vertices=verts[np.abs(verts) <= short_cut]))
    if not short.info.converged:
        return replace(est, temperature=abs(base.temperature - 1.0), a2=float("nan"),
                       zeta=max(est.zeta or 0.0, identity),
                       note=f"{est.note}; f without the cut-off's share (the state cut at "
                            f"{short_cut:.3g} did not converge: {short.info.message})")
    closure = ErrorEstimate.from_comparison(
        base, short.distribution(), method="the mesh cut at half the cut-off",
        factor=1.0 / ((verts[-1] / short_cut) ** 3 - 1.0))
    return replace(est, temperature=abs(base.temperature - 1.0), a2=float("nan"),
                   zeta=max(est.zeta or 0.0, identity),
                   f_relative=est.f_relative + closure.f_relative,
                   method=f"{BISECTED_METHOD} plus the cut-off halved")


def maxwell_tail_recipe(state: MaxwellTailState) -> ErrorRecipe:
    """The :class:`~kinetic_fem.error.ErrorRecipe` of :func:`maxwell_tail_estimate`.

    Parameters
    ----------
    state : MaxwellTailState
        A converged state.
    """
    return ErrorRecipe(lambda dist: maxwell_tail_estimate(state), BISECTED_METHOD)


def heavy_tail_moments(raw: NDArray[np.float64]) -> NDArray[np.float64]:
    """Raw moments of an even state with a :math:`c^{-4}` tail.

    The moments of the quadrature are finite only because it stops at the far end of
    :func:`~kinetic_fem.operators.maxwell_tail.tail_quadrature`; the state's own
    :math:`\\langle c^k\\rangle` diverges for even :math:`k \\ge 4`
    (:math:`c^{k-4}` is not integrable) and its odd moments vanish by symmetry (as a
    principal value for :math:`k \\ge 3`).  So :math:`a_2 = \\infty` and the higher
    Sonine coefficients are undefined (NaN).

    Parameters
    ----------
    raw : ndarray, shape (MAX_MOMENT + 1,)
        Raw moments of the quadrature (mass, energy and the truncated higher ones).

    Returns
    -------
    ndarray
        ``raw`` with the odd moments 0 and the even ones from order 4 on infinite.

    Examples
    --------
    >>> heavy_tail_moments(np.array([1.0, 1e-17, 1.0, 1e-16, 2e9, 0.0, 1e18]))
    array([ 1.,  0.,  1.,  0., inf,  0., inf])
    """
    out = np.array(raw, dtype=float)
    out[1::2] = 0.0
    out[4::2] = np.inf
    return out


def maxwell_tail_state(disc: FEMDiscretisation, *, tol: float = 1e-11,
                       max_iter: int = 20) -> MaxwellTailState:
    """The Maxwell-model HCS on ``disc`` with the tail closure beyond its cut-off.

    Parameters
    ----------
    disc : FEMDiscretisation
        Maxwell kernel (``gamma = 0``), symmetric mesh on :math:`[-V, V]`.
    tol : float
        Stop when the row-scaled residual (a rate) is below ``tol`` times
        :math:`\\zeta`, or below its round-off floor (as
        :func:`~kinetic_fem.solvers.fem.cooling_newton.newton_cooling` from a close start).
    max_iter : int
        Newton and chord steps allowed.

    Returns
    -------
    MaxwellTailState
        ``info.converged`` False if Newton's method did not converge.
    """
    start = time.perf_counter()
    system = MaxwellTailSystem(disc)
    u0 = np.log(maxwell_hcs(disc.dof_locations))
    x0 = np.append(system.reduce(u0), 0.25 * (1.0 - disc.alpha**2))
    # the stopping rule of kinetic_fem.solvers.fem.cooling_newton.newton_cooling from a
    # close start: the row-scaled residual (a rate) below tol * zeta or its round-off floor
    scale = float(x0[-1])
    floor = max(RESIDUAL_FLOOR, RESIDUAL_FLOOR_REL * scale)
    res = newton(system, x0, tol=max(tol * scale, floor), max_iter=max_iter,
                 criterion="residual", norm=_residual_size, step_norm=_step_size,
                 row_scale=system.row_scale, factorize=lambda j: EquilibratedLU(j).solve,
                 chord=CHORD_LEVEL, stall_level=RESIDUAL_STALL * scale,
                 name="FEM cooling Newton (Maxwell tail)")
    info = RunInfo(converged=res.converged, iterations=res.iterations,
                   residual=res.residual / scale, wall_time=time.perf_counter() - start,
                   message=f"{res.message} (residual / zeta {res.residual / scale:.1e}, "
                           f"last step {res.step:.1e})")
    return MaxwellTailState(system, system.sym @ res.x[:system.n_red], float(res.x[-1]), info)


def maxwell_cooling_state(alpha: float, *, order: int | None = None,
                          spacing: float | None = None, intorder: int | None = None,
                          tol: float = 1e-11, max_iter: int = 20) -> MaxwellTailState:
    """The default Maxwell-model HCS: P3 on :func:`maxwell_tail_vertices` with the tail.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    order : int, optional
        Lagrange degree (default :data:`MAXWELL_TAIL_ORDER`).
    spacing : float, optional
        Bulk element size (default :data:`MAXWELL_TAIL_SPACING`, half of it for P1/P2).
    intorder : int, optional
        Gauss degree (default ``2 * order + 1``).
    tol, max_iter
        As for :func:`maxwell_tail_state`.

    Returns
    -------
    MaxwellTailState

    Raises
    ------
    ConvergenceError
        If Newton's method does not converge.
    """
    order = MAXWELL_TAIL_ORDER if order is None else order
    if spacing is None:
        spacing = MAXWELL_TAIL_SPACING if order == 3 else 0.5 * MAXWELL_TAIL_SPACING
    disc = FEMDiscretisation(alpha, maxwell_tail_vertices(spacing), order,
                             intorder or 2 * order + 1, gamma=0.0)
    state = maxwell_tail_state(disc, tol=tol, max_iter=max_iter)
    if not state.info.converged:
        raise ConvergenceError(
            f"FEM cooling Newton (Maxwell model, tail closure beyond c = "
            f"{MAXWELL_TAIL_CUTOFF:g}) did not converge at alpha={alpha} from the closed-form "
            f"start ({state.info.message}); refine the mesh (smaller spacing) or pass a "
            "cutoff for the truncated mesh")
    return state
