"""Grid convergence of the homogeneous cooling state solver (cooling ``method="fd"``).

For each alpha the HCS is solved with spacings ``2 h, h, h/2, h/4`` (``h`` the default,
:func:`kinetic_fem.solvers.fd_cooling.default_spacing`) on a common cut-off, and the script prints
the cooling rate zeta, a2, the energy identity ``zeta - (1-alpha^2)<|c-c'|^3>/8``
(zero in the continuum, not imposed), the mass-defect rate, successive differences
with observed orders ``log2(d_h / d_{h/2})``, and the max relative difference of f(c)
wherever f > 1e-30.  The last block compares the default solution with DSMC-free
independent checks: the Sonine moment method (order 8) where it converges.

    python benchmarks/convergence_cooling.py [--alphas 0.5 0.85] [--levels 4]
    python benchmarks/convergence_cooling.py --defaults --alphas 0.5 0.999

The study also prints the two-level Richardson values of zeta from the grids
(2h, h, h/2) and (h, h/2, h/4) and their difference.  ``--defaults`` times the default
call (``solve_cooling(alpha, method="fd")``: two Richardson levels over 2h, h, h/2)
against one grid of the default spacing h (the old default) and prints the error
estimates the result reports.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.solvers import fd_cooling as cooling  # noqa: E402
from kinetic_fem.solvers import spectral
from kinetic_fem.solvers.richardson import richardson_scalar  # noqa: E402


def f_rel(coarse: cooling.HCSSolution, fine: cooling.HCSSolution) -> float:
    """Max |f_coarse / f_fine - 1| on the coarse nodes where f > 1e-30."""
    ff = np.interp(coarse.grid.v, fine.grid.v, np.log(fine.f))
    keep = coarse.f > 1e-30
    return float(np.max(np.abs(np.exp(np.log(coarse.f[keep]) - ff[keep]) - 1.0)))


def a2(sol: cooling.HCSSolution) -> float:
    w = sol.grid.half_weights
    return float(np.dot(w, sol.grid.v**4 * sol.f) / 3.0 - 1.0)


def orders(d: list[float]) -> list[str]:
    return [""] + [f"{math.log2(d[i - 1] / d[i]):5.2f}" if d[i] > 0 else "" for i in
                   range(1, len(d))]


def study(alpha: float, levels: int) -> None:
    h0 = cooling.default_spacing(alpha)
    cut = cooling.default_cutoff(alpha)
    spacings = [2 * h0 / 2**k for k in range(levels)]
    cutoff = spacings[0] * math.ceil(cut / spacings[0])
    sols, walls = [], []
    for h in spacings:
        t0 = time.perf_counter()
        sols.append(cooling.solve_hcs(alpha, spacing=h, cutoff=cutoff))  # one grid each
        walls.append(time.perf_counter() - t0)
    print(f"\n=== alpha = {alpha}: default spacing {h0:.4g}, cut-off {cutoff:.3g} ===")
    print(f"{'spacing':>8} {'n':>5} {'it':>3} {'wall s':>7} {'zeta':>16} {'a2':>14} "
          f"{'energy id':>10} {'lambda':>9} {'f(0)/max f':>10}")
    for h, s, t in zip(spacings, sols, walls, strict=True):
        ident = s.zeta - s.energy_identity(alpha)
        print(f"{h:8.5f} {s.grid.n:5d} {s.iterations:3d} {t:7.2f} {s.zeta:16.12f} "
              f"{a2(s):14.10f} {ident / s.zeta:10.2e} {s.multiplier:9.1e} "
              f"{s.f[0] / s.f.max():10.6f}")
    dz = [abs(sols[i].zeta / sols[i + 1].zeta - 1) for i in range(levels - 1)]
    da = [abs(a2(sols[i]) - a2(sols[i + 1])) for i in range(levels - 1)]
    df = [f_rel(sols[i], sols[i + 1]) for i in range(levels - 1)]
    di = [abs(s.zeta - s.energy_identity(alpha)) / s.zeta for s in sols]
    print(f"{'h -> h/2':>9} {'dzeta/zeta':>11} {'ord':>5} {'|da2|':>10} {'ord':>5} "
          f"{'max df/f':>10} {'ord':>5}")
    for i, (a, b, c, oa, ob, oc) in enumerate(zip(dz, da, df, orders(dz), orders(da),
                                                  orders(df), strict=True)):
        print(f"{spacings[i]:9.5f} {a:11.2e} {oa:>5} {b:10.2e} {ob:>5} {c:10.2e} {oc:>5}")
    print("energy identity |zeta - (1-alpha^2)<g^3>/8|/zeta, observed orders: "
          + ", ".join(f"{x:.2e}" for x in di) + "  (" + ", ".join(o for o in orders(di) if o)
          + ")")
    # error of the default (index 1) estimated from Richardson with the finer grids
    p = 2.0
    zr = (2**p * sols[2].zeta - sols[1].zeta) / (2**p - 1)
    ar = (2**p * a2(sols[2]) - a2(sols[1])) / (2**p - 1)
    print(f"default spacing: estimated error zeta {abs(sols[1].zeta / zr - 1):.1e} (rel), "
          f"a2 {abs(a2(sols[1]) - ar):.1e} (abs), f {df[1]:.1e} (rel, vs h/2)")
    if levels >= 4:
        z_a, _ = richardson_scalar([s.zeta for s in sols[0:3]])
        z_b, _ = richardson_scalar([s.zeta for s in sols[1:4]])
        print(f"two Richardson levels: zeta = {z_a:.13f} (2h, h, h/2), {z_b:.13f} "
              f"(h, h/2, h/4), relative difference {abs(z_a / z_b - 1):.1e}; one grid of "
              f"spacing h misses zeta by {abs(sols[1].zeta / z_b - 1):.1e}")
    try:
        son, zeta_s = spectral.solve_sonine_cooling(alpha, 8)
        son6, _ = spectral.solve_sonine_cooling(alpha, 6)
        print(f"Sonine order 8: a2 = {son.coefficients[2]:.6f} (order 6: "
              f"{son6.coefficients[2]:.6f}), zeta = {zeta_s:.8f}; fd default: "
              f"a2 = {a2(sols[1]):.6f}, zeta = {sols[1].zeta:.8f}")
    except RuntimeError as exc:
        print(f"Sonine order 8 (or 6): no solution ({str(exc)[:60]}...)")


def defaults(alpha: float) -> None:
    """The default call (two levels) against one grid of the default spacing."""
    t0 = time.perf_counter()
    one = kf.solve_cooling(alpha, method="fd", richardson=0)
    t_one = time.perf_counter() - t0
    t0 = time.perf_counter()
    best = kf.solve_cooling(alpha, method="fd")
    t_best = time.perf_counter() - t0
    e = best.info.extra
    z1, zb = one.info.extra["zeta"], e["zeta"]
    print(f"alpha={alpha}: one grid h={one.info.extra['spacing']:.4g}: zeta={z1:.12f} "
          f"({t_one:.1f} s); default (2 levels, spacings "
          f"{', '.join(f'{h:.4g}' for h in e['spacings'])}): zeta={zb:.13f} "
          f"({t_best:.1f} s), one-grid error {abs(z1 / zb - 1):.1e}; estimated errors of "
          f"the default: zeta {e['estimated_error_zeta']:.1e}, a2 "
          f"{e['estimated_error_a2']:.1e}, f {e['estimated_error_f']:.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+", default=[0.0, 0.5, 0.85, 0.99])
    parser.add_argument("--levels", type=int, default=4)
    parser.add_argument("--defaults", action="store_true",
                        help="time and check the default call instead of the study")
    args = parser.parse_args()
    if args.defaults:
        for alpha in args.alphas:
            defaults(alpha)
        return
    for alpha in args.alphas:
        study(alpha, args.levels)


if __name__ == "__main__":
    main()
