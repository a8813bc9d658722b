"""Galerkin FEM for the homogeneous cooling state: cooling ``method="fem"``.

Without forcing, :math:`P(v, t) = f(v/s)/s` with :math:`s = \\sqrt T` solves the
homogeneous Boltzmann equation with kernel :math:`|g|^\\gamma` when

.. math::

    \\zeta\\,\\frac{d}{dc}\\big(c f(c)\\big) = \\tilde Q[f](c), \\qquad
    \\int f = 1, \\quad \\int c^2 f = 1 .

Derivation: :math:`\\partial_t P = -(\\dot s/s^2)(cf)'` and, the collision operator being
homogeneous of degree :math:`\\gamma - 1` in :math:`s`,
:math:`Q[P](v) = n s^{\\gamma-1}\\tilde Q[f](c)`; with the convention
:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`, i.e. :math:`\\dot s = -\\zeta n s^{\\gamma+1}`,
both sides carry :math:`n s^{\\gamma-1}`, so the scaled equation is the same for every
kernel and does not depend on :math:`n`.  Multiplying by :math:`c^2` and integrating,
:math:`-2\\zeta = -\\tfrac14\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle`: the energy identity

.. math::

    \\zeta = \\tfrac18\\,\\langle (1-\\alpha^2)\\,|c - c'|^{\\gamma+2}\\rangle_f ,

which the solver does not impose (it is a check, reported in ``info.extra``).

Discretisation: P2 (or P1) Lagrange elements on :math:`[-V, V]`, the unknown
:math:`u_h = \\ln f_h` (even), the collision weak form :math:`C_i` of the heated solver
(:class:`kinetic_fem.solvers.fem.FEMDiscretisation`) and the drift in weak form,

.. math::

    R_i = C_i[f_h] + \\zeta \\int \\varphi_i'\\, c\\, f_h \\,dc
          - \\zeta \\big[\\varphi_i\\, c f_h\\big]_{-V}^{V} = 0 ,

keeping the outflow through :math:`\\pm V` (the characteristics of the drift leave the
interval there, so no boundary condition may be imposed: a zero-flux condition would
force :math:`\\ln f \\to -\\infty` at the cut-off).  The collision weak form conserves
mass exactly, so :math:`\\sum_i R_i = -2\\zeta V f_h(V)`, the outflow (below 1e-30 for
exponential tails, :math:`O(V^{-3})` for the Maxwell power law): the equation at
:math:`c = 0` is replaced by the normalisation, and the unit temperature
:math:`\\int c^2 f_h = 1` closes the system for :math:`(u_h, \\zeta)`.  Newton's method
(:class:`kinetic_fem.solvers.fem.EquilibratedLU`, the log update of the heated solver) starts
from a Gaussian at the Gaussian estimate of :math:`\\zeta`; near :math:`\\alpha = 1` by
continuation in :math:`\\varepsilon = 1 - \\alpha`, and below :math:`\\alpha = 0.5`
(long exponential tails far from the Gaussian start) by continuation in
:math:`\\alpha` from 0.5.

The inelastic Maxwell model (:math:`\\gamma = 0`) has the closed-form state
:math:`f(c) = 2/(\\pi(1+c^2)^2)` for every alpha (Baldassarri, Marini Bettolo Marconi,
Puglisi, Europhys. Lett. 58, 14 (2002)), :math:`\\zeta = (1-\\alpha^2)/4`; its
:math:`c^{-4}` tail (infinite fourth moment) is resolved on a geometric mesh out to
:math:`V = 10^8`.

A velocity-dependent restitution law has no homogeneous cooling state (the law has its
own speed scale, so the state changes as the gas cools); such problems are refused.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from skfem import LinearForm, asm

from ..distribution import VelocityDistribution
from ..model import CoolingProblem, UnsupportedModelError, check_positive
from ..solve import register_solver
from .fem import (
    ELEMENTS,
    ConvergenceError,
    EquilibratedLU,
    FEMDiscretisation,
    bath_drift,
    bath_drift_jacobian,
    log_update,
    mass,
    newton_info,
    stalled,
    weighted_mass,
)

__all__ = ["solve_fem_cooling", "cooling_state", "CoolingState", "hcs_cutoff", "hcs_spacing",
           "hcs_vertices", "maxwell_hcs", "initial_log_f", "newton_cooling",
           "MAXWELL_CUTOFF"]

logger = logging.getLogger(__name__)

MAXWELL_CUTOFF = 1e8
"""Cut-off of the Maxwell-model mesh: the energy beyond, 4/(pi V), is 1e-8."""
DECADES = 33.0
CONTINUATION_EPS = 0.01
"""Below this inelasticity the state is reached by continuation (steps of CONTINUATION_RATIO)."""
CONTINUATION_RATIO = 2.0
STRONG_ALPHA = 0.5
"""Below this alpha (long exponential tails, far from the Gaussian start) the state is
reached by continuation in alpha from here, in steps of at most STRONG_STEP."""
STRONG_STEP = 0.125
PSEUDO_TIME_STEP = 1.0
"""First pseudo-time step of the globalised Newton iteration (scaled collision times)."""
INCREASE_LIMIT = 2.0
"""Largest increase of ln f in one Newton step (unbounded increases of the tail, where
the starting guess is many decades off, make the iteration diverge)."""


def maxwell_hcs(c: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`f(c) = 2/(\\pi(1+c^2)^2)`, the Maxwell-model HCS at unit temperature.

    Examples
    --------
    >>> from scipy.integrate import quad
    >>> round(quad(lambda c: c**2 * maxwell_hcs(c), -np.inf, np.inf)[0], 12)
    1.0
    """
    c = np.asarray(c, dtype=float)
    return 2.0 / (math.pi * (1.0 + c * c) ** 2)


@LinearForm
def second_moment(v, w):
    """:math:`\\int c^2 \\varphi_i e^{u}` (the gradient of the temperature)."""
    return w.x[0] ** 2 * np.exp(w.u) * v


def hcs_cutoff(problem: CoolingProblem) -> float:
    """Cut-off :math:`V` (thermal velocities) of the HCS mesh.

    The tail :math:`\\zeta c f' \\approx -c^\\gamma f` gives
    :math:`\\ln f \\approx -c^\\gamma/(\\gamma\\zeta)`; :math:`V` is where that reaches 33
    decades, at least the outer edge :math:`1 + 12\\varepsilon^{1/3}` of the near-elastic
    humps and 12 (a Gaussian's 1e-33), plus 1.5; :data:`MAXWELL_CUTOFF` for the Maxwell
    model's power law.
    """
    gamma = problem.gas.gamma
    if gamma == 0.0:
        return MAXWELL_CUTOFF
    zeta = problem.zeta_estimate()
    eps = problem.gas.epsilon
    tail = (DECADES * math.log(10.0) * gamma * zeta) ** (1.0 / gamma)
    return min(max(tail, 1.0 + 12.0 * eps ** (1.0 / 3.0), 12.0) + 1.5, MAXWELL_CUTOFF)


def hcs_spacing(problem: CoolingProblem) -> float:
    """Bulk P2 element size: :math:`\\min(0.05, \\varepsilon^{1/3}/10)` (0.02 for the
    Maxwell model), from ``benchmarks/convergence_fem_cooling.py`` (alpha = 0.85:
    zeta 1.8e-9, a2 8e-9 at 0.05; 3.1e-8, 1.4e-7 at 0.1; fourth order)."""
    if problem.gas.gamma == 0.0:
        return 0.02
    return min(0.05, problem.gas.epsilon ** (1.0 / 3.0) / 10.0)


def hcs_vertices(c_max: float, spacing: float, *, gamma: float,
                 bulk: float = 3.0) -> NDArray[np.float64]:
    """Symmetric HCS vertices: uniform ``spacing`` up to ``bulk``, then graded.

    Element size :math:`h(c) = h_0 \\max(1, c/c_b)^{\\kappa}` with
    :math:`\\kappa = (3 - \\gamma)/3` (P2 error :math:`h^3 (\\ln f)'''` constant in the
    tail :math:`\\ln f \\sim -c^\\gamma`); for the Maxwell model a geometric mesh, ratio
    :math:`1 + h_0/2` up to :math:`c = 30` and 1.1 beyond (the far tail only feeds mass
    and energy back to the bulk).

    Examples
    --------
    >>> v = hcs_vertices(20.0, 0.1, gamma=1.0)
    >>> bool(v[0] == -20.0 and v[-1] == 20.0 and np.all(np.diff(v) > 0))
    True
    """
    half = [0.0]
    c = 0.0
    kappa = (3.0 - gamma) / 3.0
    while c < c_max:
        if gamma == 0.0:
            h = max(spacing, 0.5 * spacing * c if c < 30.0 else 0.1 * c)
        else:
            h = spacing * max(1.0, c / bulk) ** kappa
        c = c + h
        half.append(c)
    half = np.array(half)
    if half[-1] - c_max > 0.5 * (half[-1] - half[-2]):
        half = half[:-1]
    half[-1] = c_max
    return np.concatenate([-half[:0:-1], half])


def initial_log_f(c: NDArray, gamma: float, zeta: float) -> NDArray:
    """A starting :math:`\\ln f`: Gaussian bulk continued by the tail
    :math:`-c^\\gamma/(\\gamma\\zeta)` matched in value and slope (a :math:`c^{-4}` power
    law for the Maxwell model); normalised on a fine grid."""
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


class CoolingState:
    """A converged HCS: discretisation, ``u_h = ln f_h``, ``zeta`` and run info."""

    def __init__(self, disc: FEMDiscretisation, u: NDArray, zeta: float, info) -> None:
        self.disc = disc
        self.u = u
        self.zeta = zeta
        self.info = info

    def energy_identity(self) -> float:
        """:math:`\\tfrac18\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle` by the pair rule."""
        return 0.5 * self.disc.energy_loss(self.u)

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


def newton_cooling(disc: FEMDiscretisation, u0: NDArray, zeta0: float, *, tol: float = 1e-11,
                   max_iter: int = 40, step_limit: float = 10.0) -> CoolingState:
    """Newton's method for :math:`(u_h, \\zeta)` with unit mass and temperature."""
    start = time.perf_counter()
    sym = disc.symmetry
    basis = disc.basis
    red_x = np.zeros(sym.shape[1])
    red_x[sym.indices] = np.abs(disc.dof_locations)
    row0 = int(np.argmin(red_x))
    n_red = sym.shape[1]
    edges = np.array([np.argmin(disc.dof_locations), np.argmax(disc.dof_locations)])

    def system(u_red: NDArray, zeta: float, jacobian: bool = True
               ) -> tuple[NDArray, NDArray | None]:
        u = sym @ u_red
        field = disc.field(u)
        coll, cjac, _ = disc.collision(u, jacobian=jacobian)
        outflow = np.zeros(u.size)
        outflow[edges] = np.abs(disc.dof_locations[edges]) * np.exp(u[edges])
        drift = asm(bath_drift, basis, u=field) - outflow
        grad_mass = asm(mass, basis, u=field)
        grad_temp = asm(second_moment, basis, u=field)
        r = np.empty(n_red + 1)
        r[:n_red] = sym.T @ (coll + zeta * drift)
        r[row0] = grad_mass.sum() - 1.0
        r[n_red] = grad_temp.sum() - 1.0
        if not jacobian:
            return r, None
        djac = asm(bath_drift_jacobian, basis, u=field).toarray()
        djac[edges, edges] -= outflow[edges]
        j = np.zeros((n_red + 1, n_red + 1))
        j[:n_red, :n_red] = sym.T @ (sym.T @ (cjac + zeta * djac).T).T
        j[:n_red, n_red] = sym.T @ drift
        j[row0, :n_red] = sym.T @ grad_mass
        j[row0, n_red] = 0.0
        j[n_red, :n_red] = sym.T @ grad_temp
        return r, j

    def size(delta: NDArray, zeta: float) -> float:
        return max(float(np.abs(delta[:n_red]).max()), abs(delta[n_red]) / max(abs(zeta), 1e-3))

    def trial(u_red: NDArray, zeta: float, delta: NDArray, lam: float) -> tuple[NDArray, float]:
        update = np.minimum(log_update(lam * delta[:n_red], step_limit), INCREASE_LIMIT)
        return u_red + update, zeta + lam * delta[n_red]

    u_red = (sym.T @ u0) / np.asarray(sym.sum(axis=0)).ravel()
    zeta = zeta0
    history: list[float] = []
    dtau = PSEUDO_TIME_STEP
    for it in range(1, max_iter + 1):
        r, j = system(u_red, zeta)
        if dtau < np.inf:
            # pseudo-transient continuation: implicit Euler in the scaled time of
            # d f/d tau = Q[f] - zeta (c f)', whose attractor is the HCS; the step grows
            # geometrically and becomes Newton's method near the solution
            weight = asm(weighted_mass, basis, u=disc.field(sym @ u_red)).toarray()
            damp = sym.T @ (sym.T @ weight.T).T / dtau
            damp[row0] = 0.0
            j[:n_red, :n_red] -= damp
        delta = EquilibratedLU(j).solve(-r)
        step = size(delta, zeta)
        history.append(step)
        logger.debug("HCS newton %d: max|du| = %.3e, zeta = %.15g, dtau = %.3g", it, step,
                     zeta, dtau)
        if not np.isfinite(step):
            break
        u_red, zeta = trial(u_red, zeta, delta, 1.0)
        if dtau == np.inf and (step < tol or stalled(history)):
            break
        # switched evolution relaxation: grow the step while the updates shrink
        ratio = history[-2] / step if len(history) > 1 else 2.0
        dtau = np.inf if step < 1e-2 else dtau * min(max(ratio, 0.5), 3.0)
    return CoolingState(disc, sym @ u_red, zeta, newton_info(history, tol, it, start))


def _discretisation(problem: CoolingProblem, vertices: NDArray, order: int,
                    intorder: int | None) -> FEMDiscretisation:
    return FEMDiscretisation(problem.gas.alpha, vertices, order, intorder or 2 * order + 1,
                             gamma=problem.gas.gamma)


def cooling_state(problem: CoolingProblem, *, order: int = 2, spacing: float | None = None,
                  cutoff: float | None = None, vertices=None, intorder: int | None = None,
                  tol: float = 1e-11, max_iter: int = 100) -> CoolingState:
    """The HCS by Newton's method (see :func:`solve_fem_cooling` for the options)."""
    if problem.gas.restitution.constant is None:
        raise UnsupportedModelError(
            f"the homogeneous cooling state needs a constant restitution coefficient, got "
            f"{problem.gas.restitution!r}: a velocity-dependent law has its own speed scale, "
            "so no scaling state exists (the gas approaches elastic collisions as it cools); "
            "use particles.dsmc.simulate_cooling for the transient")
    if order not in ELEMENTS:
        raise ValueError(f"order must be one of {sorted(ELEMENTS)}, got {order!r}")
    spacing = hcs_spacing(problem) if spacing is None else check_positive("spacing", spacing)
    if vertices is None:
        c_max = hcs_cutoff(problem) if cutoff is None else check_positive("cutoff", cutoff)
        bulk = max(3.0, 1.0 + 12.0 * problem.gas.epsilon ** (1.0 / 3.0))
        verts = hcs_vertices(c_max, spacing, gamma=problem.gas.gamma, bulk=bulk)
    else:
        verts = np.sort(np.asarray(vertices, dtype=float))
        if not np.allclose(verts, -verts[::-1], rtol=0, atol=1e-12 * np.abs(verts).max()) \
                or not np.any(verts == 0.0):
            raise ValueError("vertices must be symmetric about 0 and include c = 0")
    disc = _discretisation(problem, verts, order, intorder)
    eps = problem.gas.epsilon
    zeta0 = problem.zeta_estimate()
    u0 = initial_log_f(disc.dof_locations, problem.gas.gamma, zeta0)
    if eps < CONTINUATION_EPS * (1.0 - 1e-9):
        eps_prev = min(CONTINUATION_EPS, CONTINUATION_RATIO * eps)
        coarse_problem = CoolingProblem.from_parameters(1.0 - eps_prev,
                                                        kernel=problem.gas.kernel)
        coarse = cooling_state(coarse_problem, order=order, tol=1e-7, max_iter=max_iter,
                               spacing=2.0 * hcs_spacing(coarse_problem))
        u0 = coarse.log_f(disc.dof_locations)
        zeta0 = coarse.zeta * (1.0 - (1.0 - eps) ** 2) / (1.0 - (1.0 - eps_prev) ** 2)
    elif problem.gas.alpha < STRONG_ALPHA and problem.gas.gamma > 0.0:
        n_steps = math.ceil((STRONG_ALPHA - problem.gas.alpha) / STRONG_STEP - 1e-9)
        alpha_prev = problem.gas.alpha + (STRONG_ALPHA - problem.gas.alpha) / n_steps
        coarse_problem = CoolingProblem.from_parameters(alpha_prev, kernel=problem.gas.kernel)
        coarse = cooling_state(coarse_problem, order=order, tol=1e-7, max_iter=max_iter,
                               spacing=2.0 * hcs_spacing(coarse_problem))
        u0 = coarse.log_f(disc.dof_locations)
        zeta0 = coarse.zeta * (1.0 - problem.gas.alpha**2) / (1.0 - alpha_prev**2)
    state = newton_cooling(disc, u0, zeta0, tol=tol, max_iter=max_iter)
    if not state.info.converged:
        raise ConvergenceError(
            f"FEM cooling Newton did not converge in {max_iter} iterations at alpha="
            f"{problem.gas.alpha} ({state.info.message}); refine the mesh (smaller spacing) "
            "or increase max_iter")
    return state


@register_solver("fem", problem="cooling")
def solve_fem_cooling(problem: CoolingProblem, *, order: int = 2,
                      spacing: float | None = None, cutoff: float | None = None,
                      vertices=None, intorder: int | None = None, tol: float = 1e-11,
                      max_iter: int = 100) -> VelocityDistribution:
    """Homogeneous cooling state by Galerkin FEM and Newton's method.

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, any kernel :math:`|g|^\\gamma`.
    order : int
        Lagrange degree, 1 or 2.
    spacing : float, optional
        Bulk element size (thermal velocities); default :func:`hcs_spacing`.
    cutoff : float, optional
        Half-width of the interval (thermal velocities); default :func:`hcs_cutoff`.
    vertices : array_like, optional
        Explicit symmetric vertices (thermal velocities); overrides the two above.
    intorder : int, optional
        Gauss degree; default ``2 * order + 1``.
    tol : float
        Stop when the Newton update of :math:`\\ln f` (and the relative update of
        :math:`\\zeta`) is below ``tol``, or when it stalls at round-off.
    max_iter : int
        Newton iteration limit.

    Returns
    -------
    VelocityDistribution
        :math:`f(c)` at unit temperature on the quadrature points;
        ``info.extra["zeta"]`` the cooling rate (:math:`dT/dt = -2\\zeta n
        T^{1+\\gamma/2}`), ``info.extra["zeta_identity"]`` the energy identity
        :math:`\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle/8` by the pair rule.

    Raises
    ------
    UnsupportedModelError
        For a velocity-dependent restitution law.
    ConvergenceError
        If Newton's method does not converge.
    """
    state = cooling_state(problem, order=order, spacing=spacing, cutoff=cutoff,
                          vertices=vertices, intorder=intorder, tol=tol, max_iter=max_iter)
    info = replace(state.info, extra={"zeta": float(state.zeta),
                                      "zeta_identity": float(state.energy_identity()),
                                      "n_dofs": int(state.u.size), "order": order,
                                      "cutoff": float(state.disc.vertices[-1])})
    return state.disc.distribution(state.u, method="fem", params=problem.as_dict(), info=info)
