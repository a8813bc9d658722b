"""Peak of the effective exponent n(c) of the heated steady state against eps (F6, C6, C7).

The paper (C7): n(v) = d ln(-ln(P/P0))/d ln v peaks at v* ~ eps^(-1/3) with
3 - n* ~ eps^(1/3); C6: the peak sits at a fixed multiple of v_cr1 = (D/(n eps))^(1/3),
i.e. x* = v* eps^(1/3) constant (n = D = 1).

Two methods, overlapping at eps = 1e-3:

* eps = 1e-1 ... 1e-3 (``--fem-eps``): FEM (P2, log unknown, Newton;
  ``kinetic_fem.analysis.peak_study.peak_sweep(method="fem")``) with the cut-off moved
  beyond the default, spacings 0.05 and 0.035 (thermal velocities), Gauss degree 9, two
  cut-offs per eps.  A peak counts as converged if it is interior and x* moves by < 1 %
  and n* by < 1e-3 between spacings and cut-offs.
* eps = 1e-3 ... 1e-6 (``--tail-eps``): the tail equation in log variables
  (``kinetic_fem.analysis.heated_tail``) on the FEM bulk, matched at ln(P/P0) = -30.
  The peak lies at ln(P/P0) ~ -240 at eps = 1e-4 and ~ -3900 (f ~ 1e-1700) at 1e-6,
  below the double-precision range the FEM weak form (which evaluates P = e^u) can
  reach.  Checks per eps: FEM bulk at the default spacing and at the default / sqrt 2,
  tail grid 0.1 and 0.05, matching depth -30 and -40 with a 25 % longer grid;
  converged if x* moves by < 0.1 % and n* by < 1e-3 of 3 - n*.

Error bars are the largest change of the peak between these resolutions, carried
through the two-point exponents.  The last table compares with the two-term
quasi-elastic expansion n(x) = n_phi(x) - (3/16) eps x^3
(``kinetic_fem.analysis.heated_tail.quasi_elastic_peak``), whose peak is
x* ~ (64 <x^2>/(3 eps))^(1/5): v* ~ eps^(-8/15), 3 - n* ~ eps^(2/5).

Usage: python benchmarks/effective_exponent_peak.py [--fem-eps 0.1 ...] [--tail-eps ...]

Measured results: benchmarks/results/heated_near_elastic.md.
"""

from __future__ import annotations

import argparse
import functools
import math
import time

import numpy as np

from kinetic_fem.analysis.heated_tail import quasi_elastic_peak, tail_sweep
from kinetic_fem.analysis.peak_study import (
    FEM_PEAK_SPACINGS,
    combine_sweeps,
    peak_sweep,
)
from kinetic_fem.solvers.fem import heated as fem

FEM_EPS = (0.1, 0.03, 0.01, 3e-3, 1e-3)
TAIL_EPS = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6)


def _print_sweep(title: str, sweep) -> None:
    print(f"\n{title}: tolerances x* {sweep.x_tol:g} (relative), n* {sweep.n_tol:g}")
    print(f"{'eps':>8} {'c*':>9} {'v*':>10} {'x*':>9} {'n*':>9} {'3-n*':>9} "
          f"{'dx(mesh)':>9} {'dx(cut)':>9} {'dn(mesh)':>9} {'dn(cut)':>9}  ok")
    others = sweep.other_cutoff or sweep.coarse
    for p, pc, po, ok in zip(sweep.peaks, sweep.coarse, others, sweep.converged,
                             strict=True):
        print(f"{p.eps:8.0e} {p.c:9.5f} {p.v:10.4f} {p.x:9.5f} {p.n:9.6f} {3 - p.n:9.6f} "
              f"{pc.x / p.x - 1:9.1e} {po.x / p.x - 1:9.1e} {pc.n - p.n:9.1e} "
              f"{po.n - p.n:9.1e}  {'yes' if ok else 'NO'}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fem-eps", type=float, nargs="*", default=FEM_EPS)
    ap.add_argument("--tail-eps", type=float, nargs="*", default=TAIL_EPS)
    args = ap.parse_args(argv)
    start = time.perf_counter()

    def log(msg: str) -> None:
        print(f"[{time.perf_counter() - start:7.1f} s] {msg}", flush=True)

    @functools.lru_cache(maxsize=None)
    def bulk(alpha: float, spacing: float):
        t = time.perf_counter()
        state = fem.steady_state(alpha, spacing=spacing)
        log(f"FEM bulk alpha=1-{1 - alpha:.0e} h={spacing:.4g}: "
            f"{state.disc.dof_locations.size} dofs, {time.perf_counter() - t:.1f} s")
        return state

    sweeps = []
    if args.fem_eps:
        fsweep = peak_sweep(tuple(args.fem_eps), spacing=FEM_PEAK_SPACINGS[0], method="fem",
                            fine_spacing=FEM_PEAK_SPACINGS[1], intorder=9, log=log)
        _print_sweep(f"FEM P2, Gauss degree 9, spacings {FEM_PEAK_SPACINGS}", fsweep)
        sweeps.append(fsweep)
    if args.tail_eps:
        tsweep = tail_sweep(tuple(args.tail_eps), bulk=bulk, log=log)
        _print_sweep("tail equation on the FEM bulk (bulk h0, h0/sqrt2; tail h 0.1, 0.05; "
                     "match -30/-40)", tsweep)
        sweeps.append(tsweep)
        if args.fem_eps:
            fem_peaks = {p.eps: p for p in sweeps[0].selected()}
            for p in tsweep.selected():
                if p.eps in fem_peaks:
                    f = fem_peaks[p.eps]
                    print(f"\noverlap at eps = {p.eps:g}: FEM x* = {f.x:.5f}, n* = {f.n:.6f}; "
                          f"tail x* = {p.x:.5f}, n* = {p.n:.6f} (x* differ by "
                          f"{p.x / f.x - 1:+.1e}, n* by {p.n - f.n:+.1e})")
    both = combine_sweeps(*sweeps)
    if len(both.peaks) < 2:
        return
    tail_eps = set(args.tail_eps or ())
    print("\ncombined (the tail solver where it ran, FEM above), with the two-term "
          "quasi-elastic prediction:")
    print(f"{'eps':>8} {'method':>6} {'v*':>10} {'x*':>9} {'+-dx/x':>8} {'n*':>9} "
          f"{'+-dn':>8} {'x*(th)':>9} {'n*(th)':>9} {'x*/x*(th)-1':>12}")
    for p, (dv, dn) in zip(both.peaks, both.errors(), strict=True):
        xt, nt = quasi_elastic_peak(p.eps)
        meth = "tail" if p.eps in tail_eps else "fem"
        print(f"{p.eps:8.0e} {meth:>6} {p.v:10.4f} {p.x:9.5f} {dv:8.1e} {p.n:9.6f} "
              f"{dn:8.1e} {xt:9.4f} {nt:9.6f} {p.x / xt - 1:+12.2e}")
    eps = np.array([p.eps for p in both.peaks])
    v_exp, n_exp = both.fits()
    print(f"\nleast squares over eps = {eps.max():g} ... {eps.min():g}: "
          f"v* ~ eps^{v_exp:+.4f}, 3 - n* ~ eps^{n_exp:+.4f}")
    print("\nlocal (two-point) exponents with error bars from the resolution checks; "
          "asymptotic theory: v* -8/15 = -0.5333, x* -1/5, 3 - n* +2/5")
    print(f"{'eps1':>8} {'eps2':>8} {'v*':>8} {'+-':>7} {'x*':>8} {'3-n*':>8} {'+-':>7} "
          f"{'v*(th)':>8} {'3-n*(th)':>9}")
    for (e1, e2, ve, ne), (dve, dne) in zip(both.local(), both.local_errors(), strict=True):
        le = math.log(e2 / e1)
        (xa, na), (xb, nb) = quasi_elastic_peak(e1), quasi_elastic_peak(e2)
        vt = math.log(xb / xa) / le - 1 / 3
        nt = math.log((3 - nb) / (3 - na)) / le
        print(f"{e1:8.0e} {e2:8.0e} {ve:+8.4f} {dve:7.1e} {ve + 1 / 3:+8.4f} "
              f"{ne:+8.4f} {dne:7.1e} {vt:+8.4f} {nt:+9.4f}")
    print(f"\ntotal wall time {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
