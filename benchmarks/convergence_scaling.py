"""Convergence of the quasi-elastic phi and psi solvers (kinetic_fem.solvers.scaling).

Prints, for every returned constant, the change under grid refinement with the
observed order log2(d_h / d_{h/2}), the error against domain size, the Newton
cost, the asymptotic checks of claims C5 and C12 beside the paper's statements, and
the sup-norm distance between the heated FEM solution rescaled by
(n eps / D)^(1/3) and phi as eps -> 0.

Run: python benchmarks/convergence_scaling.py [--skip-fem] [--dsmc]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.solvers.scaling import LAMBDA_PAPER, solve_phi, solve_psi


def spacing_table(title, solve, sizes, names):
    """Solve on each size; print constants, successive differences and orders."""
    print(f"\n## {title}: grid spacing")
    sols = []
    for n in sizes:
        t = time.perf_counter()
        s = solve(n)
        sols.append((n, s, time.perf_counter() - t))
    print(f"{'n_v':>6} {'h':>9} {'iters':>5} {'residual':>9} {'time/s':>7}  "
          + " ".join(f"{k:>20}" for k in names))
    for n, s, dt in sols:
        h = float(s.distribution.v[1] - s.distribution.v[0])
        print(f"{n:6d} {h:9.5f} {s.info.iterations:5d} {s.info.residual:9.1e} {dt:7.3f}  "
              + " ".join(f"{s.constants()[k]:20.14f}" for k in names))
    vals = np.array([[s.constants()[k] for k in names] for _, s, _ in sols])
    diffs = np.abs(np.diff(vals, axis=0))
    print("  |q_h - q_h/2| and observed order log2(d_h / d_h/2):")
    for i in range(diffs.shape[0]):
        order = (np.log2(diffs[i - 1] / diffs[i]) if i > 0 else np.full(len(names), np.nan))
        print(f"  h/{2 ** (i + 1):<3d}  " + " ".join(f"{d:10.2e} p={p:5.2f}" for d, p in
                                                 zip(diffs[i], order, strict=True)))
    return sols


def domain_table(title, solve, params, names, reference):
    """Errors against a large-domain reference at fixed spacing."""
    print(f"\n## {title}: domain size (fixed h, error vs the default domain)")
    print(f"{'domain':>14}  " + " ".join(f"{k:>10}" for k in names))
    for p in params:
        s = solve(p)
        print(f"{str(p):>14}  " + " ".join(f"{abs(s.constants()[k] - reference[k]):10.1e}"
                                            for k in names))


def phi_report():
    names = ["C", "lam", "x2", "x4", "a2", "x_cr"]
    spacing_table("phi", lambda n: solve_phi(n_v=n, estimate_errors=False),
                  [177, 353, 705, 1409, 2817, 5633], names)
    sol = solve_phi()
    ref = sol.constants()

    def on_domain(cutoff):
        return solve_phi(cutoff=cutoff, n_v=4 * round(cutoff / 0.02) + 1, estimate_errors=False)

    domain_table("phi", on_domain, [3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0], names, ref)
    print("  (domain error ~ phi(L) ~ C exp(-L^3/6 - <x^2> L/2): 1.6e-5 at L=3, 1.3e-12 at L=5)")
    print("\n## phi: constants at the default grid (cutoff 7, n_v 1401) with estimated errors")
    for k in names:
        print(f"  {k:5s} = {ref[k]:.13f} +- {sol.errors[k]:.1e}")
    print(f"  lambda = {sol.lam:.10f}   paper: {LAMBDA_PAPER}")
    print(f"  x_cr = 3 lambda = {sol.x_cr:.10f}   paper: 2.36")
    a = sol.asymptotics()
    print("\n## phi asymptotics (C5)")
    print(f"  tail on x in {a.tail_window}: max|ln phi - (ln C - x^3/6 - <x^2> x/2)| = "
          f"{a.tail_deviation:.2e}")
    print(f"  the paper's C exp(-x^3/6) alone: ln phi - (ln C - x^3/6) at x={a.tail_window[1]} = "
          f"{a.tail_linear_term:.6f} (= -<x^2> x/2 = {-sol.x2 * a.tail_window[1] / 2:.6f})")
    print(f"  effective tail exponent d ln(-ln(phi/C))/d ln x at x={a.tail_window[1]}: "
          f"{a.tail_exponent:.4f} (-> 3)")
    print(f"  core fit: lambda = {a.core_lambda:.8f} (int|x|phi = {sol.lam:.8f}), "
          f"x^4 coefficient {a.core_quartic:.6f} (theory -phi(0)/12 = "
          f"{-sol.values[sol.x.size // 2] / 12:.6f})")
    print(f"  C~ = C exp(-<|x|^3>/6) vs phi(0): relative difference {a.c_tilde_rel:.1e}")
    print(f"  crossover: effective exponent = 5/2 at x = {a.x_cr_observed:.4f}; "
          f"3 lambda = {sol.x_cr:.4f}")
    print(f"  (ln phi)'''' + 2 phi, max on |x|<=3 / max phi: {a.ode_residual:.1e}")
    print(f"  energy balance: int int |x-y|^3 phi phi = {a.energy_identity:.12f} (exact 4)")
    return sol


def psi_report():
    names = ["C", "y2", "y3", "y_peak", "psi_peak"]
    spacing_table("psi", lambda n: solve_psi(n_v=n, estimate_errors=False),
                  [263, 525, 1049, 2097, 4193, 8385], names)
    sol = solve_psi()
    ref = sol.constants()
    h = 0.01

    def on_domain(ends):
        lo, hi = ends
        n = round((hi - lo) / h) + 1
        return solve_psi(domain=(lo, hi), n_v=n + (n + 1) % 2, estimate_errors=False)

    domain_table("psi (left end)", on_domain,
                 [(-2.5, 36.0), (-3.0, 36.0), (-3.5, 36.0), (-4.0, 36.0), (-4.5, 36.0)],
                 names, ref)
    print("  (left error ~ exp(lo^3/3): 5.5e-3 at -2.5, 5.1e-10 at -4.5)")
    domain_table("psi (right end)", on_domain,
                 [(-6.0, 15.0), (-6.0, 20.0), (-6.0, 25.0), (-6.0, 30.0)], names, ref)
    print("  (right error ~ hi^3 exp(-<y^2> hi): each +5 in hi gains exp(-6.05) = 2.4e-3)")
    print("\n## psi: constants at the default grid (domain (-6, 36), n_v 4201) with errors")
    for k in names:
        print(f"  {k:8s} = {ref[k]:.13f} +- {sol.errors[k]:.1e}")
    a = sol.asymptotics()
    lnc = np.log(sol.C)
    print("\n## psi checks (C12); 'paper' = the printed formula, 'derived' = from eq. (psi)")
    print(f"  <y> = {a.mean:.1e}, c - <y^2> = {a.c_minus_y2:.1e}")
    print(f"  left tail fit ln psi = a + b y^3 on {a.left_window}: b = {a.left_cubic:.10f} "
          f"(1/3), a = {a.left_log_prefactor:.10f} (ln C = {lnc:.10f})")
    print(f"  right tail fit ln psi = a + s y on {a.right_window}: s = {a.right_slope:.10f}")
    print(f"     derived -<y^2> = {-sol.y2:.10f}; paper -2<y^2> = {-2 * sol.y2:.10f}")
    print(f"     a = {a.right_log_prefactor:.10f}; derived ln C + <y^3>/3 = "
          f"{lnc + sol.y3 / 3:.10f}; paper ln C - <y^3>/3 = {lnc - sol.y3 / 3:.10f}")
    print(f"  (ln psi)'''' + 2 psi, max on [-3, 6] / max psi: {a.ode_residual:.1e} (derived)")
    print(f"  (ln psi)'''' - psi,   max on [-3, 6] / max psi: {a.ode_residual_paper:.3f} (paper)")
    print(f"  eq. (psi) differential form on the solution, max|res|/max|psi'|: "
          f"{a.differential_residual:.1e}")
    return sol


def fem_report(phi):
    import kinetic_fem.solvers.fem.heated  # noqa: F401  (registers "fem")

    print("\n## heated FEM solution rescaled by x = (n eps/D)^(1/3) v vs phi, |x| <= 4")
    x = np.linspace(-4.0, 4.0, 801)
    prev = None
    print(f"{'alpha':>8} {'eps':>8} {'sup|P_x - phi|':>15} {'rate':>6} {'T_x - <x^2>':>12} "
          f"{'a2 - a2_phi':>12} {'time/s':>7}")
    for alpha in (0.99, 0.999, 0.9999):
        eps = 1.0 - alpha
        t = time.perf_counter()
        d = kf.solve_heated(alpha, method="fem").rescaled(eps ** (1.0 / 3.0))
        dt = time.perf_counter() - t
        sup = float(np.max(np.abs(d.pdf(x) - phi(x))))
        rate = np.log10(prev / sup) if prev else float("nan")
        print(f"{alpha:8.4f} {eps:8.0e} {sup:15.3e} {rate:6.2f} {d.temperature - phi.x2:12.3e} "
              f"{d.a2 - phi.a2:12.3e} {dt:7.1f}")
        prev = sup
    print("  rate = log10 of the ratio per decade of eps (1 = linear in eps)")


def dsmc_report(psi):
    """DSMC hump at eps = 1e-2 against psi: a rough check of the slow-side decay rate."""
    from particles import dsmc

    eps, cpp = 1e-2, 6000.0
    print(f"\n## DSMC free cooling at eps = {eps}, N = 20000, {cpp:.0f} collisions/particle "
          "vs psi (left hump, y = (c + 1)/eps^(1/3))")
    t = time.perf_counter()
    run = dsmc.simulate_cooling(1 - eps, 20000, seed=7, collisions_per_particle=cpp, bins=400,
                                c_max=1.6)
    d = run.distribution
    delta = eps ** (1 / 3)
    y = (d.c + 1) / delta
    print(f"  ({time.perf_counter() - t:.0f} s; relaxed after {run.relaxed_at:.0f} "
          f"collisions/particle)")
    print(f"{'y':>7} {'DSMC f':>9} {'psi/(2 delta)':>14}")
    for yy, ff in list(zip(y, d.f_values, strict=True))[::6]:
        if -3.0 < yy < 4.0:
            print(f"{yy:7.2f} {ff:9.4f} {psi(np.array([yy]))[0] / (2 * delta):14.4f}")
    win = (y > 1.1) & (y < 2.8)
    s_dsmc = np.polyfit(y[win], np.log(d.f_values[win]), 1)[0]
    s_psi = np.polyfit(y[win], np.log(psi(y[win])), 1)[0]
    print(f"  slow-side slope d ln f/dy on 1.1 < y < 2.8: DSMC {s_dsmc:.3f}, psi {s_psi:.3f}; "
          f"asymptotic: derived -<y^2> = {-psi.y2:.3f}, paper -2<y^2> = {-2 * psi.y2:.3f}")
    print("  (corrections are O(eps^(1/3)) = 0.2 here; the humps overlap near c = 0)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-fem", action="store_true", help="skip the FEM comparison")
    parser.add_argument("--dsmc", action="store_true", help="add a DSMC hump check (~1 min)")
    args = parser.parse_args()
    phi = phi_report()
    psi = psi_report()
    if not args.skip_fem:
        fem_report(phi)
    if args.dsmc:
        dsmc_report(psi)


if __name__ == "__main__":
    main()
