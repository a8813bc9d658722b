"""Reproduce items of the deterministic homogeneous cooling state (cooling ``"fd"``).

Registered on import:

* ``F9-HCS``: the HCS f(c) of the homogeneous Boltzmann equation for several alpha
  against the Gaussian (the deterministic counterpart of the DSMC curves of F7, F9);
  claims C9 (cooling rate zeta -> eps, i.e. T = (n eps t)^-2), C10 (the restitution
  above which f(c) has two humps, located by bisection on the sign of f''(0)) and
  C15 (first-order and order-8 Sonine a2 against the HCS).
* ``F11-HCS``: the humps of the Galerkin (FEM) HCS rescaled onto the psi equation (F10,
  F11) from eps = 1e-2 down to the smallest inelasticity the FEM continuation reaches:
  claims C11 (hump width ~ eps^nu, nu fitted) and C12 (distance to psi -> 0).

:func:`near_elastic_states` (FEM, hump meshes, one continuation in eps; cached) also
gives the lines that the DSMC items F9 and F11 of ``particles.figures`` draw beside
their histograms, and the FEM hump panel of ``F9-HCS`` (the paper's F9 at
eps = 1e-2, 1e-3, 1e-4 and further).  Quick mode: eps = 1e-2, 1e-3 at
:data:`QUICK_RESOLUTION` hump widths.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache

import numpy as np

from ..analysis.humps import psi_profile
from ..distribution import VelocityDistribution
from ..reproduce import ClaimRow, Context, register
from ..solvers.fd_cooling import HCSSolution, solve_hcs
from ..solvers.fem.cooling import HUMP_FRONTIER, HUMP_STEP_RESOLUTION
from ..solvers.fem.cooling_chain import hump_states
from ..solvers.scaling import solve_psi
from ..solvers.spectral import solve_sonine_cooling
from .plotting import save, subplots

FEM_EPS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
"""Inelasticities of the FEM hump panels (full mode): those the continuation reaches
(down to :data:`~kinetic_fem.solvers.fem.cooling.HUMP_FRONTIER`), plus that frontier."""
QUICK_EPS = (1e-2, 1e-3)
"""Inelasticities of the quick mode."""
QUICK_RESOLUTION = 0.14
"""Element size in the humps (hump widths) of the quick mode (zeta to ~5e-10)."""


def fem_eps(quick: bool) -> tuple[float, ...]:
    """The inelasticities of the FEM hump panels: :data:`QUICK_EPS`, or :data:`FEM_EPS`
    down to the frontier and the frontier itself.

    Parameters
    ----------
    quick : bool
        Quick mode.

    Returns
    -------
    tuple of float
        Decreasing inelasticities.
    """
    if quick:
        return QUICK_EPS
    reached = tuple(e for e in FEM_EPS if e >= HUMP_FRONTIER)
    return reached + ((HUMP_FRONTIER,) if reached[-1] > HUMP_FRONTIER else ())


@lru_cache(maxsize=2)
def near_elastic_states(quick: bool) -> dict[float, VelocityDistribution]:
    """The FEM cooling states (hard rods) at :func:`fem_eps`, one continuation (cached).

    Parameters
    ----------
    quick : bool
        Quick mode: :data:`QUICK_EPS` at :data:`QUICK_RESOLUTION` hump widths; else
        :func:`fem_eps` at the continuation's resolution (0.07 hump widths).

    Returns
    -------
    dict of float to VelocityDistribution
        ``info.extra["zeta"]`` the cooling rate; ``info.extra["resolution"]``.
    """
    res = QUICK_RESOLUTION if quick else HUMP_STEP_RESOLUTION
    out = {}
    for eps, st in hump_states(fem_eps(quick), resolution=res).items():
        info = replace(st.info, extra={"zeta": float(st.zeta), "resolution": res,
                                       "n_dofs": int(st.u.size)})
        out[eps] = st.disc.distribution(st.u, method="fem", params={"alpha": 1.0 - eps},
                                        info=info)
    return out


def fem_psi_profile(dist: VelocityDistribution, eps: float):
    """The right hump of a FEM state on the psi variables
    (:func:`kinetic_fem.analysis.humps.psi_profile` on its quadrature points).

    Parameters
    ----------
    dist : VelocityDistribution
        A symmetric cooling state (unit temperature).
    eps : float
        Its inelasticity.

    Returns
    -------
    HumpProfile
    """
    c = np.linspace(0.0, float(dist.v[-1]), 40001)
    w = np.full_like(c, 2.0 * (c[1] - c[0]))
    w[0] = w[-1] = c[1] - c[0]
    return psi_profile(c, dist.f(c), w, eps)


@lru_cache(maxsize=16)
def _hcs(alpha: float) -> HCSSolution:
    """The HCS at the default grid (cached: items share solutions)."""
    return solve_hcs(alpha)


def _a2(sol: HCSSolution) -> float:
    return float(np.dot(sol.grid.half_weights, sol.grid.v**4 * sol.f) / 3.0 - 1.0)


def _bimodal(alpha: float) -> bool:
    """f has a local minimum at c = 0 (ln f rises from the first node)."""
    sol = _hcs(alpha)
    return bool(sol.f[1] > sol.f[0])


def _threshold(lo: float, hi: float, tol: float) -> tuple[float, float]:
    """Bisect the restitution at which f''(0) changes sign, ``lo`` unimodal, ``hi`` not."""
    if _bimodal(lo) or not _bimodal(hi):
        raise RuntimeError(f"bimodality threshold not bracketed by [{lo}, {hi}]")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if _bimodal(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


def _fem_humps(ctx: Context) -> list[ClaimRow]:
    """The paper's F9 from the FEM state: the two humps at eps = 1e-2 ... the frontier;
    C9 (zeta/eps -> 1, with the quasi-elastic correction 0.18 eps^(4/3))."""
    states = near_elastic_states(ctx.quick)
    fig, (ax, axl) = subplots(1, 2, figsize=(10, 4))
    c = np.linspace(-1.6, 1.6, 3201)
    for eps, dist in states.items():
        ax.plot(c, dist.f(c), label=f"FEM eps = {eps:.3g}")
        cl = np.linspace(0.0, float(dist.v[-1]), 4001)
        axl.semilogy(cl, dist.f(cl), label=f"eps = {eps:.3g}")
    ax.set(xlabel="c", ylabel="f(c)", title="near-elastic HCS (FEM, hump meshes)")
    axl.set(xlabel="c", ylabel="f(c)", ylim=(1e-45, 1e3), title="log scale: outer edge "
            "exp(-|y|^3/3), inner tail exp(-<y^2> y)")
    ax.legend(fontsize=7)
    save(fig, ctx.out / "F9-HCS_fem_humps.png")
    zeta = {e: d.info.extra["zeta"] / e for e, d in states.items()}
    res = next(iter(states.values())).info.extra["resolution"]
    mode = ("quick: " if ctx.quick else "") + f"FEM, {res:g} hump widths"
    return [ClaimRow("C9", "FEM cooling rate zeta/eps near elastic (dT/dt = -2 zeta n "
                     "T^(3/2))", ", ".join(f"{z:.12f} (eps={e:.3g})" for e, z in zeta.items()),
                     "-> 1: T = (n eps t)^-2 (two delta peaks)",
                     bool(all(abs(z - 1.0) < 0.01 for z in zeta.values())), "fem (HCS)",
                     mode + "; (zeta/eps - 1)/eps^(4/3) = " + ", ".join(
                         f"{(z - 1.0) / e ** (4 / 3):.4f}" for e, z in zeta.items())
                     + " (quasi-elastic expansion: -> 0.18)")]


@register("F9-HCS", "deterministic homogeneous cooling state f(c): two humps for alpha > 0.8",
          claims=("C9", "C10", "C15"))
def hcs_figure(ctx: Context) -> list[ClaimRow]:
    """HCS f(c) at several alpha; zeta/eps, the bimodality threshold, Sonine vs HCS."""
    alphas = (0.0, 0.5, 0.8, 0.85, 0.9, 0.99)
    sols = {a: _hcs(a) for a in alphas}
    fig, (ax, axl) = subplots(1, 2, figsize=(10, 4))
    c = np.linspace(-3.0, 3.0, 601)
    gauss = np.exp(-0.5 * c**2) / math.sqrt(2.0 * math.pi)
    for a, s in sols.items():
        f = np.interp(np.abs(c), s.grid.v, s.f)
        ax.plot(c, f, label=f"alpha = {a}")
        cl = np.linspace(0, min(12.0, s.grid.v[-1]), 600)
        axl.semilogy(cl, np.interp(cl, s.grid.v, s.f), label=f"alpha = {a}")
    ax.plot(c, gauss, "k:", label="Gaussian")
    axl.semilogy(c[c >= 0], gauss[c >= 0], "k:")
    ax.set(xlabel="c", ylabel="f(c)", title="homogeneous cooling state (fd)")
    axl.set(xlabel="c", ylabel="f(c)", ylim=(1e-30, 10), title="tails: exp(-c/zeta)/c")
    ax.legend(fontsize=7)
    save(fig, ctx.out / "F9-HCS_cooling_state.png")
    rows = _fem_humps(ctx)
    z99 = sols[0.99].zeta
    rows.append(ClaimRow("C9", "dimensionless cooling rate zeta/eps at alpha = 0.99 "
                         "(dT/dt = -2 zeta n T^(3/2))", f"{z99 / 0.01:.5f}",
                         "-> 1: T = (n eps t)^-2 (two delta peaks)",
                         bool(abs(z99 / 0.01 - 1) < 0.01), "fd (HCS)",
                         "zeta: " + ", ".join(f"{a}: {s.zeta:.6g}" for a, s in sols.items())))
    tol = 0.01 if ctx.quick else 0.0005
    lo, hi = _threshold(0.75, 0.85, tol)
    onset = 0.5 * (lo + hi)
    rows.append(ClaimRow("C10", "onset of two humps in the HCS f(c): restitution where "
                         "f''(0) changes sign", f"{onset:.4f} +- {0.5 * (hi - lo):.4f}",
                         "two humps appear for alpha > 0.8", bool(hi <= 0.8 and _bimodal(0.8)),
                         "fd (HCS)",
                         "bisection at the default grid; the paper's 0.8 is read off DSMC "
                         "histograms, where humps with peak/f(0) < 1.02 (alpha < 0.8) are hard "
                         "to see: peak/f(0) = " + ", ".join(
                             f"{a}: {s.f.max() / s.f[0]:.3f}" for a, s in sols.items()
                             if a >= 0.8)))
    for a in (0.5, 0.85, 0.9, 0.99):
        lin, _ = solve_sonine_cooling(a, 2, linearized=True)
        try:
            s8, _ = solve_sonine_cooling(a, 8)
            o8 = f"{s8.coefficients[2]:+.4f}"
        except RuntimeError:
            o8 = "no solution"
        hcs = _a2(sols[a])
        rows.append(ClaimRow("C15", f"HCS a2 at alpha = {a}: fd vs Sonine (first order; "
                             "order 8)", f"{hcs:+.4f} vs {lin.coefficients[2]:+.4f}; {o8}",
                             "Sonine fails for free cooling at small eps", None, "fd vs spectral",
                             "first-order 1D HCS a2 = 16(1-2 alpha^2)/(33+30 alpha^2)"))
    return rows


@register("F11-HCS", "FEM HCS humps rescaled with eps^(1/3) onto psi", claims=("C11", "C12"))
def hcs_psi_figure(ctx: Context) -> list[ClaimRow]:
    """Width of the FEM humps against eps and their distance to the psi equation."""
    states = near_elastic_states(ctx.quick)
    epss = tuple(states)
    psi = solve_psi(estimate_errors=False)
    yy = np.linspace(-3.0, 5.0, 801)
    widths, dists = [], []
    fig, (ax, axl) = subplots(1, 2, figsize=(10, 4))
    for eps, dist in states.items():
        hump = fem_psi_profile(dist, eps)
        y, p, mean_abs = hump.y, hump.psi, hump.mean_abs
        c = mean_abs * (1.0 - eps ** (1.0 / 3.0) * y)
        pos = c >= 0.0
        f = p / (2.0 * eps ** (1.0 / 3.0) * mean_abs)
        dc = np.abs(np.gradient(c))
        var = 2.0 * float(np.sum(((c - mean_abs) ** 2 * f * dc)[pos]))
        widths.append(math.sqrt(var))
        py = np.interp(yy, y, p)
        dists.append(float(np.trapezoid(np.abs(py - psi(yy)), yy)))
        ax.plot(yy, py, label=f"FEM eps = {eps:.3g}")
        wide = (y > -8.0) & (y < 30.0)
        axl.semilogy(y[wide], np.maximum(p[wide], 1e-300), label=f"FEM eps = {eps:.3g}")
    ax.plot(yy, psi(yy), "k--", label="psi equation")
    yl = np.linspace(-8.0, 30.0, 1001)
    axl.semilogy(yl, psi(yl), "k--")
    ax.set(xlabel="y = (1 - |c|/<|c|>)/eps^(1/3)", ylabel="psi(y)")
    axl.set(xlabel="y", ylabel="psi(y)", ylim=(1e-30, 2))
    ax.legend(fontsize=8)
    save(fig, ctx.out / "F11-HCS_psi.png")
    nu = float(np.polyfit(np.log(epss), np.log(widths), 1)[0])
    rate = float(np.polyfit(np.log(epss), np.log(dists), 1)[0])
    local = [math.log(dists[k] / dists[k + 1]) / math.log(epss[k] / epss[k + 1])
             for k in range(len(epss) - 1)]
    mode = ("quick: " if ctx.quick else "") + "FEM on hump meshes, eps = " + ", ".join(
        f"{e:.3g}" for e in epss)
    return [
        ClaimRow("C11", "fitted exponent nu of the hump width sqrt(<(|c|-<|c|>)^2>)",
                 f"{nu:.3f}", "1/3", bool(abs(nu - 1 / 3) < 0.05), "fem (HCS)",
                 f"{mode}; widths " + ", ".join(f"{w:.5f}" for w in widths)
                 + "; psi predicts width/eps^(1/3) -> sqrt(<y^2>) <|c|> = "
                 + f"{math.sqrt(psi.y2):.4f}"),
        ClaimRow("C12", "L1 distance int |psi_HCS - psi| dy over -3 < y < 5",
                 ", ".join(f"{d:.4f} (eps={e:.3g})" for d, e in zip(dists, epss, strict=True)),
                 "-> 0 as eps -> 0 (quantitative agreement improving)",
                 bool(all(dists[i + 1] < dists[i] for i in range(len(dists) - 1))),
                 "fem (HCS) vs psi", f"{mode}; fitted rate d ln L1/d ln eps = {rate:.3f}, "
                 "local " + ", ".join(f"{r:.3f}" for r in local)
                 + " (next order of the eps^(1/3) expansion gives 1/3)"),
    ]
