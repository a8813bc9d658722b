"""Studies of the heated steady state that several figures, examples and benchmarks share.

* :func:`solve_steady`: the paper's finite-difference scheme solved by Newton's method
  (``steady="newton"``, cubic interpolation of the gain-term argument) with a cut-off
  beyond the default, so the Dirichlet condition is negligible over the tail fits;
* :func:`fem_steady`: the FEM (P2, Newton) state on an interval widened step by step
  beyond the default cut-off (the peak of the effective exponent lies at f ~ 1e-100 at
  eps = 1e-4), each step started from the last state continued by a cubic in ``|v|``;
* :func:`peak_sweep`: the peak :math:`(v^*, n^*)` of the effective exponent against
  eps with its resolution checks (:class:`PeakSweep`, claims C6 and C7, figure F6);
* :func:`combine_sweeps`: FEM peaks above eps = 1e-3 joined with those of
  :func:`kinetic_fem.analysis.heated_tail.tail_sweep` (the log-variable tail solver, for
  the peaks below the double-precision range at eps <= 1e-3);
* :func:`relaxation_run`: the paper's time marching from a Gaussian (claim C2).

Moved here from ``kinetic_fem.figures.heated`` (figures plot and register only).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..distribution import VelocityDistribution
from ..solve import solve_heated
from ..solvers.finite_difference import ConvergenceWarning, default_cutoff
from ..sonine import steady_temperature as sonine_temperature
from .exponent import ExponentPeak, exponent_peak, local_exponents, power_law_exponent

__all__ = ["solve_steady", "fem_steady", "peak_sweep", "PeakSweep", "relaxation_run",
           "fem_cutoff_factors", "FEM_PEAK_SPACINGS", "combine_sweeps"]


def solve_steady(alpha: float, *, spacing: float = 0.04, cutoff_factor: float = 1.3,
                 nest: float | None = None) -> VelocityDistribution:
    """FD steady state at ``n = D = 1`` with the cut-off ``cutoff_factor`` times the default.

    The default cut-off puts f near 1e-60; a factor 1.3 pushes it below 1e-89 for every
    alpha, so the Dirichlet condition there is negligible over the range of the fits.
    ``nest`` rounds the cut-off up to a multiple of that spacing, so that solutions at
    ``nest``, ``nest/2``, ... share nodes (Richardson extrapolation).

    Parameters
    ----------
    alpha : float
        Coefficient of restitution (hard rods, white noise, ``n = D = 1``).
    spacing : float
        Grid spacing (thermal velocities).
    cutoff_factor : float
        Cut-off in units of the FD default cut-off.
    nest : float, optional
        Round the cut-off up to a multiple of this spacing (nested grids).

    Returns
    -------
    VelocityDistribution

    Raises
    ------
    RuntimeError
        If Newton's method does not converge.
    """
    cutoff = cutoff_factor * default_cutoff(alpha)
    if nest is not None:
        cutoff = nest * math.ceil(cutoff / nest)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        dist = solve_heated(alpha, method="fd", steady="newton", spacing=spacing,
                            cutoff=cutoff, interpolation_order=3, richardson=0)
    if not dist.info.converged:
        raise RuntimeError(f"FD steady state not converged at alpha={alpha}: "
                           f"{dist.info.message}; reduce spacing")
    return dist


def fem_steady(alpha: float, *, spacing: float = 0.05, cutoff_factor: float = 1.5,
               widen_spacing: float = 0.07, widen_step: float = 1.08,
               intorder: int = 5) -> VelocityDistribution:
    """FEM (P2, Newton) steady state at ``n = D = 1`` with a cut-off beyond the default.

    The cut-off is ``cutoff_factor`` times :func:`kinetic_fem.solvers.fem.default_cutoff` (which
    puts f near 1e-33); at small eps the peak of n(c) lies deeper (f ~ 1e-100 at
    eps = 1e-4), so the interval is widened in steps of ``widen_step`` at spacing
    ``widen_spacing``, each Newton solve started from the previous one continued by a
    cubic in ``|v|`` (the C5 tail; a Gaussian continuation makes Newton diverge), and
    the last solve is at ``spacing`` with Gauss degree ``intorder``.  In the deep tail
    at small eps the gain and loss terms cancel to O(eps), so their quadrature error is
    amplified by 1/eps and n(c) becomes noisy (degree 5: below f ~ 1e-44 at h = 0.1,
    eps = 1e-3; near the peak at h = 0.05, eps = 1e-4); degree 9 at h = 0.05 is smooth
    and converged at the peak for eps down to 1e-4 (``benchmarks/effective_exponent_peak.py``).

    Parameters
    ----------
    alpha : float
        Coefficient of restitution (hard rods, white noise, ``n = D = 1``).
    spacing : float
        Element size of the final solve (thermal velocities).
    cutoff_factor : float
        Target cut-off in units of the FEM default (<= 1: the default interval).
    widen_spacing : float
        Element size of the widening steps.
    widen_step : float
        Growth factor of the interval per step.
    intorder : int
        Gauss degree of the final solve.

    Returns
    -------
    VelocityDistribution

    Raises
    ------
    ConvergenceError
        If a Newton solve fails.
    """
    from ..operators.grid import symmetric_grid, uniform_grid
    from ..solvers.fem import heated as fem

    scale = math.sqrt(sonine_temperature(alpha))
    target = cutoff_factor * fem.default_cutoff(alpha)
    if cutoff_factor <= 1.0:
        # the default interval (widened by steady_state itself if f(cut-off) > 1e-33)
        state = fem.steady_state(alpha, spacing=spacing, intorder=intorder)
        c_max = float(state.disc.vertices[-1]) / scale
        return state.disc.distribution(state.u, method="fem", info=state.info,
                                       params={"alpha": alpha, "density": 1.0,
                                               "diffusion": 1.0, "cutoff": c_max,
                                               "spacing": spacing})
    state = fem.steady_state(alpha, spacing=min(widen_spacing, 0.2), tol=1e-9)
    c_max = float(state.disc.vertices[-1]) / scale
    while True:
        last = c_max >= 0.999 * target
        c_max = c_max if last else min(target, widen_step * c_max)
        h = spacing if last else widen_spacing
        half = max(2, int(math.ceil(c_max / h)))
        disc = fem.FEMDiscretisation(alpha, symmetric_grid(uniform_grid(c_max * scale, half + 1)),
                                     intorder=intorder if last else 5)
        u, info = fem.newton_steady(disc, _cubic_continuation(state, disc.dof_locations),
                                    tol=1e-11 if last else 1e-9)
        if not info.converged:
            raise fem.ConvergenceError(f"FEM Newton failed at alpha={alpha}, cut-off "
                                       f"{c_max:.2f}: {info.message}; use a smaller "
                                       "cutoff_factor or widen_step")
        state = fem.SteadyState(disc, u, info)
        if last:
            return disc.distribution(u, method="fem", info=info,
                                     params={"alpha": alpha, "density": 1.0,
                                             "diffusion": 1.0, "cutoff": c_max,
                                             "spacing": spacing})


def _cubic_continuation(state, v: NDArray[np.float64]) -> NDArray[np.float64]:
    """ln P of ``state`` at ``v``, continued beyond 0.9 of its edge as a cubic in |v|."""
    v0 = 0.9 * float(state.disc.vertices[-1])
    l0, l1 = np.log(state.disc.evaluate(state.u, np.array([0.999 * v0, v0])))
    slope = (l1 - l0) / (0.001 * v0)
    a = np.abs(v)
    out = l1 + slope * (a**3 - v0**3) / (3.0 * v0**2)
    inside = np.flatnonzero(a <= v0)
    order = inside[np.argsort(a[inside])]
    out[order] = np.log(state.disc.evaluate(state.u, a[order]))
    return out


def relaxation_run(alpha: float, *, spacing: float = 0.2, initial_temperature: float = 0.5
                   ) -> VelocityDistribution:
    """Time marching (the paper's iteration) from a Gaussian at a fraction of T.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    spacing : float
        Grid spacing (thermal velocities), at most 0.25.
    initial_temperature : float
        Temperature of the Gaussian start, in units of the steady temperature estimate.

    Returns
    -------
    VelocityDistribution
        The final state; ``series`` holds ``time`` and ``temperature``.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_heated(alpha, method="fd", steady="march", spacing=spacing,
                            initial_temperature=initial_temperature, tol=1e-9, richardson=0)


@dataclass(frozen=True)
class PeakSweep:
    """Peaks of n(c) at each eps: best resolution, coarser spacing, (other cut-off).

    ``converged`` where the peak is interior and moved by less than ``x_tol``
    (relative, in x*) and ``n_tol`` (absolute, in n*) between the resolutions (FD:
    spacing h and 2h; FEM: spacing h and h_fine, and cut-offs a and b).

    Parameters
    ----------
    peaks : tuple of ExponentPeak
        Best-resolved peak at each eps (decreasing eps).
    coarse : tuple of ExponentPeak
        The peaks at the coarser spacing.
    converged : tuple of bool
        The resolution checks passed.
    other_cutoff : tuple of ExponentPeak
        FEM: the peaks with the second cut-off.
    method : str
        ``"fd"`` or ``"fem"``.
    x_tol, n_tol : float
        Tolerances of the checks (relative in x*; in n* absolute for ``"fd"`` and
        ``"fem"``, relative to 3 - n* for ``"tail"``).
    """

    peaks: tuple[ExponentPeak, ...]
    coarse: tuple[ExponentPeak, ...]
    converged: tuple[bool, ...]
    other_cutoff: tuple[ExponentPeak, ...] = ()
    method: str = "fd"
    x_tol: float = 0.02
    n_tol: float = math.inf

    def selected(self) -> list[ExponentPeak]:
        """The converged peaks."""
        return [p for p, ok in zip(self.peaks, self.converged, strict=True) if ok]

    def fits(self) -> tuple[float, float]:
        """Exponents of v* and 3 - n* against eps over the converged peaks."""
        sel = self.selected()
        if len(sel) < 2:
            return math.nan, math.nan
        eps = np.array([p.eps for p in sel])
        return (power_law_exponent(eps, np.array([p.v for p in sel])),
                power_law_exponent(eps, 3.0 - np.array([p.n for p in sel])))

    def local(self) -> list[tuple[float, float, float, float]]:
        """``(eps_1, eps_2, exponent of v*, exponent of 3 - n*)`` between successive
        converged peaks."""
        return local_exponents(self.selected())

    def errors(self) -> list[tuple[float, float]]:
        """Error bars of the converged peaks from the resolution checks.

        Returns
        -------
        list of tuple
            ``(relative error of v*, absolute error of n*)``: the largest change between
            the reported peak and its checks (coarser mesh, other cut-off or depth).
        """
        out = []
        for p, pc, ok, k in zip(self.peaks, self.coarse, self.converged,
                                range(len(self.peaks)), strict=True):
            if not ok:
                continue
            checks = [pc] + ([self.other_cutoff[k]] if self.other_cutoff else [])
            out.append((max(abs(q.v / p.v - 1) for q in checks),
                        max(abs(q.n - p.n) for q in checks)))
        return out

    def local_errors(self) -> list[tuple[float, float]]:
        """Error bars of :meth:`local`: the peaks' error bars carried through the
        two-point exponents (worst case, added).

        Returns
        -------
        list of tuple
            ``(error of the exponent of v*, error of the exponent of 3 - n*)``.
        """
        sel, err = self.selected(), self.errors()
        out = []
        for a, b, ea, eb in zip(sel[:-1], sel[1:], err[:-1], err[1:], strict=True):
            le = abs(math.log(b.eps / a.eps))
            out.append(((ea[0] + eb[0]) / le,
                        (ea[1] / (3.0 - a.n) + eb[1] / (3.0 - b.n)) / le))
        return out


FEM_PEAK_SPACINGS = (0.05, 0.035)
"""FEM spacings of the full peak sweep (thermal velocities), with Gauss degree 9."""


def fem_cutoff_factors(eps: float) -> tuple[float, float]:
    """Two cut-offs (times the FEM default) placing the peak of n(c) well inside.

    Parameters
    ----------
    eps : float
        Inelasticity ``1 - alpha``.

    Returns
    -------
    tuple of float
    """
    if eps >= 1e-2:
        return (1.0, 1.3)
    return (1.3, 1.5) if eps >= 1e-3 else (1.5, 1.7)


def peak_sweep(eps_values: tuple[float, ...], *, spacing: float, method: str = "fd",
               fine_spacing: float | None = None, x_tol: float | None = None,
               n_tol: float | None = None, widen_spacing: float = 0.07,
               cutoff_check: bool = True, intorder: int = 9, log=None) -> PeakSweep:
    """:func:`exponent_peak` of the steady state at each ``eps``.

    ``method="fd"``: :func:`solve_steady` at spacings ``2 spacing`` and ``spacing``,
    converged if x* moved by < 2 %.  ``method="fem"``: :func:`fem_steady` at
    (``spacing``, cut-off a), (``fine_spacing``, a) and (``spacing``, cut-off b) with
    the cut-offs of :func:`fem_cutoff_factors`; converged if the peak is interior and
    x* moved by < ``x_tol`` (default 1 %) and n* by < ``n_tol`` (default 1e-3) in
    both comparisons; the fine-spacing peak is reported.  ``widen_spacing``: see
    :func:`fem_steady`.  Peaks are returned in order of decreasing eps.
    ``cutoff_check=False`` skips the second cut-off (quick mode,
    where the peak lies at f > 1e-10, far inside the default cut-off).  ``intorder``:
    Gauss degree of the final solves (9: 5 points per element); in the deep tail at
    small eps the gain and loss terms cancel to O(eps), so their quadrature error is
    amplified by 1/eps (eps = 3e-4, h = 0.05: x* = 9.43 with degree 5, 9.01 with 9).

    Parameters
    ----------
    eps_values : tuple of float
        Inelasticities.
    spacing : float
        Spacing of the (coarser) solves.
    method : {"fd", "fem"}
        Solver.
    fine_spacing : float, optional
        FEM: spacing of the finer solve (default ``spacing / sqrt(2)``).
    x_tol, n_tol : float, optional
        Tolerances of the convergence checks.
    widen_spacing : float
        See :func:`fem_steady`.
    cutoff_check : bool
        FEM: also solve with the second cut-off.
    intorder : int
        FEM: Gauss degree of the final solves.
    log : callable, optional
        ``log(str)`` called with one line per solve.

    Returns
    -------
    PeakSweep

    Raises
    ------
    ValueError
        For another ``method``.
    """
    eps_values = tuple(sorted(eps_values, reverse=True))
    if method == "fd":
        coarse = tuple(exponent_peak(solve_steady(1.0 - e, spacing=2 * spacing))
                       for e in eps_values)
        fine = tuple(exponent_peak(solve_steady(1.0 - e, spacing=spacing)) for e in eps_values)
        tol = 0.02 if x_tol is None else x_tol
        ok = tuple(abs(f.x / c.x - 1) < tol for f, c in zip(fine, coarse, strict=True))
        return PeakSweep(fine, coarse, ok, x_tol=tol)
    if method != "fem":
        raise ValueError(f"method must be 'fd' or 'fem', got {method!r}")
    fine_spacing = spacing / math.sqrt(2.0) if fine_spacing is None else fine_spacing
    x_tol = 0.01 if x_tol is None else x_tol
    n_tol = 1e-3 if n_tol is None else n_tol
    coarse_peaks: list[ExponentPeak] = []
    fine_peaks: list[ExponentPeak] = []
    other: list[ExponentPeak] = []
    converged: list[bool] = []

    def peak(eps: float, h: float, factor: float) -> ExponentPeak:
        dist = fem_steady(1.0 - eps, spacing=h, cutoff_factor=factor,
                          widen_spacing=widen_spacing, intorder=intorder)
        # stay clear of the zero-flux boundary layer at the cut-off
        p = exponent_peak(dist, floor=1e-300, c_max=0.9 * float(dist.c.max()), drop=0.01)
        if log is not None:
            log(f"eps={eps:g} h={h:g} cut-off={dist.c.max():.2f} (x{factor}) "
                f"nodes={dist.v.size}: c*={p.c:.4f} x*={p.x:.4f} n*={p.n:.5f}"
                + ("" if p.interior else " (at the end of the range)"))
        return p

    for eps in eps_values:
        fa, fb = fem_cutoff_factors(eps)
        pc, pf = peak(eps, spacing, fa), peak(eps, fine_spacing, fa)
        checks = [pc]
        if cutoff_check:
            other.append(peak(eps, spacing, fb))
            checks.append(other[-1])
        coarse_peaks.append(pc)
        fine_peaks.append(pf)
        converged.append(all(p.interior for p in (pf, *checks))
                         and all(abs(q.x / pf.x - 1) < x_tol and abs(q.n - pf.n) < n_tol
                                 for q in checks))
    return PeakSweep(tuple(fine_peaks), tuple(coarse_peaks), tuple(converged), tuple(other),
                     "fem", x_tol, n_tol)


def combine_sweeps(*sweeps: PeakSweep) -> PeakSweep:
    """The converged peaks of several sweeps in one, a later sweep replacing an earlier
    one at the same eps (e.g. FEM above eps = 1e-3 and the tail solver at and below).

    Parameters
    ----------
    *sweeps : PeakSweep
        Sweeps in order of precedence (last wins).

    Returns
    -------
    PeakSweep
        ``method`` joins the methods with ``+``; tolerances are the largest ones.
    """
    chosen: dict[float, tuple[ExponentPeak, ExponentPeak, ExponentPeak]] = {}
    for sw in sweeps:
        others = sw.other_cutoff or sw.coarse
        for p, pc, po, ok in zip(sw.peaks, sw.coarse, others, sw.converged, strict=True):
            if ok:
                chosen[p.eps] = (p, pc, po)
    order = sorted(chosen, reverse=True)
    return PeakSweep(tuple(chosen[e][0] for e in order), tuple(chosen[e][1] for e in order),
                     tuple(True for _ in order), tuple(chosen[e][2] for e in order),
                     "+".join(sw.method for sw in sweeps),
                     max((sw.x_tol for sw in sweeps), default=0.0),
                     max((sw.n_tol for sw in sweeps), default=0.0))
