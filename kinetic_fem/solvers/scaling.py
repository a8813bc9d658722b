"""Quasi-elastic limits: the phi (heated) and psi (free cooling) equations.

**Heated gas** (paper section 2.2, claim C5).  For :math:`\\epsilon = 1-\\alpha \\to 0`
the steady state in the scaled velocity :math:`x = (n\\epsilon/D)^{1/3} v`,
:math:`\\phi(x) = (D/n\\epsilon)^{1/3} P_s(v)`, solves

.. math::

    \\phi(x) = C \\exp\\Big(-\\frac16 \\int dy\\, |y-x|^3 \\phi(y)\\Big),
    \\qquad \\int \\phi = 1.

(The paper writes :math:`\\phi = (n\\epsilon/D)^{1/3} P_s`, which is not normalised:
a misprint.)  Its asymptotics: exactly
:math:`\\ln\\phi = \\ln C - |x|^3/6 - \\langle x^2\\rangle |x|/2 + o(1)` for large
:math:`|x|` (the paper keeps only the cubic term) and
:math:`\\phi \\approx \\tilde C e^{-\\lambda x^2/2}` at small :math:`x` with
:math:`\\lambda = \\int |x|\\phi`, :math:`\\tilde C = \\phi(0)`; the crossover is
:math:`x_{cr} = 3\\lambda`.

**Free cooling** (paper section 3.2, claim C12).  Each hump of the scaled
distribution has the shape :math:`\\psi(y)`, solution of

.. math::

    \\psi' + \\langle y^2\\rangle_\\psi \\psi + \\frac12 \\psi \\int dy'\\, \\psi(y')
    \\big(|y-y'|(y-y') - (y+y')^2\\big) = 0, \\qquad \\int\\psi = 1,\\
    \\langle y\\rangle_\\psi = 0,

equivalently (the sign of the integral is a misprint in the paper)

.. math::

    \\ln\\psi(y) = \\ln C - \\langle y^2\\rangle_\\psi\\, y
    - \\frac16 \\int dy'\\, \\psi(y') \\big(|y-y'|^3 - (y+y')^3\\big).

See :mod:`kinetic_fem.solvers.scaling_psi` and ``docs/user_guide/quasi_elastic.rst`` for the
derivation from the Boltzmann equation and the corrected tails and ODE.

Both are solved on uniform grids with Simpson weights; the kernels are O(N)
cumulative-moment sums (:mod:`kinetic_fem.operators.grid`), and Newton-GMRES iterates on
:math:`\\ln\\phi` (or :math:`\\ln\\psi`) to a max-norm residual of :math:`10^{-12}`.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..distribution import RunInfo, VelocityDistribution
from ..gas import check_positive
from ..operators.grid import abs_power_convolution, simpson_weights
from .newton import run_info
from .scaling_common import (
    Evaluation,
    LimitSolution,
    check_int,
    check_solver_options,
    combine_errors,
    fourth_derivative_extrapolated,
    log_normalise,
    newton_krylov,
    refinement_estimate,
    with_estimate,
)
from .scaling_psi import PsiAsymptotics, PsiSolution, solve_psi

__all__ = ["solve_phi", "PhiSolution", "PhiAsymptotics", "solve_psi", "PsiSolution",
           "PsiAsymptotics", "LAMBDA_PAPER", "phi_grid"]

logger = logging.getLogger(__name__)

LAMBDA_PAPER = 0.785
"""The paper's value of :math:`\\lambda = \\int |x| \\phi(x) dx` (three digits)."""

PHI_CONSTANTS = ("C", "lam", "x2", "x4", "a2", "x_cr")


@dataclass(frozen=True)
class PhiAsymptotics:
    """Numerical checks of the asymptotics of :math:`\\phi` (claim C5).

    Attributes
    ----------
    tail_window : tuple of float
        The :math:`x` range of the tail checks.
    tail_linear_term : float
        :math:`\\ln\\phi - (\\ln C - x^3/6)` at the window's upper end; the exact tail
        predicts :math:`-\\langle x^2\\rangle x/2`.
    tail_deviation : float
        :math:`\\max |\\ln\\phi - (\\ln C - x^3/6 - \\langle x^2\\rangle x/2)|` in the window.
    tail_exponent : float
        Slope of :math:`\\ln(-\\ln(\\phi/C))` against :math:`\\ln x` at the window's
        upper end (tends to 3).
    core_lambda : float
        :math:`\\lambda` fitted from :math:`\\ln\\phi = a_0 - \\lambda x^2/2 + a_4 x^4`
        on :math:`|x| \\le 0.4`.
    core_quartic : float
        The fitted :math:`a_4`; theory :math:`-\\tilde C/12` from
        :math:`(\\ln\\phi)'''' = -2\\phi`.
    c_tilde_rel : float
        :math:`|C e^{-\\langle |x|^3\\rangle/6} / \\phi(0) - 1`.
    x_cr_observed : float
        Where the effective exponent of :math:`\\phi` reaches 5/2, halfway from 2 to 3.
    ode_residual : float
        :math:`\\max |(\\ln\\phi)'''' + 2\\phi| / \\max\\phi` on :math:`|x| \\le 3` by finite
        differences.
    energy_identity : float
        :math:`\\int\\int |x-y|^3\\phi\\phi` (exactly 4: energy balance C1 in the limit).
    """

    tail_window: tuple[float, float]
    tail_linear_term: float
    tail_deviation: float
    tail_exponent: float
    core_lambda: float
    core_quartic: float
    c_tilde_rel: float
    x_cr_observed: float
    ode_residual: float
    energy_identity: float


@dataclass(frozen=True)
class PhiSolution(LimitSolution):
    """Solution of the heated quasi-elastic equation (see :func:`solve_phi`).

    Attributes
    ----------
    distribution : VelocityDistribution
        :math:`\\phi` on its grid (``method="phi"``), with moments and interpolation.
    C, lam, x2, x4, a2, x_cr : float
        :math:`C`, :math:`\\lambda = \\int|x|\\phi`, :math:`\\langle x^2\\rangle`,
        :math:`\\langle x^4\\rangle`, the kurtosis
        :math:`a_2 = \\langle x^4\\rangle/(3\\langle x^2\\rangle^2) - 1`, :math:`3\\lambda`.
    errors : dict of str to float
        Estimated error of each constant (NaN if not estimated): 16/15 of the change
        on halving the spacing (Richardson, order 4) plus the change on enlarging the
        domain by a quarter.
    info : RunInfo
        Newton convergence; ``info.extra["error_parts"]`` splits the errors.
    """

    distribution: VelocityDistribution
    C: float
    lam: float
    x2: float
    x4: float
    a2: float
    x_cr: float
    errors: Mapping[str, float] = field(default_factory=dict)
    info: RunInfo = field(default_factory=RunInfo)

    names = PHI_CONSTANTS

    @property
    def x(self) -> NDArray[np.float64]:
        """Grid nodes."""
        return self.distribution.v

    def asymptotics(self) -> PhiAsymptotics:
        """Check the tail, the Gaussian core, the crossover and the ODE (claim C5)."""
        x, phi = self.x, self.values
        lnphi = np.log(phi)
        h = float(x[1] - x[0])
        lnc = np.log(self.C)
        top = min(float(x[-1]) - 0.5, 6.5)
        tail = (x >= 4.0) & (x <= top)
        exact = lnc - x**3 / 6 - self.x2 * x / 2
        i_top = int(np.nonzero(tail)[0][-1])
        dev = lnphi - (lnc - x**3 / 6)
        slope = np.gradient(np.log(lnc - lnphi[tail]), np.log(x[tail]))[-1]
        core = np.abs(x) <= 0.5
        _, a4, a2c, _ = np.polyfit(x[core] ** 2, lnphi[core], 3)
        wphi = simpson_weights(x) * phi
        c_tilde = self.C * np.exp(-float(np.sum(wphi * np.abs(x) ** 3)) / 6)
        n_eff = self.distribution.effective_exponent

        def n_minus(c: float) -> float:
            return float(n_eff(np.array([c]))[0]) - 2.5

        s = np.sqrt(self.x2)
        x_obs = s * brentq(n_minus, 0.5 / s, 5.0 / s, xtol=1e-12)
        d4 = fourth_derivative_extrapolated(lnphi, h, max(1, int(round(0.02 / h))))
        inner = np.abs(x) <= 3.0
        energy = float(np.sum(wphi * abs_power_convolution(x, wphi, 3)))
        return PhiAsymptotics(
            tail_window=(4.0, top),
            tail_linear_term=float(dev[i_top]),
            tail_deviation=float(np.max(np.abs(lnphi[tail] - exact[tail]))),
            tail_exponent=float(slope),
            core_lambda=float(-2 * a2c),
            core_quartic=float(a4),
            c_tilde_rel=float(abs(c_tilde / phi[x.size // 2] - 1)),
            x_cr_observed=float(x_obs),
            ode_residual=float(np.nanmax(np.abs(d4[inner] + 2 * phi[inner])) / phi.max()),
            energy_identity=energy,
        )


def phi_grid(cutoff: float, n_v: int) -> NDArray[np.float64]:
    """Symmetric uniform grid on ``[-cutoff, cutoff]`` with ``n_v = 4k + 1`` nodes.

    ``n_v = 4k + 1`` puts :math:`x = 0` on a Simpson panel boundary, so that
    :math:`\\int |x|\\phi` (kink at 0) keeps fourth order.

    Parameters
    ----------
    cutoff : float
        Half-width of the grid.
    n_v : int
        Number of nodes, ``4k + 1``.

    Returns
    -------
    ndarray, shape (n_v,)
    """
    cutoff = check_positive("cutoff", cutoff)
    n_v = check_int("n_v", n_v, minimum=9)
    if n_v % 4 != 1:
        raise ValueError(f"n_v={n_v} is not allowed; n_v must be 4k + 1 (e.g. "
                         f"{4 * (n_v // 4) + 1}) so that x = 0 is a Simpson panel boundary")
    return np.linspace(-cutoff, cutoff, n_v)


def _solve_phi_on(x: NDArray[np.float64], u0: NDArray[np.float64], tol: float,
                  max_iter: int) -> tuple[NDArray[np.float64], float, RunInfo]:
    """Newton for :math:`\\ln\\phi` on a symmetric grid; unknowns on ``x >= 0`` only.

    Restricting to even functions removes the translation mode of the infinite-line
    equation (any shift of a solution solves it), which makes the Jacobian singular.
    """
    w = simpson_weights(x)
    mid = x.size // 2

    def full(half: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([half[:0:-1], half])

    def evaluate(uh: NDArray[np.float64]) -> Evaluation:
        phi = np.exp(full(uh))
        ln_t = log_normalise(-abs_power_convolution(x, w * phi, 3) / 6.0, w)
        t = np.exp(ln_t)

        def jvp(d: NDArray[np.float64]) -> NDArray[np.float64]:
            du = abs_power_convolution(x, w * phi * full(d), 3) / 6.0
            return d + du[mid:] - np.sum(w * t * du)

        return uh - ln_t[mid:], jvp

    start = time.perf_counter()
    out = newton_krylov(u0[mid:], evaluate, tol=tol, max_iter=max_iter, name="solve_phi")
    u = full(out.x)
    ln_c = float(np.mean(u + abs_power_convolution(x, w * np.exp(u), 3) / 6.0))
    return u, ln_c, run_info(out, start=start)


def _phi_constants(x: NDArray[np.float64], phi: NDArray[np.float64], ln_c: float) -> dict:
    w = simpson_weights(x)
    lam = float(np.sum(w * np.abs(x) * phi))
    x2, x4 = float(np.sum(w * x**2 * phi)), float(np.sum(w * x**4 * phi))
    return {"C": float(np.exp(ln_c)), "lam": lam, "x2": x2, "x4": x4,
            "a2": x4 / (3 * x2**2) - 1.0, "x_cr": 3 * lam}


def solve_phi(
    *,
    cutoff: float = 7.0,
    n_v: int = 1401,
    tol: float = 1e-12,
    max_iter: int = 50,
    estimate_errors: bool = True,
) -> PhiSolution:
    """Solve :math:`\\phi(x) = C\\exp(-\\frac16\\int|y-x|^3\\phi(y)dy)`, :math:`\\int\\phi = 1`.

    Parameters
    ----------
    cutoff : float
        Half-width :math:`L` of the grid :math:`[-L, L]` (:math:`\\phi(7) \\approx 10^{-26}`).
    n_v : int
        Number of nodes, ``4k + 1``.
    tol : float
        Newton stops when :math:`\\max_j|\\ln\\phi_j - \\ln\\mathcal T[\\phi]_j| <` ``tol``.
    max_iter : int
        Newton iterations allowed.
    estimate_errors : bool
        Also solve with half the spacing and with a domain larger by a quarter; the
        changes estimate the error of every constant.

    Returns
    -------
    PhiSolution

    Notes
    -----
    With Simpson weights :math:`w_j`, :math:`U_i = \\frac16\\sum_j w_j|x_i-x_j|^3\\phi_j`
    is an O(N) cumulative-moment sum (:func:`~kinetic_fem.operators.grid.abs_power_convolution`)
    and :math:`\\mathcal T[\\phi]_i = e^{-U_i}/\\sum_j w_j e^{-U_j}`.  Newton-GMRES
    on :math:`u = \\ln\\phi` over even functions converges quadratically from a
    Gaussian in five iterations.  The constants converge as :math:`h^4` (Simpson);
    the domain error is :math:`O(e^{-L^3/6})`.

    Examples
    --------
    >>> sol = solve_phi(n_v=701, estimate_errors=False)
    >>> round(sol.lam, 6), round(sol.x_cr, 3)
    (0.785475, 2.356)
    """
    tol, max_iter = check_solver_options(tol, max_iter)
    x = phi_grid(cutoff, n_v)
    if not isinstance(estimate_errors, bool):
        raise TypeError(f"estimate_errors must be a bool, got {estimate_errors!r}")

    def run(grid: NDArray[np.float64]) -> tuple[NDArray[np.float64], dict, RunInfo]:
        u, ln_c, info = _solve_phi_on(grid, -grid**2 / 2 - 0.5 * np.log(2 * np.pi), tol, max_iter)
        return u, _phi_constants(grid, np.exp(u), ln_c), info

    def as_dist(grid: NDArray[np.float64], u: NDArray[np.float64], **kw) -> VelocityDistribution:
        return VelocityDistribution.from_values(grid, np.exp(u), weights=simpson_weights(grid),
                                                normalize=False, **kw)

    u, consts, info = run(x)
    errors = {k: float("nan") for k in consts}
    extra: dict = {"cutoff": float(cutoff), "n_v": int(n_v), "tol": tol}
    variants = []
    if estimate_errors:
        half = (n_v - 1) // 2
        grow = 2 * max(1, round(half / 8))  # even: keeps n_v = 4k + 1
        for grid in (phi_grid(cutoff, 2 * n_v - 1),
                     phi_grid(cutoff * (half + grow) / half, n_v + 2 * grow)):
            variants.append((grid, *run(grid)[:2]))
        errors, parts = combine_errors(consts, variants[0][2], variants[1][2])
        extra["error_parts"] = parts
    info = RunInfo(converged=info.converged, iterations=info.iterations,
                   residual=info.residual, wall_time=info.wall_time, message=info.message,
                   extra=extra)
    dist = as_dist(x, u, method="phi", params={"limit": "heated, eps -> 0", "variable": "x"},
                   info=info)
    if variants:  # dist.error: T, a2, f of phi by the same two changes
        dist = with_estimate(dist, refinement_estimate(
            dist, *(as_dist(grid, ug) for grid, ug, _ in variants)))
    logger.info("solve_phi: lambda = %.12f, C = %.12f (%s)", consts["lam"], consts["C"],
                info.message)
    return PhiSolution(distribution=dist, errors=errors, info=info, **consts)
