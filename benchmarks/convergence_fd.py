"""Convergence study of the finite-difference (Biben) solver, ``method="fd"``.

For each alpha the steady state is computed on grids with spacing h, h/2, h/4, ...
(in units of sqrt(T)); the script prints, per quantity, the successive differences
and the observed order p = log2(|Q_h - Q_{h/2}| / |Q_{h/2} - Q_{h/4}|), then the
Richardson-extrapolated values (4 Q_{h/2} - Q_h)/3 and their own differences
(an estimate of the error of the extrapolated solution), the energy balance C1,
the mass-defect rate lambda of the discrete collision term, the number of decades
of f(c) resolved, and, when the FEM solver is importable, the FD/FEM differences.

    python benchmarks/convergence_fd.py                 # all alphas of issue 3
    python benchmarks/convergence_fd.py --alphas 0.6 --spacings 0.1 0.05 0.025
    python benchmarks/convergence_fd.py --defaults --fem   # accuracy of the defaults

``--defaults`` prints, per alpha, the error of the old default (one grid of spacing
0.04, the fixed point of the paper's time marching, computed here by Newton) and of
the new default (Newton, two Richardson levels over 0.08/0.04/0.02) against the FEM
defaults, with the error estimates the FD result reports and the wall times.
"""

from __future__ import annotations

import argparse
import importlib
import math
import time
import warnings

import numpy as np

import kinetic_fem as kf
import kinetic_fem.solvers.finite_difference  # noqa: F401  (registers "fd")
from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.operators.collision import energy_balance

ORDER = 2


def solve(alpha: float, spacing: float, cutoff: float) -> VelocityDistribution:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return kf.solve_heated(alpha, method="fd", steady="newton", spacing=spacing,
                               cutoff=cutoff, interpolation_order=ORDER, richardson=0)


def f_rel(a: VelocityDistribution, b: VelocityDistribution) -> float:
    """Max relative difference of f(c) on the common nodes of a (coarse) and b (fine)."""
    fa = a.f_values
    fb = b.f(a.c)
    keep = (fa > 1e-30) & (fb > 1e-30)
    return float(np.max(np.abs(fa[keep] / fb[keep] - 1.0)))


def orders(diffs: list[float]) -> list[str]:
    return ["" if i == 0 or diffs[i] == 0 else f"{math.log2(diffs[i - 1] / diffs[i]):.2f}"
            for i in range(len(diffs))]


def study(alpha: float, spacings: list[float]) -> None:
    cut = kinetic_fem.solvers.finite_difference.default_cutoff(alpha)
    print(f"\n=== alpha = {alpha}  (cutoff {cut:.1f} sqrt(T), Newton on the FD equations, "
          f"interpolation order {ORDER}) ===")
    sols, times = [], []
    # a cut-off on the coarsest grid, so that all grids nest
    cutoff = spacings[0] * math.ceil(kinetic_fem.solvers.finite_difference.default_cutoff(alpha)
                                     / spacings[0])
    for h in spacings:
        t0 = time.perf_counter()
        sols.append(solve(alpha, h, cutoff))
        times.append(time.perf_counter() - t0)
    print(f"{'h':>8} {'n_v':>6} {'T':>20} {'a2':>20} {'C1 resid':>10} {'lambda':>10} "
          f"{'iters':>5} {'conv':>5} {'wall s':>7}")
    for h, d, t in zip(spacings, sols, times, strict=True):
        eb = energy_balance(d.v, d.values, _weights(d), alpha=alpha, density=1.0, diffusion=1.0)
        print(f"{h:8.4f} {d.v.size:6d} {d.temperature:20.14f} {d.a2:20.14f} "
              f"{eb.relative_residual:10.2e} {d.info.extra['mass_defect_rate']:10.2e} "
              f"{d.info.iterations:5d} {str(d.info.converged):>5} {t:7.2f}")
    dt = [abs(sols[i].temperature / sols[i + 1].temperature - 1) for i in range(len(sols) - 1)]
    da = [abs(sols[i].a2 - sols[i + 1].a2) for i in range(len(sols) - 1)]
    df = [f_rel(sols[i], sols[i + 1]) for i in range(len(sols) - 1)]
    print(f"{'h -> h/2':>10} {'dT/T':>10} {'order':>6} {'|da2|':>10} {'order':>6} "
          f"{'max df/f':>10} {'order':>6}")
    for i, (a, b, c, oa, ob, oc) in enumerate(zip(dt, da, df, orders(dt), orders(da),
                                                  orders(df), strict=True)):
        print(f"{spacings[i]:10.4f} {a:10.2e} {oa:>6} {b:10.2e} {ob:>6} {c:10.2e} {oc:>6}")
    if len(sols) >= 3:
        rich = [richardson_pair(sols[i], sols[i + 1]) for i in range(len(sols) - 1)]
        print("Richardson (4 Q_{h/2} - Q_h)/3 of T and a2, ln f; differences of successive "
              "extrapolations:")
        for i in range(len(rich) - 1):
            r0, r1 = rich[i], rich[i + 1]
            print(f"  h={spacings[i]:.4f}: T={r0.temperature:.14f} a2={r0.a2:.14f}  "
                  f"dT/T={abs(r0.temperature / r1.temperature - 1):.2e} "
                  f"|da2|={abs(r0.a2 - r1.a2):.2e} max df/f={f_rel(r0, r1):.2e}")
    finest = sols[-1]
    f = finest.f_values
    print(f"decades of f(c) resolved on the finest grid: max f = {f.max():.3g}, "
          f"f at the cut-off = {f[-1]:.3g}, c_cut = {finest.c[-1]:.1f}")
    if "fem" in kf.HEATED_SOLVERS:
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fem = kf.solve_heated(alpha, method="fem")
        except Exception as exc:  # report, do not hide, a failing FEM solve
            print(f"FEM defaults failed: {type(exc).__name__}: {str(exc)[:200]}")
            return
        tf = time.perf_counter() - t0
        best = rich[-1] if len(sols) >= 3 else finest
        cmp = best.compare(fem)
        print(f"FD (finest Richardson) vs FEM defaults ({tf:.1f} s): "
              f"dT/T={cmp.temperature_rel:.2e} |da2|={cmp.a2_abs:.2e} "
              f"max df/f(f>1e-30)={cmp.f_rel_max:.2e}")
        if len(sols) >= 3:
            # second Richardson level (eliminates h^4): (16 R_{h/2} - R_h)/15
            r2 = richardson_pair(rich[-2], rich[-1], weight=16.0)
            cmp2 = r2.compare(fem)
            print(f"FD (two Richardson levels, h = {spacings[-3]:g}, {spacings[-2]:g}, "
                  f"{spacings[-1]:g}) vs FEM defaults: dT/T={cmp2.temperature_rel:.2e} "
                  f"|da2|={cmp2.a2_abs:.2e} max df/f(f>1e-30)={cmp2.f_rel_max:.2e}")


def defaults(alpha: float) -> None:
    """Old default (one grid, h = 0.04) and new default (two Richardson levels) vs FEM."""
    importlib.import_module("kinetic_fem.solvers.fem")  # registers "fem"

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        fem = kf.solve_heated(alpha, method="fem")
        t_fem = time.perf_counter() - t0
        t0 = time.perf_counter()
        old = kf.solve_heated(alpha, method="fd", spacing=0.04, richardson=0)
        t_old = time.perf_counter() - t0
        t0 = time.perf_counter()
        new = kf.solve_heated(alpha, method="fd")
        t_new = time.perf_counter() - t0
    for name, d, t in (("one grid h=0.04", old, t_old), ("default (2 levels)", new, t_new)):
        cmp = d.compare(fem)
        e = d.info.extra
        print(f"alpha={alpha:<6} {name:>19}: dT/T={cmp.temperature_rel:8.1e} "
              f"|da2|={cmp.a2_abs:8.1e} max df/f={cmp.f_rel_max:8.1e}  estimated: "
              f"{e['estimated_error_temperature']:8.1e} {e['estimated_error_a2']:8.1e} "
              f"{e['estimated_error_f']:8.1e}  {t:6.1f} s (FEM {t_fem:.1f} s)")


def _weights(d: VelocityDistribution) -> np.ndarray:
    from kinetic_fem.operators.grid import simpson_weights
    return simpson_weights(d.v)


def richardson_pair(coarse: VelocityDistribution, fine: VelocityDistribution,
                    weight: float = 4.0) -> VelocityDistribution:
    """(w ln P_fine - ln P_coarse)/(w - 1) on the coarse nodes (w = 2^order)."""
    pf = fine.values[:: (fine.v.size - 1) // (coarse.v.size - 1)]
    pc = coarse.values
    out = pf.copy()
    ok = (pf > 0) & (pc > 0)
    out[ok] = np.exp((weight * np.log(pf[ok]) - np.log(pc[ok])) / (weight - 1))
    return VelocityDistribution.from_values(coarse.v, out, method="fd-richardson")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+",
                        default=[0.0, 0.1, 0.6, 0.9, 0.99, 0.999])
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.16, 0.08, 0.04, 0.02])
    parser.add_argument("--fem", action="store_true", help="compare with the FEM solver")
    parser.add_argument("--defaults", action="store_true",
                        help="accuracy of the default call against the FEM defaults")
    parser.add_argument("--order", type=int, default=2, choices=(2, 3),
                        help="interpolation order of the gain argument (2: the paper)")
    args = parser.parse_args()
    global ORDER
    ORDER = args.order
    if args.fem:
        import kinetic_fem.solvers.fem.heated  # noqa: F401
    if args.defaults:
        for alpha in args.alphas:
            defaults(alpha)
        return
    for alpha in args.alphas:
        study(alpha, args.spacings)


if __name__ == "__main__":
    main()
