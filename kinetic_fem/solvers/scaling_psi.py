"""The free-cooling quasi-elastic equation for the hump shape :math:`\\psi(y)` (claim C12).

Derived from the Boltzmann equation in ``docs/user_guide/quasi_elastic.rst``:

.. math::

    \\psi' + \\langle y^2\\rangle_\\psi\\,\\psi
    + \\frac12 \\psi \\int dy'\\,\\psi(y')\\big(|y-y'|(y-y') - (y+y')^2\\big) = 0,
    \\qquad \\int \\psi = 1,\\quad \\langle y \\rangle_\\psi = 0,

whose integral is

.. math::

    \\ln\\psi(y) = \\ln C - c\\, y - K[\\psi](y), \\qquad
    K[\\psi](y) = \\frac16\\int dy'\\,\\psi(y')\\big(|y-y'|^3 - (y+y')^3\\big),

with :math:`c = \\langle y^2\\rangle_\\psi + \\langle y\\rangle_\\psi^2`.  Consequences
(the paper's printed versions differ by misprints, see the user guide):
left tail :math:`\\psi \\simeq C e^{y^3/3}`; right tail
:math:`\\psi \\simeq C e^{\\langle y^3\\rangle/3} e^{-\\langle y^2\\rangle y}`;
:math:`(\\ln\\psi)'''' = -2\\psi`.

Numerics.  Splitting the integral at :math:`y` makes the kernel polynomial on each
side,

.. math::

    K(y) = -y^2 S_1^<(y) - \\tfrac13 S_3^<(y) - \\tfrac13 y^3 S_0^>(y) - y S_2^>(y),

with :math:`S_k^{<,>}` the forward and backward running sums of
:func:`~kinetic_fem.operators.grid.partial_moments`: O(N) and free of the large cancellations
of :math:`|y-y'|^3` against :math:`(y+y')^3`.  The condition
:math:`\\langle y\\rangle = 0` is imposed directly with :math:`c` as an extra unknown:
imposing :math:`c = \\langle y^2\\rangle` instead only implies
:math:`\\langle y\\rangle^2 = 0`, a double root on which Newton's method converges
linearly.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from ..distribution import RunInfo, VelocityDistribution
from ..operators.grid import abs_power_convolution, partial_moments, simpson_weights
from .scaling_common import (
    Evaluation,
    LimitSolution,
    check_int,
    check_solver_options,
    combine_errors,
    first_derivative,
    fourth_derivative_extrapolated,
    line_fit,
    log_normalise,
    newton_krylov,
    refinement_estimate,
    with_estimate,
)

__all__ = ["solve_psi", "PsiSolution", "PsiAsymptotics", "psi_kernel", "psi_flux_kernel"]

PSI_CONSTANTS = ("C", "y2", "y3", "y_peak", "psi_peak")


def psi_kernel(y: NDArray[np.float64], wpsi: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`K_i = \\frac16\\sum_j (wpsi)_j (|y_i-y_j|^3 - (y_i+y_j)^3)` in O(N).

    Parameters
    ----------
    y : ndarray, shape (n,)
        Increasing nodes.
    wpsi : ndarray, shape (n,)
        Quadrature weights times :math:`\\psi` at the nodes.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> y = np.array([-1.0, 0.0, 2.0]); wpsi = np.array([0.5, 0.25, 0.25])
    >>> brute = ((np.abs(y[:, None] - y) ** 3 - (y[:, None] + y) ** 3) @ wpsi) / 6
    >>> bool(np.allclose(psi_kernel(y, wpsi), brute))
    True
    """
    lo, up = partial_moments(y, wpsi, 3)
    return -y**2 * lo[1] - lo[3] / 3 - y**3 * up[0] / 3 - y * up[2]


def psi_flux_kernel(y: NDArray[np.float64], wpsi: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`\\sum_j (wpsi)_j (|y_i-y_j|(y_i-y_j) - (y_i+y_j)^2) = 2K'(y_i)` in O(N).

    Parameters
    ----------
    y : ndarray, shape (n,)
        Increasing nodes.
    wpsi : ndarray, shape (n,)
        Quadrature weights times :math:`\\psi` at the nodes.

    Returns
    -------
    ndarray, shape (n,)
    """
    lo, up = partial_moments(y, wpsi, 2)
    return -4 * y * lo[1] - 2 * y**2 * up[0] - 2 * up[2]


@dataclass(frozen=True)
class PsiAsymptotics:
    """Numerical checks of the :math:`\\psi` equation and its tails (claim C12).

    Attributes
    ----------
    left_window, right_window : tuple of float
        Fit ranges of the tails.
    left_cubic : float
        Fitted :math:`b` of :math:`\\ln\\psi = a + b y^3` on the left (theory 1/3).
    left_log_prefactor : float
        Fitted :math:`a` (theory :math:`\\ln C`).
    right_slope : float
        Fitted slope of :math:`\\ln\\psi` on the right (theory :math:`-\\langle y^2\\rangle`;
        the paper prints :math:`-2\\langle y^2\\rangle`).
    right_log_prefactor : float
        Fitted intercept (theory :math:`\\ln C + \\langle y^3\\rangle/3`; the paper prints
        :math:`\\ln C - \\langle y^3\\rangle/3`).
    ode_residual : float
        :math:`\\max|(\\ln\\psi)'''' + 2\\psi| / \\max\\psi` on :math:`[-3, 6]`.
    ode_residual_paper : float
        The same for the paper's :math:`(\\ln\\psi)'''' = \\psi`.
    differential_residual : float
        :math:`\\max|\\psi' + \\langle y^2\\rangle\\psi + \\frac12\\psi K_1| / \\max|\\psi'|`,
        the paper's differential form (eq. psi) on the solution of the integral form.
    mean : float
        :math:`\\langle y\\rangle_\\psi` (zero).
    c_minus_y2 : float
        :math:`c - \\langle y^2\\rangle` (zero when :math:`\\langle y\\rangle = 0`).
    """

    left_window: tuple[float, float]
    right_window: tuple[float, float]
    left_cubic: float
    left_log_prefactor: float
    right_slope: float
    right_log_prefactor: float
    ode_residual: float
    ode_residual_paper: float
    differential_residual: float
    mean: float
    c_minus_y2: float


@dataclass(frozen=True)
class PsiSolution(LimitSolution):
    """Solution of the free-cooling quasi-elastic equation (see :func:`solve_psi`).

    Attributes
    ----------
    distribution : VelocityDistribution
        :math:`\\psi` on its grid (``method="psi"``), with moments and interpolation.
    C, y2, y3 : float
        :math:`C`, :math:`\\langle y^2\\rangle_\\psi`, :math:`\\langle y^3\\rangle_\\psi`.
    y_peak, psi_peak : float
        Position and height of the maximum of :math:`\\psi`.
    c : float
        The linear coefficient of the integral form (equals ``y2``).
    errors : dict of str to float
        Estimated error of each constant: 16/15 of the change on halving the spacing
        (Richardson, order 4) plus the change on moving both ends of the domain out
        by a quarter; NaN if not estimated.
    info : RunInfo
        Newton convergence; ``info.extra["error_parts"]`` splits the errors.
    """

    distribution: VelocityDistribution
    C: float
    y2: float
    y3: float
    y_peak: float
    psi_peak: float
    c: float
    errors: Mapping[str, float] = field(default_factory=dict)
    info: RunInfo = field(default_factory=RunInfo)

    names = PSI_CONSTANTS

    @property
    def y(self) -> NDArray[np.float64]:
        """Grid nodes."""
        return self.distribution.v

    def humps(self, x: ArrayLike, eps: float) -> NDArray[np.float64]:
        """Leading-order scaled cooling distribution :math:`\\Phi(x)` built from :math:`\\psi`.

        :math:`\\Phi(x) = \\frac{1}{2\\delta}[\\psi((x+1)/\\delta) + \\psi((1-x)/\\delta)]`,
        :math:`\\delta = \\epsilon^{1/3}`, :math:`x = n\\epsilon t v` (F9-F11).
        """
        d = float(eps) ** (1.0 / 3.0)
        x = np.asarray(x, dtype=float)
        return (self((x + 1) / d) + self((1 - x) / d)) / (2 * d)

    def asymptotics(self) -> PsiAsymptotics:
        """Fit both tails, and check the ODE and the differential form (claim C12)."""
        y, psi = self.y, self.values
        h = float(y[1] - y[0])
        lnpsi = np.log(psi)
        left = (y >= y[0] + 0.5) & (y <= -3.0)
        right_hi = min(30.0, float(y[-1]) - 2.0)
        right = (y >= 12.0) & (y <= right_hi)
        lc, la = line_fit(y[left] ** 3, lnpsi[left])
        rs, ra = line_fit(y[right], lnpsi[right])
        d4 = fourth_derivative_extrapolated(lnpsi, h, max(1, int(round(0.02 / h))))
        core = (y >= -3.0) & (y <= 6.0)
        k1 = psi_flux_kernel(y, simpson_weights(y) * psi)
        dpsi = first_derivative(psi, h)
        diff = dpsi + self.y2 * psi + 0.5 * psi * k1
        return PsiAsymptotics(
            left_window=(float(y[0] + 0.5), -3.0), right_window=(12.0, right_hi),
            left_cubic=lc, left_log_prefactor=la, right_slope=rs, right_log_prefactor=ra,
            ode_residual=float(np.nanmax(np.abs(d4[core] + 2 * psi[core])) / psi.max()),
            ode_residual_paper=float(np.nanmax(np.abs(d4[core] - psi[core])) / psi.max()),
            differential_residual=float(np.nanmax(np.abs(diff)) / np.nanmax(np.abs(dpsi))),
            mean=self.distribution.mean, c_minus_y2=self.c - self.y2,
        )


def psi_grid(domain: tuple[float, float], n_v: int) -> NDArray[np.float64]:
    """Uniform grid on ``domain = (lo, hi)``, ``lo < 0 < hi``, odd ``n_v``."""
    n_v = check_int("n_v", n_v, minimum=9)
    try:
        lo, hi = (float(b) for b in domain)
    except (TypeError, ValueError):
        raise TypeError(f"domain must be a pair of numbers (lo, hi), got {domain!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < 0.0 < hi):
        raise ValueError(f"domain={domain!r} is not allowed; need finite lo < 0 < hi")
    if n_v % 2 != 1:
        raise ValueError(f"n_v={n_v} is not allowed; n_v must be odd (Simpson's rule)")
    return np.linspace(lo, hi, n_v)


def _solve_psi_on(y: NDArray[np.float64], u0: NDArray[np.float64], c0: float, tol: float,
                  max_iter: int) -> tuple[NDArray[np.float64], float, float, RunInfo]:
    """Newton for :math:`(\\ln\\psi, c)`; residual :math:`(u - \\mathcal T, \\langle y\\rangle)`."""
    w = simpson_weights(y)
    n = y.size

    def evaluate(z: NDArray[np.float64]) -> Evaluation:
        u, c = z[:n], z[n]
        psi = np.exp(u)
        ln_t = log_normalise(-c * y - psi_kernel(y, w * psi), w)
        t = np.exp(ln_t)

        def jvp(d: NDArray[np.float64]) -> NDArray[np.float64]:
            dk = d[n] * y + psi_kernel(y, w * psi * d[:n])
            return np.concatenate([d[:n] + dk - np.sum(w * t * dk), [np.sum(w * y * psi * d[:n])]])

        return np.concatenate([u - ln_t, [np.sum(w * y * psi)]]), jvp

    start = time.perf_counter()
    out = newton_krylov(np.concatenate([u0, [c0]]), evaluate, tol=tol, max_iter=max_iter,
                        name="solve_psi")
    u, c = out.x[:n], float(out.x[n])
    ln_c = float(np.mean(u + c * y + psi_kernel(y, w * np.exp(u))))
    info = RunInfo(converged=out.converged, iterations=out.iterations, residual=out.residual,
                   wall_time=time.perf_counter() - start, message=out.message)
    return u, c, ln_c, info


def _peak(y: NDArray[np.float64], u: NDArray[np.float64], c: float,
          ln_c: float) -> tuple[float, float]:
    """Maximum of :math:`\\psi` from the equation itself, not from differences of data.

    :math:`(\\ln\\psi)' = -c - K_1/2` is known at the nodes to quadrature accuracy;
    its root is found on a local cubic spline, and the height is
    :math:`\\ln C - c y^* - K(y^*)` with :math:`K(y^*)` summed exactly at :math:`y^*`.
    """
    wpsi = simpson_weights(y) * np.exp(u)
    slope = -c - 0.5 * psi_flux_kernel(y, wpsi)
    i = int(np.argmax(u))
    sl = slice(max(i - 8, 0), min(i + 9, y.size))
    spline = CubicSpline(y[sl], slope[sl])
    y_peak = brentq(lambda s: float(spline(s)), y[i - 1], y[i + 1], xtol=1e-15)
    k = (abs_power_convolution(y, wpsi, 3, at=np.array([y_peak]))[0]
         - np.sum(wpsi * (y_peak + y) ** 3)) / 6.0
    return float(y_peak), float(np.exp(ln_c - c * y_peak - k))


def _psi_constants(y: NDArray[np.float64], u: NDArray[np.float64], c: float,
                   ln_c: float) -> dict:
    w, psi = simpson_weights(y), np.exp(u)
    y_peak, psi_peak = _peak(y, u, c, ln_c)
    return {"C": float(np.exp(ln_c)), "y2": float(np.sum(w * y**2 * psi)),
            "y3": float(np.sum(w * y**3 * psi)), "y_peak": y_peak, "psi_peak": psi_peak}


def solve_psi(
    *,
    domain: tuple[float, float] = (-6.0, 36.0),
    n_v: int = 4201,
    tol: float = 1e-12,
    max_iter: int = 60,
    estimate_errors: bool = True,
) -> PsiSolution:
    """Solve the free-cooling quasi-elastic equation for :math:`\\psi` (see module notes).

    Parameters
    ----------
    domain : (float, float)
        Grid ends ``(lo, hi)``, ``lo < 0 < hi``.  The domain is asymmetric like
        :math:`\\psi`: the left tail falls as :math:`e^{y^3/3}` (:math:`10^{-31}` at
        -6), the right one only as :math:`e^{-1.21 y}` (:math:`10^{-19}` at 36).
    n_v : int
        Number of nodes (odd).
    tol : float
        Newton stops when the max-norm of
        :math:`(\\ln\\psi - \\ln\\mathcal T[\\psi], \\langle y\\rangle)` is below ``tol``.
    max_iter : int
        Newton iterations allowed.
    estimate_errors : bool
        Also solve with half the spacing and with both ends moved out by a quarter.

    Returns
    -------
    PsiSolution

    Examples
    --------
    >>> sol = solve_psi(n_v=1051, estimate_errors=False)
    >>> round(sol.y2, 5), abs(sol.distribution.mean) < 1e-12
    (1.20971, True)
    """
    tol, max_iter = check_solver_options(tol, max_iter)
    y = psi_grid(domain, n_v)
    if not isinstance(estimate_errors, bool):
        raise TypeError(f"estimate_errors must be a bool, got {estimate_errors!r}")
    # start from the two tails joined at the origin: e^{y^3/3} and e^{-1.2 y}
    u, c, ln_c, info = _solve_psi_on(y, log_normalise(np.minimum(y**3 / 3, -1.2 * y),
                                                      simpson_weights(y)), 1.2, tol, max_iter)
    consts = _psi_constants(y, u, c, ln_c)
    errors = {k: float("nan") for k in consts}
    extra: dict = {"domain": [float(y[0]), float(y[-1])], "n_v": int(n_v), "tol": tol}
    shapes: list[VelocityDistribution] = []
    if estimate_errors:
        h = float(y[1] - y[0])
        grow_lo = max(1, round(abs(y[0]) / (4 * h)))
        grow_hi = max(1, round(y[-1] / (4 * h)))
        grow_hi += (grow_lo + grow_hi) % 2  # keep the node count odd
        variants = []
        for grid in (psi_grid((y[0], y[-1]), 2 * n_v - 1),
                     psi_grid((y[0] - grow_lo * h, y[-1] + grow_hi * h), n_v + grow_lo + grow_hi)):
            u0 = np.interp(grid, y, u, left=-1e3)
            beyond = grid > y[-1]
            u0[beyond] = u[-1] - c * (grid[beyond] - y[-1])  # the exponential right tail
            ug, cg, ln_cg, _ = _solve_psi_on(grid, log_normalise(u0, simpson_weights(grid)), c,
                                            tol, max_iter)
            variants.append(_psi_constants(grid, ug, cg, ln_cg))
            shapes.append(VelocityDistribution.from_values(
                grid, np.exp(ug), weights=simpson_weights(grid), normalize=False))
        errors, parts = combine_errors(consts, *variants)
        extra["error_parts"] = parts
    info = RunInfo(converged=info.converged, iterations=info.iterations,
                   residual=info.residual, wall_time=info.wall_time, message=info.message,
                   extra=extra)
    dist = VelocityDistribution.from_values(y, np.exp(u), weights=simpson_weights(y),
                                            method="psi", params={"limit": "cooling, eps -> 0",
                                                                  "variable": "y"},
                                            info=info, normalize=False)
    if shapes:  # dist.error: T, a2, f of psi by the same two changes
        dist = with_estimate(dist, refinement_estimate(dist, *shapes))
    return PsiSolution(distribution=dist, c=c, errors=errors, info=info, **consts)
