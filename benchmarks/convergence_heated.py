"""Mesh convergence of the FEM heated steady state (issue 3, part 4).

For each alpha the mesh is refined (element size ``spacing`` in thermal velocities,
halved each time) and T, a2, f(c) are compared with the finest mesh; observed
orders are ``log2`` of successive error ratios.  Also printed: the energy balance
C1 (2D against the pair-quadrature loss), the solver's own discrete identity, the
smallest resolved f(c), and the far-tail slope of ln f against c^(3/2) beside the
predicted amplitude (claim C4).

    python benchmarks/convergence_heated.py [--quick] [--order 2] [--alphas 0 0.9]

``--order 3``: P3 (the default of ``kf.solve_heated`` for this model, at 2-2.5 times the P2
default spacing) on meshes 1.5 times coarser than P2's.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # dense LU; avoid oversubscription

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from kinetic_fem import sonine  # noqa: E402
from kinetic_fem.operators.collision import energy_balance  # noqa: E402
from kinetic_fem.solvers.fem import heated as fem  # noqa: E402

ALPHAS = (0.0, 0.1, 0.6, 0.9, 0.99, 0.999)


def scaled_f(state: fem.SteadyState, c: np.ndarray) -> tuple[np.ndarray, float, float]:
    """f(c) of the FE field (exact evaluation of exp(u_h)), T and a2."""
    dist = state.disc.distribution(state.u)
    s = math.sqrt(dist.temperature)
    return s * state.disc.evaluate(state.u, c * s), dist.temperature, dist.a2


def tail_slope(state: fem.SteadyState, temperature: float) -> tuple[float, float]:
    """Slope of ln f against c^(3/2) over the last two decades-ish above 1e-30."""
    dist = state.disc.distribution(state.u)
    c, f = dist.c, dist.f_values
    keep = (c > 0) & (f > 1e-30)
    c_end = c[keep].max()
    sel = keep & (c > 0.8 * c_end)
    slope = np.polyfit(c[sel] ** 1.5, np.log(f[sel]), 1)[0]
    return -slope, c_end


def study(alpha: float, spacings: list[float], order: int, symmetric: bool) -> None:
    states, times = [], []
    for h in spacings:
        t0 = time.perf_counter()
        states.append(fem.steady_state(alpha, order=order, spacing=h, symmetric=symmetric))
        times.append(time.perf_counter() - t0)
    ref = states[-1]
    dist_ref = ref.disc.distribution(ref.u)
    c_ref = dist_ref.c
    f_ref = dist_ref.f_values
    keep = (f_ref > 1e-30) & (np.abs(c_ref) < 0.999 * min(np.abs(s.disc.vertices).max()
                                                         for s in states) / math.sqrt(
                                                             dist_ref.temperature))
    c_cmp = c_ref[keep]
    bracket = "full" if symmetric else "reduced"
    print(f"\nalpha = {alpha}   P{order}, {bracket} bracket   cut-off c = "
          f"{ref.disc.vertices[-1] / math.sqrt(dist_ref.temperature):.2f}   "
          f"f compared on {keep.sum()} points, |c| <= {np.abs(c_cmp).max():.2f}, "
          f"f >= {f_ref[keep].min():.1e}")
    print(f"{'spacing':>8} {'n_dofs':>7} {'newton':>6} {'time/s':>7} {'T':>18} {'|dT|/T':>9} "
          f"{'ord':>5} {'a2':>14} {'|da2|':>9} {'ord':>5} {'max|df/f|':>9} {'ord':>5} "
          f"{'C1 rel':>9} {'own id':>9}")
    prev = None
    for h, st, wall in zip(spacings, states, times, strict=True):
        f, temp, a2 = scaled_f(st, c_cmp)
        err = (abs(temp / dist_ref.temperature - 1), abs(a2 - dist_ref.a2),
               float(np.max(np.abs(f / f_ref[keep] - 1))))
        dist = st.disc.distribution(st.u)
        c1 = energy_balance(dist.v, dist.values, st.disc.points[1], alpha=alpha,
                            density=1.0, diffusion=1.0).relative_residual
        inj, loss = st.energy_terms()
        own = abs(inj - loss) / 2.0
        orders = ["" if prev is None or st is ref or e == 0 or p == 0
                  else f"{math.log2(p / e):5.2f}" for e, p in zip(err, prev or err, strict=True)]
        if st is ref:
            err_s = ["(ref)"] * 3
        else:
            err_s = [f"{e:9.2e}" for e in err]
        print(f"{h:8.4f} {st.u.size:7d} {st.info.iterations:6d} {wall:7.2f} {temp:18.12f} "
              f"{err_s[0]:>9} {orders[0]:>5} {a2:14.10f} {err_s[1]:>9} {orders[1]:>5} "
              f"{err_s[2]:>9} {orders[2]:>5} {c1:9.1e} {own:9.1e}")
        prev = err
    amp, c_end = tail_slope(ref, dist_ref.temperature)
    pred = sonine.tail_exponent_amplitude(temperature=dist_ref.temperature)
    print(f"far tail: fitted A_c = {amp:.4f} on c in [{0.8 * c_end:.1f}, {c_end:.1f}]  "
          f"predicted (C4) A_c = (2/3) T^(3/4) = {pred:.4f}  ratio {amp / pred:.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="three coarse meshes only")
    parser.add_argument("--order", type=int, default=2)
    parser.add_argument("--alphas", type=float, nargs="*", default=list(ALPHAS))
    parser.add_argument("--symmetric", action="store_true", help="full collision bracket")
    args = parser.parse_args()
    spacings = [0.4, 0.2, 0.1] if args.quick else [0.4, 0.2, 0.1, 0.05, 0.025]
    if args.order == 1:
        spacings = [s / 4 for s in spacings]
    elif args.order == 3:  # P3 (the default for this model): 1.5 times the P2 sizes
        spacings = [round(1.5 * s, 9) for s in spacings]
    for alpha in args.alphas:
        # near-elastic: Newton from the continuation guess needs spacing <= 0.2
        sp = [s / 2 for s in spacings] if alpha >= 0.99 else spacings
        if alpha >= 0.99 and args.order == 3:  # P3 from the continuation: spacing <= 0.15
            sp = [s / 4 for s in spacings][:-1]
        study(alpha, sp, args.order, args.symmetric)


if __name__ == "__main__":
    main()
