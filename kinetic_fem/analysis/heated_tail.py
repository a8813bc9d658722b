"""The far tail of the heated steady state in log variables, beyond the reach of double precision.

Near the elastic limit the peak of the effective exponent lies very deep in the tail:
:math:`-\\ln(P/P_0) \\approx x^{*3}/6` with :math:`x^* \\approx 1.8\\,\\varepsilon^{-1/5}`, i.e.
:math:`P/P_0 \\sim 10^{-104}` at :math:`\\varepsilon = 10^{-4}` and :math:`10^{-1700}` at
:math:`10^{-6}`.  The FEM weak form evaluates :math:`P = e^{u_h}` and underflows below
:math:`e^{-708}`.  In the tail the equation is linear in :math:`P` given the bulk, and
divided by :math:`P(v)` it involves only differences of :math:`u = \\ln P` (``n = D = 1``):

.. math::

    u'' + u'^2 + \\int dy\\, |v - y| P(y)
    \\left[\\frac{e^{u(v + \\delta (v - y)) - u(v)}}{b^2} - 1\\right] = 0,
    \\qquad b = \\frac{1 + \\alpha}2,\\ \\delta = \\frac{1 - \\alpha}{1 + \\alpha},

the strong form of :math:`P'' + Q[P] = 0` (gain from the pre-collision velocity
:math:`v + \\delta(v - y)`, loss at the rate :math:`\\int|v-y|P(y)dy`).  Pairs with both
velocities beyond the matching point :math:`v_m` are left out; their relative weight is
:math:`P(v_m)/P(0)` (``match_log = -30``: :math:`10^{-13}`).

:func:`solve_tail` takes the bulk :math:`P(y)`, :math:`|y| \\le v_m`, from a FEM state
(its quadrature points and weights), fixes :math:`u(v_m)` to the FEM value, and solves
the equation on a uniform grid :math:`v_m \\le v \\le V` by Newton's method (fourth-order
central differences, quintic Lagrange interpolation of :math:`u` at the shifted
points, sparse Jacobian).  The decaying solution is selected by the grid's end: the
growing one falls off backwards like :math:`\\exp(-2\\int|u'|)`, so the end condition
(zero third difference) does not reach the range of the fits (checked by moving
:math:`V`).  The FEM slope :math:`u'(v_m)` is not imposed; its agreement with the tail
solution is a check (``TailSolution.slope_mismatch``).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from .exponent import ExponentPeak
from .peak_study import PeakSweep

__all__ = ["TailSolution", "solve_tail", "tail_peak", "MATCH_LOG", "tail_sweep",
           "quasi_elastic_peak", "TAIL_SPACINGS"]

logger = logging.getLogger(__name__)

MATCH_LOG = -30.0
"""Default matching depth: :math:`\\ln(P(v_m)/P(0))`."""

_STENCIL = 6  # quintic Lagrange interpolation


@dataclass(frozen=True)
class TailSolution:
    """:math:`u = \\ln P` of the heated state on the tail grid (``n = D = 1``).

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    v : ndarray
        Tail grid, ``v[0]`` the matching point.
    u : ndarray
        :math:`\\ln P` on the grid.
    slope : ndarray
        :math:`u'` on the grid (fourth-order differences, third order at the ends).
    u0 : float
        :math:`\\ln P(0)` of the bulk.
    temperature : float
        Temperature of the bulk.
    slope_mismatch : float
        :math:`|u'_{tail}(v_m) / u'_{FEM}(v_m) - 1|`: the matching check.
    iterations : int
        Newton iterations.
    residual : float
        Largest Newton update at the end.
    """

    alpha: float
    v: NDArray[np.float64]
    u: NDArray[np.float64]
    slope: NDArray[np.float64]
    u0: float
    temperature: float
    slope_mismatch: float
    iterations: int
    residual: float

    @property
    def c(self) -> NDArray[np.float64]:
        """The grid in thermal velocities."""
        return self.v / math.sqrt(self.temperature)

    def effective_exponent(self) -> NDArray[np.float64]:
        """:math:`n = v u' / (u - u_0)` on the grid."""
        return self.v * self.slope / (self.u - self.u0)


def _lagrange_weights(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Weights of the 6-point Lagrange rule at offset ``t`` (nodes 0..5, unit spacing)."""
    w = np.ones((t.size, _STENCIL))
    for k in range(_STENCIL):
        for m in range(_STENCIL):
            if m != k:
                w[:, k] *= (t - m) / (k - m)
    return w


def _derivative_matrices(m: int, h: float) -> tuple[scipy.sparse.csr_matrix,
                                                     scipy.sparse.csr_matrix]:
    """First and second derivative on ``m`` uniform nodes: 5-point central stencils,
    6-point one-sided ones at the two nodes next to each end."""
    d1 = scipy.sparse.lil_matrix((m, m))
    d2 = scipy.sparse.lil_matrix((m, m))
    c1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / (12.0 * h)
    c2 = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / (12.0 * h * h)
    for j in range(2, m - 2):
        d1[j, j - 2:j + 3] = c1
        d2[j, j - 2:j + 3] = c2
    # one-sided, exact for quintics
    for j, base in ((0, 0), (1, 0), (m - 2, m - 6), (m - 1, m - 6)):
        nodes = np.arange(6) + base
        t = float(j - base)
        vand = np.vander(nodes - base - t, 6, increasing=True).T  # rows: powers
        e1 = np.zeros(6)
        e1[1] = 1.0
        e2 = np.zeros(6)
        e2[2] = 2.0
        d1[j, nodes] = np.linalg.solve(vand, e1) / h
        d2[j, nodes] = np.linalg.solve(vand, e2) / h**2
    return d1.tocsr(), d2.tocsr()


def solve_tail(state, *, extent: float = 2.0, spacing: float = 0.05,
               match_log: float = MATCH_LOG, tol: float = 1e-12,
               max_iter: int = 40) -> TailSolution:
    """Solve the tail equation from the matching point to ``extent`` times the peak guess.

    Parameters
    ----------
    state : kinetic_fem.solvers.fem.SteadyState
        A converged FEM heated state of the paper's model (``n = D = 1``).
    extent : float
        End of the grid in units of the quasi-elastic peak estimate
        :math:`x^* = (10\\langle x^2\\rangle/(9\\varepsilon/16))^{1/5}` (at least 1.5 times
        the matching point).
    spacing : float
        Grid spacing in thermal velocities.
    match_log : float
        :math:`\\ln(P(v_m)/P(0))` at the matching point (negative).
    tol : float
        Stop when the largest Newton update of :math:`u` is below ``tol`` times
        :math:`\\max|u - u_0|` (relative: the deepest values are large).
    max_iter : int
        Newton iterations allowed.

    Returns
    -------
    TailSolution

    Raises
    ------
    ValueError
        For a bad option or a state whose tail does not reach ``match_log``.
    RuntimeError
        If Newton's method does not converge.
    """
    if not match_log < 0:
        raise ValueError(f"match_log must be negative, got {match_log!r}")
    if not (spacing > 0 and extent > 0):
        raise ValueError("spacing and extent must be positive")
    disc, u_fem = state.disc, state.u
    alpha = float(disc.alpha)
    eps = 1.0 - alpha
    dist = disc.distribution(u_fem)
    temperature = float(dist.temperature)
    scale = math.sqrt(temperature)
    yq, wq, _ = disc.points
    lnp_q = np.log(disc.values(u_fem))
    u0 = float(np.log(disc.evaluate(u_fem, np.array([0.0])))[0])
    # matching point: the first v > 0 with ln(P/P0) = match_log
    grid = np.linspace(0.0, float(disc.vertices[-1]), 20001)
    lnp = np.log(disc.evaluate(u_fem, grid)) - u0
    deep = np.flatnonzero(lnp <= match_log)
    if deep.size == 0:
        raise ValueError(f"the FEM tail does not reach ln(P/P0) = {match_log}; "
                         "use a larger cutoff or a smaller |match_log|")
    v_m = float(grid[deep[0]])
    keep = np.abs(yq) <= v_m
    y, wp = yq[keep], wq[keep] * np.exp(lnp_q[keep])
    x2 = 0.936129168  # <x^2> of phi (kinetic_fem.scaling.solve_phi)
    x_star = (16.0 * 10.0 * x2 / (9.0 * eps)) ** 0.2
    v_end = max(extent * x_star * eps ** (-1.0 / 3.0), 1.5 * v_m)
    h = spacing * scale
    m = int(math.ceil((v_end - v_m) / h)) + 1
    v = np.asarray(v_m + h * np.arange(m), dtype=np.float64)
    u_m = float(np.log(disc.evaluate(u_fem, np.array([v_m])))[0])
    probe = np.log(disc.evaluate(u_fem, np.array([v_m - 1e-3 * h, v_m])))
    fem_slope = float(probe[1] - probe[0]) / (1e-3 * h)
    b = 0.5 * (1.0 + alpha)
    delta = (1.0 - alpha) / (1.0 + alpha)
    log_b2 = 2.0 * math.log(b)
    d1, d2 = _derivative_matrices(m, h)
    # start: the FEM slope continued as a cubic in v
    u = u_m + fem_slope * (v**3 - v_m**3) / (3.0 * v_m**2)

    def system(u: NDArray) -> tuple[NDArray, scipy.sparse.csr_matrix]:
        g = d1 @ u
        res = d2 @ u + g * g
        rows, cols, vals = [], [], []
        diag = np.zeros(m)
        chunk = max(1, 400000 // max(1, y.size))
        for j0 in range(1, m, chunk):
            j = np.arange(j0, min(m, j0 + chunk))
            target = v[j, None] + delta * (v[j, None] - y[None, :])  # (J, Q)
            pos = (target - v_m) / h
            base = np.clip(np.floor(pos).astype(np.int64) - 2, 0, m - _STENCIL)
            lw = _lagrange_weights((pos - base).ravel()).reshape(*pos.shape, _STENCIL)
            idx = base[..., None] + np.arange(_STENCIL)
            u_shift = np.einsum("jqk,jqk->jq", lw, u[idx])
            kern = np.abs(v[j, None] - y[None, :]) * wp[None, :]
            arg = u_shift - u[j, None] - log_b2
            res[j] += np.sum(kern * np.expm1(arg), axis=1)
            ge = kern * np.exp(arg)  # d/du of the gain bracket
            diag[j] -= ge.sum(axis=1)
            contrib = ge[..., None] * lw
            rows.append(np.broadcast_to(j[:, None, None], idx.shape).ravel())
            cols.append(idx.ravel())
            vals.append(contrib.ravel())
        jac = scipy.sparse.coo_matrix((np.concatenate(vals), (np.concatenate(rows),
                                       np.concatenate(cols))), shape=(m, m)).tocsr()
        jac = jac + d2 + scipy.sparse.diags(2.0 * g) @ d1 + scipy.sparse.diags(diag)
        # Dirichlet row at the matching point; zero third difference at the end
        res[0] = u[0] - u_m
        third = np.zeros(m)
        third[-4:] = [-1.0, 3.0, -3.0, 1.0]
        res[-1] = float(third @ u)
        jac = jac.tolil()
        jac[0, :] = 0.0
        jac[0, 0] = 1.0
        jac[m - 1, :] = third
        return res, jac.tocsr()

    step = math.inf
    it = 0
    for it in range(1, max_iter + 1):
        res, jac = system(u)
        du = scipy.sparse.linalg.spsolve(jac.tocsc(), -res)
        step = float(np.abs(du).max())
        u = u + du
        logger.debug("tail newton %d: max|du| = %.2e", it, step)
        if step < tol * max(1.0, float(np.abs(u - u0).max())):
            break
    else:
        raise RuntimeError(f"tail Newton did not converge in {max_iter} iterations "
                           f"(alpha={alpha}, last update {step:.1e}); refine the spacing")
    slope = np.asarray(d1 @ u, dtype=np.float64)
    return TailSolution(alpha, v, np.asarray(u, dtype=np.float64), slope, u0, temperature,
                        abs(slope[0] / fem_slope - 1.0), it, step)


def tail_peak(tail: TailSolution) -> ExponentPeak:
    """Maximum of the effective exponent on the tail grid (cubic spline of n on the grid).

    ``interior`` is False when the maximum is at either end of the grid.

    Parameters
    ----------
    tail : TailSolution
        A solved tail.

    Returns
    -------
    ExponentPeak
    """
    n = tail.effective_exponent()
    i = int(np.argmax(n))
    eps = 1.0 - tail.alpha
    interior = 2 < i < n.size - 3
    if interior:
        lo, hi = max(0, i - 8), min(n.size, i + 9)
        spline = CubicSpline(tail.v[lo:hi], n[lo:hi])
        fine = np.linspace(tail.v[i - 1], tail.v[i + 1], 2001)
        k = int(np.argmax(spline(fine)))
        v_star, n_star = float(fine[k]), float(spline(fine[k]))
    else:
        v_star, n_star = float(tail.v[i]), float(n[i])
    c_star = v_star / math.sqrt(tail.temperature)
    return ExponentPeak(eps, c_star, v_star, v_star * eps ** (1.0 / 3.0), n_star, interior)

TAIL_SPACINGS = (0.1, 0.05)
"""Tail-grid spacings (thermal velocities) of :func:`tail_sweep`: base and refined."""


def tail_sweep(eps_values: tuple[float, ...], *, bulk_refinement: float = math.sqrt(2.0),
               spacings: tuple[float, float] = TAIL_SPACINGS, depth_check: bool = True,
               x_tol: float = 1e-3, n_tol: float = 1e-3, bulk=None, log=None) -> PeakSweep:
    """Peaks of n(c) from :func:`kinetic_fem.analysis.heated_tail.solve_tail` at each eps.

    Per eps: the FEM bulk at its default spacing with the tail at ``spacings[0]``
    (``coarse``); the bulk at the default spacing over ``bulk_refinement`` with the
    tail at ``spacings[1]`` (``peaks``, reported); and, with ``depth_check``, the
    coarse bulk matched deeper (``match_log = -40`` instead of -30) with a grid
    reaching further (``extent`` 2.5 instead of 2; ``other_cutoff``).  Converged where
    every peak is interior and x* moved by less than ``x_tol`` (relative) and n* by
    less than ``n_tol`` times :math:`3 - n^*` (relative to the quantity fitted: an absolute
    tolerance would loosen as :math:`3 - n^* \\to 0`).  Valid for eps <= 1e-3: at
    larger eps the peak lies above the matching depth (use
    :func:`~kinetic_fem.analysis.peak_study.peak_sweep` with ``method="fem"``).

    Parameters
    ----------
    eps_values : tuple of float
        Inelasticities.
    bulk_refinement : float
        Factor by which the FEM spacing is refined for the reported peak.
    spacings : tuple of float
        Tail-grid spacings (coarse, fine) in thermal velocities.
    depth_check : bool
        Also solve with the deeper matching point and longer grid.
    x_tol, n_tol : float
        Tolerances of the convergence checks (x* relative, n* relative to 3 - n*).
    bulk : callable, optional
        ``bulk(alpha, spacing)`` returning the FEM
        :class:`~kinetic_fem.solvers.fem.SteadyState` (default
        ``fem.steady_state(alpha, spacing=spacing)``; pass a cached one to share solves).
    log : callable, optional
        ``log(str)`` called with one line per solve.

    Returns
    -------
    PeakSweep
        ``method="tail"``.
    """
    from ..solvers.fem import heated as fem
    from ..solvers.fem.defaults import default_spacing

    eps_values = tuple(sorted(eps_values, reverse=True))
    peaks, coarse, other, converged = [], [], [], []
    if bulk is None:
        def bulk(alpha: float, spacing: float):
            return fem.steady_state(alpha, spacing=spacing)

    def run(state, label: str, **kwargs) -> ExponentPeak:
        tail = solve_tail(state, **kwargs)
        p = tail_peak(tail)
        if log is not None:
            log(f"eps={p.eps:g} {label}: grid {tail.v.size} nodes to c={tail.c[-1]:.1f}, "
                f"slope mismatch {tail.slope_mismatch:.1e}: c*={p.c:.5f} x*={p.x:.5f} "
                f"n*={p.n:.6f}" + ("" if p.interior else " (at the end of the grid)"))
        return p

    for eps in eps_values:
        alpha = 1.0 - eps
        h0 = default_spacing(alpha)
        base = bulk(alpha, h0)
        fine = bulk(alpha, h0 / bulk_refinement)
        pc = run(base, f"bulk h={h0:.3g}, tail h={spacings[0]:g}", spacing=spacings[0])
        pf = run(fine, f"bulk h={h0 / bulk_refinement:.3g}, tail h={spacings[1]:g}",
                 spacing=spacings[1])
        checks = [pc]
        if depth_check:
            other.append(run(base, "deeper match, longer grid", spacing=spacings[0],
                             match_log=-40.0, extent=2.5))
            checks.append(other[-1])
        coarse.append(pc)
        peaks.append(pf)
        converged.append(all(p.interior for p in (pf, *checks))
                         and all(abs(q.x / pf.x - 1) < x_tol
                                 and abs(q.n - pf.n) < n_tol * (3.0 - pf.n) for q in checks))
    return PeakSweep(tuple(peaks), tuple(coarse), tuple(converged), tuple(other), "tail",
                     x_tol, n_tol)


def quasi_elastic_peak(eps: float, *, x2: float | None = None,
                       x3: float | None = None) -> tuple[float, float]:
    """Peak of the two-term expansion :math:`n(x) = n_\\phi(x) - \\tfrac3{16}\\varepsilon x^3`.

    Beyond the bulk of :math:`\\phi`, :math:`-\\ln(\\phi(x)/\\phi(0)) = (x^3 + 3\\langle x^2
    \\rangle x - \\langle|x|^3\\rangle)/6` up to exponentially small terms, so
    :math:`n_\\phi = 3(x^3 + \\langle x^2\\rangle x)/(x^3 + 3\\langle x^2\\rangle x -
    \\langle|x|^3\\rangle) \\approx 3 - 6\\langle x^2\\rangle/x^2`, rising toward 3.  The
    first finite-eps term of the tail equation (the second-order term of the gain's
    shift, relative size :math:`\\varepsilon x^3/8`, the onset of the crossover to the
    :math:`|v|^{3/2}` tail at :math:`x \\sim \\varepsilon^{-1/3}`) lowers :math:`n` by
    :math:`\\tfrac3{16}\\varepsilon x^3`.  The balance gives
    :math:`x^* \\approx (64\\langle x^2\\rangle/(3\\varepsilon))^{1/5}`, i.e.
    :math:`v^* \\propto \\varepsilon^{-8/15}` and :math:`3 - n^* \\propto \\varepsilon^{2/5}`.

    Parameters
    ----------
    eps : float
        Inelasticity ``1 - alpha``.
    x2, x3 : float, optional
        :math:`\\langle x^2\\rangle` and :math:`\\langle|x|^3\\rangle` of :math:`\\phi`
        (default: from :func:`kinetic_fem.solvers.scaling.solve_phi`).

    Returns
    -------
    tuple of float
        ``(x*, n*)``.
    """
    if not 0 < eps < 1:
        raise ValueError(f"eps must be in (0, 1), got {eps!r}")
    if x2 is None or x3 is None:
        from ..operators.grid import simpson_weights
        from ..solvers.scaling import solve_phi

        phi = solve_phi(estimate_errors=False)
        x2 = phi.x2 if x2 is None else x2
        d = phi.distribution
        x3 = float(np.sum(simpson_weights(d.v) * np.abs(d.v) ** 3 * d.values)) \
            if x3 is None else x3
    # the tail form of n_phi holds beyond the bulk of phi (x >= 4: phi < 1e-5)
    x = np.exp(np.linspace(math.log(4.0), math.log(50.0 * eps ** -0.2), 200001))
    n = 3.0 * (x**3 + x2 * x) / (x**3 + 3.0 * x2 * x - x3) - 3.0 / 16.0 * eps * x**3
    i = int(np.argmax(n))
    return float(x[i]), float(n[i])

