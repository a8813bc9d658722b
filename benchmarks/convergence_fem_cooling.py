"""Mesh convergence of the FEM homogeneous cooling state (issue 10, parts 2 and 3).

Near elastic collisions (``--eps``): the continuation states of
:func:`kinetic_fem.solvers.fem.cooling.cooling_state` are computed once (0.07 hump
widths), then each state of the table is solved from the previous continuation state on
hump meshes of decreasing ``resolution`` (element size in hump widths eps^(1/3)); zeta,
a2 and ln f (where f > 1e-30) are compared with the finest mesh, with observed orders
``log(e1/e2)/log(r1/r2)``, the two-level error estimate (``CoolingState.error_estimate``,
max over elements where f > 1e-30) beside the true error, and the CPU time of each solve.
Moderate inelasticity (``--alphas``): the bulk spacing is halved as before, with the FD
cooling state beside.

    python benchmarks/convergence_fem_cooling.py --eps 1e-2 1e-3 [--alphas 0.5 0.85]

Timings: CPU seconds of one process (OPENBLAS_NUM_THREADS=1) on a machine shared with other jobs:
compare them within one run only.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.solvers.fem import cooling as fc  # noqa: E402

FLOOR = math.log(1e-30)
INTORDER: int | None = None
"""Gauss degree of the hump meshes (None: the default, fem_cooling_mesh.HUMP_INTORDER)."""


def _ln_f_error(state, ref) -> tuple[float, float, float]:
    """(max |ln f - ln f_ref| where f_ref > 1e-30, max two-level estimate there
    (:meth:`CoolingState.error_estimate`), true/estimate)."""
    verts = state.disc.vertices
    pts = np.linspace(0.0, 1.0, 9)[1:-1]
    true_el = np.zeros(verts.size - 1)
    for k, (a, b) in enumerate(zip(verts[:-1], verts[1:], strict=True)):
        c = a + (b - a) * pts
        lr = ref.log_f(c)
        keep = lr > FLOOR
        if keep.any():
            true_el[k] = np.abs(state.log_f(c)[keep] - lr[keep]).max()
        else:
            true_el[k] = np.nan
    eta, _ = state.error_estimate()
    watched = np.isfinite(true_el)
    return (float(np.nanmax(true_el)), float(eta[watched].max()),
            float(np.nanmax(true_el) / eta[watched].max()))


def chain_states(eps_min: float) -> dict[float, fc.CoolingState]:
    """The continuation states down to ``eps_min`` (the default path's intermediates)."""
    prev, eps_prev = fc.hump_start(2, None), fc.HUMP_EPS
    states = {eps_prev: prev}
    for eps in fc.hump_chain(eps_min)[:-1]:
        t0 = time.process_time()
        prev = fc.continued_state(prev, eps_prev, eps, resolution=fc.HUMP_STEP_RESOLUTION,
                                  tol=fc.HUMP_STEP_TOL)
        print(f"  chain eps {eps:.3g}: {prev.u.size} dofs, {prev.info.iterations} Newton, "
              f"{time.process_time() - t0:.1f} s CPU, converged {prev.info.converged}",
              flush=True)
        if not prev.info.converged:
            raise SystemExit(f"continuation failed at eps = {eps}: {prev.info.message}")
        states[eps] = prev
        eps_prev = eps
    return states


def hump_study(eps: float, states: dict[float, fc.CoolingState],
               resolutions: list[float]) -> list[tuple[float, fc.CoolingState, float]]:
    start_eps = min(e for e in states if e >= eps * (1 - 1e-12) and e > eps) \
        if any(e > eps for e in states) else fc.HUMP_EPS
    prev = states[start_eps]
    runs = []
    for r in resolutions:
        t0 = time.process_time()
        st = fc.continued_state(prev, start_eps, eps, resolution=r, intorder=INTORDER)
        runs.append((r, st, time.process_time() - t0))
    ref = runs[-1][1]
    dists = [st.disc.distribution(st.u) for _, st, _ in runs]
    z_ref, a_ref = ref.zeta, dists[-1].a2
    print(f"\neps = {eps:g} (alpha = {1 - eps}); from the state at eps = {start_eps:.3g}; "
          f"reference: resolution {resolutions[-1]}")
    print(f"{'res':>6} {'dofs':>6} {'it':>3} {'cpu/s':>7} {'zeta/eps':>19} {'|dz|/z':>9} "
          f"{'ord':>5} {'a2':>16} {'|da2|':>9} {'ord':>5} {'ln f err':>9} {'ord':>5} "
          f"{'estimate':>9} {'true/est':>8} {'identity':>9}")
    prev_err: tuple[float, ...] | None = None
    prev_r = resolutions[0]
    for (r, st, wall), dist in zip(runs, dists, strict=True):
        last = st is ref
        ez, ea = abs(st.zeta / z_ref - 1), abs(dist.a2 - a_ref)
        ef, ind, rel = _ln_f_error(st, ref) if not last else (math.nan, math.nan, math.nan)
        errs = (ez, ea, ef)
        orders = ["" if prev_err is None or last or e == 0 or p == 0 else
                  f"{math.log(p / e) / math.log(prev_r / r):5.2f}"
                  for e, p in zip(errs, prev_err or errs, strict=True)]
        ident = abs(st.energy_identity() / st.zeta - 1)
        shown = ["(ref)"] * 3 if last else [f"{e:9.2e}" for e in errs]
        print(f"{r:6.3f} {st.u.size:6d} {st.info.iterations:3d} {wall:7.1f} "
              f"{st.zeta / eps:19.15f} {shown[0]:>9} {orders[0]:>5} {dist.a2:16.12f} "
              f"{shown[1]:>9} {orders[1]:>5} {shown[2]:>9} {orders[2]:>5} {ind:9.2e} "
              f"{'' if last else f'{rel:8.2f}':>8} {ident:9.1e}", flush=True)
        prev_err, prev_r = errs, r
    return runs


def moderate_study(alpha: float, spacings: list[float]) -> None:
    runs = []
    for h in spacings:
        t0 = time.perf_counter()
        dist = kf.solve_cooling(alpha, spacing=h)
        runs.append((h, dist, time.perf_counter() - t0))
    ref = runs[-1][1]
    z_ref, a_ref = ref.info.extra["zeta"], ref.a2
    print(f"\nalpha = {alpha}  (P2; reference: spacing {spacings[-1]})")
    print(f"{'spacing':>8} {'n_dofs':>7} {'iter':>5} {'time/s':>7} {'zeta':>18} {'|dz|/z':>9} "
          f"{'ord':>5} {'a2':>15} {'|da2|':>9} {'ord':>5} {'identity':>9}")
    prev = None
    for h, dist, wall in runs:
        zeta = dist.info.extra["zeta"]
        err = (abs(zeta / z_ref - 1), abs(dist.a2 - a_ref))
        ident = abs(dist.info.extra["zeta_identity"] / zeta - 1)
        last = dist is ref
        orders = ["" if prev is None or last or e == 0 else f"{math.log2(p / e):5.2f}"
                  for e, p in zip(err, prev or err, strict=True)]
        errs = ["(ref)"] * 2 if last else [f"{e:9.2e}" for e in err]
        print(f"{h:8.4f} {dist.info.extra['n_dofs']:7d} {dist.info.iterations:5d} {wall:7.1f} "
              f"{zeta:18.14f} {errs[0]:>9} {orders[0]:>5} {dist.a2:15.11f} {errs[1]:>9} "
              f"{orders[1]:>5} {ident:9.1e}")
        prev = err
    t0 = time.perf_counter()
    fd = kf.solve_cooling(alpha, method="fd")
    print(f"FD (default grid, {time.perf_counter() - t0:.1f} s): zeta {fd.info.extra['zeta']:.14f}"
          f" ({fd.info.extra['zeta'] / z_ref - 1:.1e}), a2 {fd.a2:.11f} ({fd.a2 - a_ref:.1e})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="*", default=[])
    parser.add_argument("--eps", type=float, nargs="*", default=[1e-2, 1e-3])
    parser.add_argument("--resolutions", type=float, nargs="*",
                        default=[0.14, 0.1, 0.07, 0.05, 0.035])
    parser.add_argument("--quick", action="store_true", help="three meshes")
    parser.add_argument("--intorder", type=int, default=None,
                        help="Gauss degree of the hump meshes (default HUMP_INTORDER)")
    args = parser.parse_args()
    global INTORDER
    INTORDER = args.intorder
    if args.eps:
        t0 = time.perf_counter()
        states = chain_states(min(args.eps))
        print(f"continuation states: {time.perf_counter() - t0:.1f} s")
        res = args.resolutions[-3:] if args.quick else args.resolutions
        for eps in args.eps:
            hump_study(eps, states, res)
    spacings = [0.2, 0.1, 0.05] if args.quick else [0.2, 0.1, 0.05, 0.025]
    for alpha in args.alphas:
        moderate_study(alpha, spacings)


if __name__ == "__main__":
    main()
