"""Mesh convergence of the hard-rod cooling state in the band eps in [0.035, 0.1) (issue 16).

For each eps the link state of :func:`kinetic_fem.solvers.fem.cooling_band.band_state`
is computed once; the P3 state (Gauss degree ``BAND_INTORDER``) is then solved from it on
:func:`~kinetic_fem.solvers.fem.cooling_band.band_vertices` with the element size in the
humps and the e-folds per tail element both scaled by ``s`` (``s = 1``: the default), and
compared with P3 at 0.05 hump widths on the near-elastic hump mesh (Gauss degree 9,
``continued_state``): zeta relative, a2 absolute, ln f where f_ref > 1e-30, with observed
orders ``log(e1/e2)/log(s1/s2)``.

    python benchmarks/convergence_fem_cooling_band.py [--eps 0.07 0.05 0.035]
        [--scales 2 1.41 1 0.71 0.5]

Prints markdown tables (``benchmarks/archive/results/fem_cooling_band_speed.md``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from kinetic_fem.solvers.fem import cooling as fc  # noqa: E402
from kinetic_fem.solvers.fem import cooling_band as fb  # noqa: E402
from kinetic_fem.solvers.fem.cooling_newton import CLOSE_DAMPING, newton_cooling  # noqa: E402
from kinetic_fem.solvers.fem.heated import FEMDiscretisation  # noqa: E402

FLOOR = math.log(1e-30)


def errors(state: fc.CoolingState, ref: fc.CoolingState) -> tuple[float, float, float]:
    """(|zeta/zeta_ref - 1|, |a2 - a2_ref|, max |ln f - ln f_ref| where f_ref > 1e-30)."""
    c = np.linspace(0.0, 0.99 * min(state.disc.vertices[-1], ref.disc.vertices[-1]), 40001)
    lr = ref.log_f(c)
    keep = lr > FLOOR
    a2 = state.disc.distribution(state.u).a2
    a2_ref = ref.disc.distribution(ref.u).a2
    return (abs(state.zeta / ref.zeta - 1.0), abs(a2 - a2_ref),
            float(np.abs(state.log_f(c)[keep] - lr[keep]).max()))


def study(eps: float, scales: list[float]) -> None:
    link = fc.continued_state(fc.link_start(2, None), fc.HUMP_EPS, eps,
                              resolution=fb.HUMP_FAST_LINK, order=2, intorder=5,
                              tol=fc.HUMP_STEP_TOL, decades=fb.HUMP_LINK_DECADES)
    runs = []
    for s in scales:
        verts = fb.band_vertices(eps, link.log_f, resolution=s * fb.BAND_RESOLUTION,
                                 efolds=s * fb.BAND_EFOLDS)
        disc = FEMDiscretisation(1.0 - eps, verts, 3, fb.BAND_INTORDER, gamma=1.0)
        t0 = time.process_time()
        st = newton_cooling(disc, link.log_f(disc.dof_locations), link.zeta, tol=1e-11,
                            max_iter=100, pseudo_time=np.inf, min_damping=CLOSE_DAMPING)
        runs.append((s, st, time.process_time() - t0))
    ref = fc.continued_state(runs[-1][1], eps, eps, resolution=0.05, order=3)
    print(f"\neps = {eps:g}: reference P3 at 0.05 hump widths ({ref.u.size} dofs, Gauss "
          f"degree {ref.disc.intorder}), zeta/eps = {ref.zeta / eps:.16f}, a2 = "
          f"{ref.disc.distribution(ref.u).a2:.16f}\n")
    print("| s | dofs | CPU s | dzeta | order | da2 | order | d ln f | order |")
    print("|---|---|---|---|---|---|---|---|---|")
    prev = None
    for s, st, cpu in runs:
        errs = errors(st, ref)
        orders = [""] * 3
        if prev is not None:
            orders = ["" if e == 0 or p == 0 else f"{math.log(p / e) / math.log(prev[0] / s):.2f}"
                      for e, p in zip(errs, prev[1], strict=True)]
        print(f"| {s:g} | {st.u.size} | {cpu:.2f} | {errs[0]:.1e} | {orders[0]} | "
              f"{errs[1]:.1e} | {orders[1]} | {errs[2]:.1e} | {orders[2]} |", flush=True)
        prev = (s, errs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--eps", type=float, nargs="*", default=[0.07, 0.05, 0.035])
    parser.add_argument("--scales", type=float, nargs="*", default=[2.0, 1.41, 1.0, 0.71, 0.5])
    args = parser.parse_args()
    for eps in args.eps:
        study(eps, args.scales)


if __name__ == "__main__":
    main()
