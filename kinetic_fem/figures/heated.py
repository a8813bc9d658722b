"""Heated steady state by the deterministic solvers: F2 (lines), F6 and C1, C2, C4, C6, C7, C16.

The steady states come from the paper's finite-difference scheme (``method="fd"``)
solved by Newton's method on its discrete equations (``steady="newton"``, the same
fixed point as the time marching, which is used for the transients of C2), with cubic
interpolation of the gain-term argument (``interpolation_order=3``), whose error is
not amplified by :math:`1/\\varepsilon` as that of the paper's quadratic one is.
The peaks of n(c) behind C6 and C7 (F6) come from the FEM solver instead
(:func:`kinetic_fem.analysis.peak_study.fem_steady`,
:func:`~kinetic_fem.analysis.peak_study.peak_sweep` with ``method="fem"``): at eps = 1e-3 the FD
peak position still moves by 20 % between h = 0.06 and 0.03.  At and below eps = 1e-3 the
peak lies below the double-precision range and comes from the tail equation in log
variables on the FEM bulk (:func:`~kinetic_fem.analysis.heated_tail.tail_sweep`).

Observables, all at ``n = D = 1``:

* effective exponent :math:`n(v) = d\\ln(-\\ln(P/P_0))/d\\ln v` (C7) and its maximum
  :math:`(v^*, n^*)`; the quasi-elastic variable is :math:`x = (n\\varepsilon/D)^{1/3} v`
  (C5), so :math:`v^* \\propto \\varepsilon^{-1/3}` means a fixed :math:`x^*`;
* far-tail amplitude from :math:`\\ln f = -A c^{3/2} + \\beta\\ln c + \\gamma` against
  :math:`A_c = \\tfrac23 T^{3/4}` (C4);
* relaxation time of :math:`T(t)` from a Gaussian start against
  :math:`\\tau \\sim \\varepsilon^{-2/3}` (C2).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import (
    power_law_exponent,
    relaxation_fit,
    richardson,
    tail_fit,
)
from ..analysis.heated_tail import quasi_elastic_peak, tail_sweep
from ..analysis.peak_study import (
    FEM_PEAK_SPACINGS,
    combine_sweeps,
    fem_steady,
    peak_sweep,
    relaxation_run,
    solve_steady,
)
from ..distribution import VelocityDistribution
from ..operators.collision import energy_balance
from ..operators.grid import simpson_weights
from ..reproduce import ClaimRow, Context, register
from ..sonine import crossover_velocities, relaxation_time
from .plotting import save, subplots


def _c1_residual(dist: VelocityDistribution) -> float:
    alpha = float(dist.params["alpha"])
    return energy_balance(dist.v, dist.values, simpson_weights(dist.v), alpha=alpha,
                          density=1.0, diffusion=1.0).relative_residual


_QUICK_SPACING = {0.1: 0.16, 0.6: 0.16, 0.9: 0.08, 0.99: 0.04}
"""Quick-mode coarsest spacing h of F2-FD per alpha (grids h, h/2, h/4)."""


@register("F2-FD", "heated f(c) of the deterministic iteration (lines of F2), 30 decades",
          claims=("C1", "C16"))
def figure_f2(ctx: Context) -> list[ClaimRow]:
    """f(c) for alpha = 0.1, 0.6, 0.9, 0.99; C16 by grid refinement; C1 residuals.

    C16: Richardson extrapolations from spacings (h, h/2) and (h/2, h/4) are compared
    wherever f > 1e-30; their difference bounds the error of the coarser one.
    """
    alphas = (0.1, 0.6, 0.9, 0.99)
    rows = []
    fig, ax = subplots(figsize=(6, 4.5))
    inset = ax.inset_axes([0.12, 0.08, 0.35, 0.35])
    for alpha in alphas:
        # quick: the coarsest grids whose Richardson values are within 5 % (convergence_fd;
        # at h = 0.16 the change is 1.8e-2 for alpha 0.1 and 3.2e-2 for 0.6, but 0.19 for
        # 0.9 and 0.26 at h = 0.08 for 0.99, which keep 0.08 and 0.04); the finest grid
        # h/4 costs three quarters of the item (the operator is dense, cost ~ N^2)
        h = _QUICK_SPACING[alpha] if ctx.quick else 0.04
        sols = [solve_steady(alpha, spacing=h / k, cutoff_factor=1.0, nest=h)
                for k in (1, 2, 4)]
        rich = [richardson(sols[0], sols[1]), richardson(sols[1], sols[2])]
        best = rich[1]
        keep = best.f_values > 1e-35
        line, = ax.semilogy(best.c[keep], best.f_values[keep], label=f"alpha={alpha}")
        if alpha in (0.6, 0.99):
            inset.plot(best.c, best.f_values, color=line.get_color())
        change = rich[0].compare(best).f_rel_max
        f = best.f_values
        decades = math.log10(f.max() / 1e-30)
        c30 = float(best.c[(best.c > 0) & (f > 1e-30)].max())
        rows.append(ClaimRow(
            "C16", f"f(c) resolved, alpha={alpha}",
            f"f from {f.max():.2f} to 1e-30 ({decades:.1f} decades, c <= {c30:.1f}) all > 0; "
            f"max rel. difference of Richardson values (h={h:g},{h / 2:g}) vs "
            f"({h / 2:g},{h / 4:g}): {change:.1e}", "30 decades",
            bool(np.all(sols[2].values > 0) and change < 0.05), "fd (Newton) + Richardson",
            "relative to the tail value itself, wherever f > 1e-30"))
        res = _c1_residual(sols[2])
        rows.append(ClaimRow("C1", f"steady energy balance, alpha={alpha}",
                             f"|2D - loss|/2D = {res:.1e} (h={h / 4:g})", "0 (exact balance)",
                             bool(res < 1e-4), "fd (Newton)",
                             "discretisation error; grows as alpha -> 1 (gain interpolation)"))
    c = np.linspace(0, 8, 200)
    gauss = np.exp(-c**2 / 2) / math.sqrt(2 * math.pi)
    ax.semilogy(c, gauss, "k:", label="Gaussian")
    inset.plot(c[:100], gauss[:100], "k:")
    ax.set_ylim(1e-35, 1)
    ax.set_xlabel("c")
    ax.set_ylabel("f(c)")
    ax.legend(loc="upper right", fontsize=8)
    save(fig, ctx.out / "F2_fd_lines.png")
    return rows


@register("F6", "effective exponent n(c) of the deterministic solution, peak scaling",
          claims=("C6", "C7"))
def figure_f6(ctx: Context) -> list[ClaimRow]:
    """n(c) for alpha = 0.6 ... 0.999 and the phi limit; fits of v* and 3 - n* over eps.

    Peaks above eps = 1e-3 come from the FEM solver (:func:`peak_sweep` with
    ``method="fem"``); at and below 1e-3 from the tail equation in log variables on the
    FEM bulk (:func:`tail_sweep`), since the peak lies at f ~ 1e-104 (eps = 1e-4) to
    1e-1700 (1e-6), below the double-precision range of the FEM weak form.  Full mode:
    FEM eps = 1e-1 ... 1e-2 at spacings 0.05 / 0.035 (Gauss degree 9, two cut-offs),
    tail eps = 1e-3 ... 1e-6 in half decades (bulk spacing h0 and h0/sqrt 2, tail grid
    0.1 and 0.05, two matching depths); quick mode FEM eps = 0.1, 0.03, 0.01 (spacings
    0.1 / 0.07, degree 5, default cut-off) and tail eps = 1e-3, 1e-4 without the depth
    check.  Measured (``benchmarks/results/heated_near_elastic.md``): local exponents
    of v* -0.577 (1e-1 -> 3e-2) ... -0.5349 (3e-6 -> 1e-6), of 3 - n* +0.297 ... +0.3946;
    the two-term expansion n = n_phi - (3/16) eps x^3 predicts x* ~ eps^(-1/5), i.e.
    v* ~ eps^(-8/15) and 3 - n* ~ eps^(2/5), and matches x* to 0.2 % at eps = 1e-6.
    """
    from ..solvers.scaling import solve_phi

    fig, (ax, bx) = subplots(1, 2, figsize=(10, 4.2))
    for alpha in (0.6, 0.9, 0.99, 0.999):
        if ctx.quick:
            d = fem_steady(alpha, spacing=0.1, cutoff_factor=1.0, intorder=9)
        else:
            d = fem_steady(alpha, spacing=FEM_PEAK_SPACINGS[0], cutoff_factor=1.3, intorder=9)
        top = 0.9 * float(d.c.max())
        c = np.linspace(0.05, top, 800)
        ax.plot(c, d.effective_exponent(c), label=f"alpha={alpha}")
    phi = solve_phi().distribution
    c = np.linspace(0.05, 0.95 * phi.c.max(), 800)
    ax.plot(c, phi.effective_exponent(c), "k:", label="alpha -> 1 (phi)")
    ax.axhline(1.5, color="gray", lw=0.5)
    ax.axhline(3.0, color="gray", lw=0.5)
    ax.set_xlabel("c")
    ax.set_ylabel("n(c)")
    ax.legend(fontsize=8)
    fem_eps: tuple[float, ...]
    tail_eps: tuple[float, ...]
    if ctx.quick:
        fem_eps, spacings, tail_eps = (0.1, 0.03, 0.01), (0.1, 0.07), (1e-3, 1e-4)
    else:
        fem_eps, spacings = (0.1, 0.03, 0.01), FEM_PEAK_SPACINGS
        tail_eps = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6)
    fsweep = peak_sweep(fem_eps, spacing=spacings[0], fine_spacing=spacings[1], method="fem",
                        cutoff_check=not ctx.quick, intorder=5 if ctx.quick else 9)
    tsweep = tail_sweep(tail_eps, depth_check=not ctx.quick)
    sweep = combine_sweeps(fsweep, tsweep)
    v_exp, n_exp = sweep.fits()
    sel = list(sweep.peaks)
    eps_sel = np.array([p.eps for p in sel])
    if sel:
        bx.loglog(eps_sel, [p.v for p in sel], "o-", label="v*")
        bx.loglog(eps_sel, [3 - p.n for p in sel], "s-", label="3 - n*")
        for slope, style in ((-1 / 3, "k:"), (-8 / 15, "k--"), (1 / 3, "k-."),
                             (2 / 5, "k-")):
            ref = sel[-1].v if slope < 0 else 3 - sel[-1].n
            bx.loglog(eps_sel, ref * (eps_sel / eps_sel[-1]) ** slope, style, lw=0.8,
                      label=f"eps^({slope:+.3f})")
    bx.set_xlabel("eps")
    bx.legend(fontsize=7)
    save(fig, ctx.out / "F6_effective_exponent.png")
    not_conv = [p.eps for sw in (fsweep, tsweep)
                for p, ok in zip(sw.peaks, sw.converged, strict=True) if not ok]
    table = "; ".join(f"eps={p.eps:.0e}: v*={p.v:.3f} x*={p.x:.4f} n*={p.n:.5f}" for p in sel)
    if not_conv:
        table += "; not converged (left out): " + ", ".join(f"{e:.0e}" for e in not_conv)
    local, errs = sweep.local(), sweep.local_errors()
    loc_v = ", ".join(f"{e1:.0e}-{e2:.0e}: {ve:+.3f}" for e1, e2, ve, _ in local)
    loc_n = ", ".join(f"{e1:.0e}-{e2:.0e}: {ne:+.3f}" for e1, e2, _, ne in local)
    ratios = [p.v / crossover_velocities(1.0 - p.eps)[0] for p in sel]
    # v_cr1^(2/5) v_cr2^(3/5) = eps^(-8/15) at n = D = 1
    scaled = [p.x * p.eps ** 0.2 for p in sel]
    theory = [quasi_elastic_peak(p.eps)[0] for p in sel]
    n0 = float(phi.effective_exponent(np.array([0.05]))[0])
    span = (f"fem P2 h={spacings[0]:g}/{spacings[1]:g} (eps >= 1e-2), tail equation on "
            f"the FEM bulk (eps <= 1e-3); fit over eps = "
            f"{', '.join(f'{e:.0e}' for e in eps_sel)}")
    why = ("x* = v* eps^(1/3) is not constant: the peak sits where the phi-limit exponent "
           "n_phi ~ 3 - 6<x^2>/x^2 (rising toward 3) is bent down by the onset of the "
           "crossover to the |v|^(3/2) tail, -(3/16) eps x^3 = -(3/16)(x/x_cr2)^3, so "
           "x* ~ (64<x^2>/(3 eps))^(1/5): v* ~ eps^(-8/15), 3 - n* ~ eps^(2/5)")
    last = local[-1] if local else (math.nan, math.nan, math.nan, math.nan)
    asymptotic = ("the least-squares value averages a drifting local exponent; the claim is "
                  "asymptotic, so the verdict is that of the local exponent at the smallest "
                  "eps (rows below)")
    last_err = errs[-1] if errs else (math.nan, math.nan)
    pair = f"eps = {last[0]:.0e} -> {last[1]:.0e}"
    return [
        ClaimRow("C7", "n(c -> 0) (phi limit, c = 0.05)", f"{n0:.4f}", "2",
                 bool(abs(n0 - 2) < 0.01), "scaling.solve_phi"),
        ClaimRow("C7", "exponent of v* against eps", f"{v_exp:.3f} (local: {loc_v})", "-1/3",
                 bool(abs(last[2] + 1 / 3) < 0.05), "fem + tail",
                 f"{span}; {asymptotic}; {why}; {table}", explained="peak exponent"),
        ClaimRow("C7", "exponent of 3 - n* against eps", f"{n_exp:.3f} (local: {loc_n})", "1/3",
                 bool(abs(last[3] - 1 / 3) < 0.05), "fem + tail",
                 f"{span}; {asymptotic}; local exponent from "
                 f"{local[0][3] if local else math.nan:.3f} (largest eps) to {last[3]:.3f} "
                 "(smallest), toward the derived 2/5", explained="peak exponent"),
        ClaimRow("C7", f"local exponent of v*, smallest pair ({pair})",
                 f"{last[2]:.4f} +- {last_err[0]:.1e}", "-1/3",
                 bool(abs(last[2] + 1 / 3) < 0.05), "fem + tail",
                 "two-point exponent between the two smallest eps, error bar from mesh "
                 "refinement; derived asymptote -8/15 = -0.5333", explained="peak exponent"),
        ClaimRow("C7", f"local exponent of 3 - n*, smallest pair ({pair})",
                 f"{last[3]:.4f} +- {last_err[1]:.1e}", "1/3",
                 bool(abs(last[3] - 1 / 3) < 0.05), "fem + tail",
                 "two-point exponent between the two smallest eps; derived asymptote 2/5",
                 explained="peak exponent"),
        ClaimRow("C6", "x* = v*/v_cr1, v_cr1 = (D/(n eps))^(1/3)",
                 ", ".join(f"{r:.2f}" for r in ratios), "O(1), eps-independent",
                 bool(ratios and max(ratios) / min(ratios) < 1.2), "fem + tail",
                 "the peak sits at a fixed multiple of v_cr1 only if x* is constant; "
                 f"measured x* grows from {ratios[0] if ratios else math.nan:.2f} to "
                 f"{ratios[-1] if ratios else math.nan:.2f} (eps = "
                 f"{eps_sel[0] if sel else math.nan:.0e} ... "
                 f"{eps_sel[-1] if sel else math.nan:.0e})", explained="peak exponent"),
        ClaimRow("C6", "v* / (v_cr1^(2/5) v_cr2^(3/5)) = x* eps^(1/5)",
                 ", ".join(f"{r:.3f}" for r in scaled),
                 "not in the paper (derived: -> (64<x^2>/3)^(1/5) = 1.820)", None,
                 "fem + tail",
                 "the peak is set by the crossover to the |v|^(3/2) tail (v_cr2), not by "
                 "v_cr1 alone; two-term prediction x*(eps) (eps <= 3e-3, where its tail "
                 "form holds): " + ", ".join(f"{p.eps:.0e}: {t:.3f}" for p, t in
                                             zip(sel, theory, strict=True) if p.eps <= 3e-3)
                 + f"; measured/predicted - 1 at the smallest eps: "
                 f"{sel[-1].x / theory[-1] - 1 if sel else math.nan:+.1e}"),
    ]


@register("C4-FD", "far tail exp(-(2/3) sqrt(n/D) |v|^(3/2)) of the deterministic solution",
          claims=("C4",))
def claim_c4(ctx: Context) -> list[ClaimRow]:
    """Fitted amplitude of the far tail against the prediction, at small alpha.

    The fitted amplitude converges to the prediction as h^2 (ratio 0.980, 0.9955, 0.9989
    at h = 0.08, 0.04, 0.02 for alpha = 0).
    """
    h = 0.06 if ctx.quick else 0.02
    rows = []
    for alpha in (0.0, 0.1, 0.6):
        fit = tail_fit(solve_steady(alpha, spacing=h))
        rows.append(ClaimRow(
            "C4", f"tail amplitude A_c, alpha={alpha}", f"{fit.amplitude:.4f}",
            f"(2/3) T^(3/4) = {fit.predicted:.4f}", bool(abs(fit.amplitude / fit.predicted - 1)
                                                         < 0.02),
            "fd (Newton)", f"fit ln f = -A c^1.5 + b ln c + g over c in [{fit.c_range[0]:.1f}, "
            f"{fit.c_range[1]:.1f}], b = {fit.beta:.2f}"))
    return rows


@register("C2-FD", "relaxation time of T(t) from a Gaussian start, tau ~ eps^(-2/3)",
          claims=("C2",))
def claim_c2(ctx: Context) -> list[ClaimRow]:
    """tau from the paper's time marching at several alpha; fitted exponent against eps."""
    alphas = (0.8, 0.9, 0.95, 0.98) if ctx.quick else (0.8, 0.9, 0.95, 0.98, 0.99, 0.995)
    h = 0.2 if ctx.quick else 0.1
    runs = [relaxation_run(a, spacing=h) for a in alphas]
    tau = np.array([relaxation_fit(d) for d in runs])
    eps = 1.0 - np.array(alphas)
    fig, (ax, bx) = subplots(1, 2, figsize=(9, 3.8))
    for a, d in zip(alphas, runs, strict=True):
        ax.plot(d.series["t"] / relaxation_time(a), d.series["temperature"] / d.temperature,
                label=f"alpha={a}")
    ax.set_xlabel("t / [D/(n(1-alpha^2))]^(2/3)")
    ax.set_ylabel("T(t) / T")
    ax.legend(fontsize=8)
    bx.loglog(eps, tau, "o-", label="fd march")
    bx.loglog(eps, tau[0] * (eps / eps[0]) ** (-2 / 3), "k:", label="eps^(-2/3)")
    bx.set_xlabel("eps")
    bx.set_ylabel("tau")
    bx.legend(fontsize=8)
    save(fig, ctx.out / "C2_relaxation.png")
    slope = power_law_exponent(eps, tau)
    slope_a = power_law_exponent(1.0 - np.array(alphas) ** 2, tau)
    table = ", ".join(f"{a}: {t:.3f}" for a, t in zip(alphas, tau, strict=True))
    return [ClaimRow("C2", "exponent of tau against eps", f"{slope:.3f}", "-2/3",
                     bool(abs(slope + 2 / 3) < 0.05), "fd (march)", f"tau: {table}"),
            ClaimRow("C2", "exponent of tau against 1 - alpha^2", f"{slope_a:.3f}", "-2/3",
                     bool(abs(slope_a + 2 / 3) < 0.05), "fd (march)",
                     "late exponential approach of T(t), Gaussian start at T/2")]
