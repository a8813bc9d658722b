"""Heated FEM state near the elastic limit: approach to the quasi-elastic phi state.

At ``n = D = 1`` write :math:`x = \\varepsilon^{1/3} v` and :math:`P(v) = \\varepsilon^{1/3}
\\phi_\\varepsilon(x)`.  In the strong form :math:`P'' + Q[P] = 0`, with
:math:`Q[P](v) = \\int dy |v-y| P(y) [P(v + \\delta(v-y))/b^2 - P(v)]`,
:math:`\\delta = \\varepsilon/(2-\\varepsilon)`, :math:`b = 1 - \\varepsilon/2`, expand the gain in
the shift :math:`s = \\delta(v - y)`: the k-th term carries :math:`(v-y)^k\\partial_v^k`,
which is invariant under :math:`v \\to x`.  Divided by :math:`\\varepsilon`, the coefficients
are :math:`(b^{-2}-1)/\\varepsilon = 1 + \\tfrac34\\varepsilon + \\dots` (k = 0),
:math:`\\delta/(\\varepsilon b^2) = \\tfrac12 + \\tfrac34\\varepsilon + \\dots` (k = 1) and
:math:`\\delta^k/(k!\\,\\varepsilon b^2) = O(\\varepsilon^{k-1})` (k >= 2): the phi equation
plus integer powers of eps.  The tail where the expansion fails
(:math:`x \\sim \\varepsilon^{-1/3}`) carries the weight :math:`e^{-1/(6\\varepsilon)}`.  Hence
:math:`\\phi_\\varepsilon = \\phi + O(\\varepsilon)` at fixed x and
:math:`a_2(\\varepsilon) - a_2^\\phi = k_1\\varepsilon + O(\\varepsilon^2)`: rate 1, neither 1/3
nor 2/3 (the cooling state differs: its humps have width eps^(1/3)).

Prints, for eps = 1e-1 ... 1e-6 (half decades), the FEM state with default options and
with the spacing refined by sqrt 2: Newton's report, a2, a2 - a2(phi), the two-point
exponents of a2 - a2(phi) with error bars from the refinement, (a2 - a2(phi))/eps, and
max |ln(phi_eps(x)/phi(x))| over |x| <= 3 (where eps x^3 < 1 for eps < 0.04) and the L1
distance of phi_eps from phi, with their exponents.

Usage: python benchmarks/heated_near_elastic.py [--eps 0.1 ...] [--no-refine]

Measured results: benchmarks/results/heated_near_elastic.md.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from kinetic_fem.solvers.fem import heated as fem
from kinetic_fem.solvers.fem.defaults import default_spacing
from kinetic_fem.solvers.scaling import solve_phi

EPS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6)
X_MAX = 3.0


def phi_distance(state, phi) -> float:
    """max |ln(phi_eps(x) / phi(x))| over |x| <= X_MAX, phi_eps the FEM state on x."""
    eps = 1.0 - float(state.disc.alpha)
    x = phi.x[(phi.x >= 0) & (phi.x <= X_MAX)]
    scale = eps ** (1.0 / 3.0)
    lnp = np.log(state.disc.evaluate(state.u, x / scale)) - math.log(scale)
    lnphi = np.log(phi.distribution.values[(phi.x >= 0) & (phi.x <= X_MAX)])
    return float(np.abs(lnp - lnphi).max())


def phi_l1(state, phi) -> float:
    """L1 distance of phi_eps from phi over the grid of phi (|x| <= 7)."""
    from kinetic_fem.operators.grid import simpson_weights

    eps = 1.0 - float(state.disc.alpha)
    scale = eps ** (1.0 / 3.0)
    x = phi.x
    order = np.argsort(x)
    p = np.empty_like(x)
    p[order] = state.disc.evaluate(state.u, x[order] / scale) / scale
    return float(np.sum(simpson_weights(x) * np.abs(p - phi.distribution.values)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--eps", type=float, nargs="+", default=EPS)
    ap.add_argument("--no-refine", action="store_true")
    args = ap.parse_args(argv)
    start = time.perf_counter()
    phi = solve_phi(n_v=2801)
    print(f"phi: a2 = {phi.a2:.12f} (+- {phi.errors['a2']:.1e}), <x^2> = {phi.x2:.10f}")
    rows = []
    for eps in sorted(args.eps, reverse=True):
        alpha = 1.0 - eps
        h0 = default_spacing(alpha)
        t = time.perf_counter()
        st = fem.steady_state(alpha)
        dt = time.perf_counter() - t
        d = st.disc.distribution(st.u)
        err, d_phi_fine = math.nan, math.nan
        if not args.no_refine:
            fine = fem.steady_state(alpha, spacing=h0 / math.sqrt(2.0))
            err = abs(fine.disc.distribution(fine.u).a2 - d.a2)
            d_phi_fine = phi_distance(fine, phi)
        dist_phi = phi_distance(st, phi)
        l1 = phi_l1(st, phi)
        rows.append((eps, d.a2, err, dist_phi, l1))
        print(f"eps={eps:7.0e} h={h0:.4f} dofs={st.disc.dof_locations.size:5d} {dt:6.1f} s  "
              f"a2={d.a2:.12f} |a2(h)-a2(h/sqrt2)|={err:.1e} "
              f"max|ln phi_eps/phi|={dist_phi:.3e} (refined {d_phi_fine:.3e}) L1={l1:.3e}; "
              f"{st.info.message.split(';')[0][:90]}", flush=True)
    print(f"\n{'eps':>8} {'a2':>16} {'a2-a2(phi)':>12} {'+-':>8} {'/eps':>9} "
          f"{'slope':>7} {'+-':>6} {'lnphi dist':>11} {'slope':>7} {'L1':>10} {'slope':>7}")
    prev = None
    for eps, a2, err, dist_phi, l1 in rows:
        diff = a2 - phi.a2
        slope = dslope = dslope_phi = slope_l1 = math.nan
        if prev is not None:
            le = math.log(eps / prev[0])
            slope = math.log(diff / (prev[1] - phi.a2)) / le
            dslope = (err / abs(diff) + prev[2] / abs(prev[1] - phi.a2)) / abs(le)
            dslope_phi = math.log(dist_phi / prev[3]) / le
            slope_l1 = math.log(l1 / prev[4]) / le
        print(f"{eps:8.0e} {a2:16.12f} {diff:12.5e} {err:8.1e} {diff / eps:9.5f} "
              f"{slope:7.4f} {dslope:6.3f} {dist_phi:11.3e} {dslope_phi:7.4f} {l1:10.3e} "
              f"{slope_l1:7.4f}")
        prev = (eps, a2, err, dist_phi, l1)
    print(f"\ntotal {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
