"""Transients of the heated gas with the Galerkin discretisation of :mod:`kinetic_fem.fem`.

The semi-discrete system for :math:`u_h = \\ln P_h` is

.. math::

    \\frac{d}{dt}\\int \\varphi_i P_h = R_i(P_h)
    = -D\\int \\varphi_i' P_h' + C_i[P_h],

integrated by variable-step BDF2: with :math:`\\omega = \\Delta t_k/\\Delta t_{k-1}`,

.. math::

    \\frac{1+2\\omega}{1+\\omega} m(P^{k+1}) - (1+\\omega)\\, m(P^k)
    + \\frac{\\omega^2}{1+\\omega} m(P^{k-1}) = \\Delta t_k\\, R(P^{k+1}),
    \\qquad m_i(P) = \\int \\varphi_i P,

whose coefficients sum to zero, so the mass is conserved exactly (up to the Newton
tolerance); :math:`P = e^u > 0` by construction.  The first step is backward Euler
and the step doubles from :math:`\\Delta t/2^{K}` to :math:`\\Delta t` over the first
``K`` steps, so the initial layer (the far tail filling in within a collision time)
is resolved.  Where BDF2 has no positive solution (a far tail decaying by more than
a factor :math:`\\approx 4` in one step) the step is redone by backward Euler and a
:class:`~kinetic_fem.fem.ResolutionWarning` says which ``dt`` avoids it.
"""

from __future__ import annotations

import logging
import math
import time
import warnings

import numpy as np
from numpy.typing import NDArray
from skfem import asm

from . import sonine
from .distribution import RunInfo, VelocityDistribution
from .fem import (
    ELEMENTS,
    ConvergenceError,
    FEMDiscretisation,
    ResolutionWarning,
    _Equilibrated,
    _log_update,
    _mesh,
    default_cutoff,
    mass,
    weighted_mass,
)
from .gas import HeatedProblem, check_positive

__all__ = ["evolve_heated", "INITIAL_FLOOR", "RAMP_STEPS"]

logger = logging.getLogger(__name__)

INITIAL_FLOOR = math.log(1e-45)
"""Floor of ln P in the initial data, 15 decades below the resolved range.

A Gaussian's far tail lies hundreds of decades below the collisional tail that
builds up within one collision time; Newton's method on ln P cannot bridge that gap
in one step, so initial data are floored here."""

RAMP_STEPS = 3
"""The first steps grow as dt / 2**RAMP_STEPS, ..., dt / 2, dt."""
MAX_HALVINGS = 5
"""A failed backward-Euler step is split in halves at most this many times."""


def _reduced(disc: FEMDiscretisation, res: NDArray, jac: NDArray) -> tuple[NDArray, NDArray]:
    """Restrict a residual and Jacobian to even fields, ``S^T R`` and ``S^T J S``."""
    sym = disc.symmetry
    return sym.T @ res, sym.T @ (sym.T @ jac.T).T


def _implicit_step(disc: FEMDiscretisation, u_now: NDArray, c_new: float, c_old: NDArray,
                   dt: float, *, tol: float, max_newton: int) -> tuple[NDArray | None, int]:
    """Solve ``c_new * m(u) - c_old - dt * R(u) = 0`` for even ``u``; None on failure."""
    sym = disc.symmetry
    u = u_now.copy()
    lu = None
    for it in range(1, max_newton + 1):
        field = disc.field(u)
        res, jac = disc.residual(u, jacobian=lu is None)
        f = c_new * asm(mass, disc.basis, u=field) - c_old - dt * res
        if lu is None:
            jf = c_new * asm(weighted_mass, disc.basis, u=field).toarray() - dt * jac
            lu = _Equilibrated(_reduced(disc, f, jf)[1])
        delta = lu.solve(-(sym.T @ f))
        size = float(np.abs(delta).max())
        if not np.isfinite(size) or size > 1e100:
            return None, it
        u = u + sym @ _log_update(delta, 10.0)
        if size < tol:
            return u, it
        if size > 0.1:  # far from converged: fresh Jacobian
            lu = None
    return None, max_newton


def _backward_euler(disc: FEMDiscretisation, u_now: NDArray, m_now: NDArray, h: float, *,
                    tol: float, max_newton: int, depth: int = 0) -> tuple[NDArray | None, int]:
    """Backward Euler over ``h``, as two half steps (recursively) if Newton fails."""
    u, its = _implicit_step(disc, u_now, 1.0, m_now, h, tol=tol, max_newton=max_newton)
    if u is not None or depth >= MAX_HALVINGS:
        return u, its
    half, its1 = _backward_euler(disc, u_now, m_now, 0.5 * h, tol=tol, max_newton=max_newton,
                                 depth=depth + 1)
    if half is None:
        return None, its + its1
    m_half = asm(mass, disc.basis, u=disc.field(half))
    u, its2 = _backward_euler(disc, half, m_half, 0.5 * h, tol=tol, max_newton=max_newton,
                              depth=depth + 1)
    return u, its + its1 + its2


def _steps(t_final: float, dt: float) -> NDArray[np.float64]:
    """Step sizes: a doubling ramp up to ``dt``, then ``dt`` (the last one shortened)."""
    ramp = dt / 2.0 ** np.arange(RAMP_STEPS, 0, -1)
    ramp = ramp[np.cumsum(ramp) < t_final]
    rest = t_final - ramp.sum()
    n = max(1, int(math.ceil(rest / dt - 1e-9)))
    return np.concatenate([ramp, np.full(n, rest / n)])


def evolve_heated(alpha: float, *, density: float = 1.0, diffusion: float = 1.0,
                  t_final: float, dt: float, initial_temperature: float | None = None,
                  order: int = 2, spacing: float = 0.2, cutoff: float | None = None,
                  n_output: int = 200, tol: float = 1e-10,
                  max_newton: int = 12) -> VelocityDistribution:
    """Relaxation of the heated gas from a Gaussian (see the module docstring).

    Parameters
    ----------
    alpha, density, diffusion : float
        Problem parameters.  The run is made at ``n = D = 1`` and rescaled exactly:
        :math:`v = u v_1`, :math:`t = t_1/(n u)` with :math:`u = (D/n)^{1/3}`.
    t_final, dt : float
        End time and step in units of ``n = D = 1``.
    initial_temperature : float, optional
        Temperature of the initial Gaussian at ``n = D = 1``; default a quarter of the
        first-order Sonine steady temperature.  The element size is ``spacing`` times
        the smaller thermal velocity, the cut-off covers the larger.
    order, spacing, cutoff
        As in :func:`kinetic_fem.fem.solve_fem`.
    n_output : int
        About this many points of the time series ``series["t"]``,
        ``"temperature"``, ``"a2"``, ``"mass"`` (physical units).
    tol : float
        Newton tolerance on the update of :math:`\\ln P` in each step.
    max_newton : int
        Newton iterations per step before the step counts as failed.

    Returns
    -------
    VelocityDistribution
        The distribution at ``t_final`` with the time series.

    Raises
    ------
    ConvergenceError
        If even a backward-Euler step fails (reduce ``dt``).
    """
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion)
    t_final = check_positive("t_final", t_final)
    dt = check_positive("dt", dt)
    if order not in ELEMENTS:
        raise ValueError(f"order must be one of {sorted(ELEMENTS)}, got {order!r}")
    t_ss = sonine.steady_temperature(alpha)
    t0 = 0.25 * t_ss if initial_temperature is None else check_positive(
        "initial_temperature", initial_temperature)
    c_max = default_cutoff(alpha) if cutoff is None else check_positive("cutoff", cutoff)
    # cut-off for the hotter, spacing for the colder of the two temperatures
    verts = _mesh(alpha, cutoff=c_max * max(1.0, math.sqrt(t0 / t_ss)),
                  spacing=spacing * min(1.0, math.sqrt(t0 / t_ss)), vertices=None)
    disc = FEMDiscretisation(alpha, verts, order, 2 * order + 1)
    start = time.perf_counter()
    steps = _steps(t_final, dt)
    u_now = np.logaddexp(disc.gaussian(t0), INITIAL_FLOOR)  # P = Gaussian + 1e-45
    m_prev = m_now = asm(mass, disc.basis, u=disc.field(u_now))
    every = max(1, steps.size // n_output)
    xq, wq, _ = disc.points
    series: dict[str, list[float]] = {"t": [], "temperature": [], "a2": [], "mass": []}

    def record(t: float, u: NDArray) -> None:
        p = disc.values(u)
        mom = [np.sum(wq * p * xq**k) for k in (0, 2, 4)]
        temp = mom[1] / mom[0]
        series["t"].append(t)
        series["temperature"].append(temp)
        series["a2"].append(mom[2] / mom[0] / (3.0 * temp**2) - 1.0)
        series["mass"].append(mom[0])

    record(0.0, u_now)
    iterations = fallbacks = 0
    t = 0.0
    for k, h in enumerate(steps):
        u = None
        if k > 0:
            w = h / steps[k - 1]
            c_old = (1.0 + w) * m_now - w * w / (1.0 + w) * m_prev
            u, its = _implicit_step(disc, u_now, (1.0 + 2.0 * w) / (1.0 + w), c_old, h,
                                    tol=tol, max_newton=max_newton)
            iterations += its
        if u is None:
            fallbacks += k > 0
            u, its = _backward_euler(disc, u_now, m_now, h, tol=tol, max_newton=max_newton)
            iterations += its
            if u is None:
                raise ConvergenceError(
                    f"implicit step {k + 1} (t={t + h:.4g}) did not converge in {max_newton} "
                    f"Newton iterations even in {2**MAX_HALVINGS} substeps; reduce dt={dt:.3g}")
        t += h
        u_now = u
        m_prev, m_now = m_now, asm(mass, disc.basis, u=disc.field(u))
        if k % every == 0 or k == steps.size - 1:
            record(t, u)
    if fallbacks:
        nu_max = float(2.0 * np.abs(verts).max())
        warnings.warn(
            f"BDF2 had no positive solution in {fallbacks} of {steps.size} steps (the far tail "
            f"relaxes at rate ~{nu_max:.3g}, dt={dt:.3g}); those steps used backward Euler "
            f"(first order). For second order throughout use dt < {1.3 / nu_max:.3g}",
            ResolutionWarning, stacklevel=2)
    scale = problem.velocity_scale
    out = {key: np.asarray(val) for key, val in series.items()}
    out["t"] = out["t"] * scale**2 / problem.diffusion  # t = t_1 / (n u) = t_1 u^2 / D
    out["temperature"] = out["temperature"] * scale**2
    info = RunInfo(converged=True, iterations=iterations, residual=float("nan"),
                   wall_time=time.perf_counter() - start,
                   message=f"BDF2, {steps.size} steps (dt={dt:.4g} after a {RAMP_STEPS}-step "
                           f"ramp), {iterations} Newton iterations",
                   extra={"n_dofs": int(disc.dof_locations.size), "dt": dt,
                          "backward_euler_steps": fallbacks + 1})
    dist = disc.distribution(u_now, method="fem", params=problem.as_dict(), info=info,
                             series=out)
    return dist.rescaled(scale) if scale != 1.0 else dist
