"""Memory effects of the heated gas: converged Kovacs hump and Mpemba threshold.

Three parts (``--part``):

* ``kovacs``: the hard-rod Kovacs hump (:func:`kinetic_fem.analysis.memory_effects.kovacs`,
  D0 = 1 -> D1 = 1e-3 for the first-Sonine t_w of T_st(0.1), then the D2 with
  T_st(D2) = T(t_w)) on a table of mesh spacings and tolerances: extremum of
  T/T_st - 1 after the switch, its time, the restart mismatch and the wall time,
  beside the first-Sonine hump;
* ``kovacs-dsmc``: DSMC ensembles of the exact protocol from the exact steady state;
  T(t) against the FEM curve at every output time (z-scores) and the DSMC hump;
* ``mpemba``: the Mpemba threshold (hot 1.5 T_st against a Gaussian at 1.4 T_st,
  crossed by 4 first-Sonine relaxation times): first Sonine, exact (FEM secant) and
  DSMC (T_hot - T_cold at the horizon for three a2, linear fit, root with its error).

Run: ``python benchmarks/memory_effects.py --part kovacs --alpha 0.3
[--grid 0.5:1e-4 0.25:1e-6 ...]``.
"""

from __future__ import annotations

import argparse
import math
import pickle
import time

import numpy as np

from kinetic_fem.analysis.memory_effects import kovacs, sonine_distribution
from kinetic_fem.analysis.mpemba import mpemba_threshold
from kinetic_fem.analysis.sonine_dynamics import sonine_relaxation_rates
from kinetic_fem.model.protocol import Protocol, steps
from particles.dsmc_transient import simulate_protocol


def kovacs_table(alpha: float, grid: list[tuple[float, float]], save: str | None = None) -> None:
    """Hump extremum against spacing and rtol (the last result pickled to ``save``)."""
    print(f"Kovacs, hard rods, alpha = {alpha}: D0 = 1 -> D1 = 1e-3 -> D2 = D0 (T(t_w)/T0)^(3/2)")
    print("| spacing | rtol | hump | t - t_w | t_w | D2 | restart mismatch | first Sonine | "
          "CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for spacing, rtol in grid:
        start = time.process_time()
        k = kovacs(alpha, spacing=spacing, rtol=rtol)
        print(f"| {spacing} | {rtol:g} | {k.hump:+.6e} | {k.hump_time:.4f} | "
              f"{k.waiting_time:.5f} | {k.diffusion[2]:.6f} | {k.restart_mismatch:+.1e} | "
              f"{k.sonine_hump:+.4e} | {time.process_time() - start:.0f} |", flush=True)
    if save:
        with open(save, "wb") as fh:
            pickle.dump(k, fh)


def kovacs_dsmc(alpha: float, spacing: float, rtol: float, n_particles: int, replicas: int,
                seed: int, load: str | None = None, own_d2: bool = False) -> None:
    """DSMC of the exact protocol against the FEM curve (loaded from ``load`` if given).

    ``own_d2``: switch to the D2 whose steady temperature is the DSMC ensemble's own
    T(t_w) and compare deviations from T_st(D2) (needed where the FEM T(t_w) and the
    DSMC one differ by more than the hump's error bar).
    """
    if load:
        with open(load, "rb") as fh:
            k = pickle.load(fh)
        alpha = k.alpha
    else:
        k = kovacs(alpha, spacing=spacing, rtol=rtol)
    start, wall = time.process_time(), time.perf_counter()
    protocol, t_st = k.protocol, k.steady_temperature
    if own_d2:
        # D2 from the ensemble's own T(t_w): a rerun with the same seed repeats the path
        # up to t_w, so T(t_w) = T_st(D2) holds for the particles too
        i_w = int(np.searchsorted(k.exact.times, k.waiting_time))
        pre = simulate_protocol(alpha, n_particles, times=k.exact.times[:i_w + 1],
                                diffusion=k.diffusion[1], initial=k.initial,
                                replicas=replicas, seed=seed)
        t_st = float(pre.temperature[-1])
        d2 = k.diffusion[0] * (t_st / k.exact.temperature[0]) ** ((k.gamma + 2.0) / 2.0)
        protocol = Protocol(diffusion=steps([k.waiting_time], [k.diffusion[1], d2]))
        print(f"  own D2 = {d2:.8f} from the DSMC T(t_w) = {t_st:.6f} "
              f"(FEM {k.steady_temperature:.6f})")
    run = simulate_protocol(alpha, n_particles, times=k.exact.times, protocol=protocol,
                            diffusion=k.diffusion[1], initial=k.initial, replicas=replicas,
                            seed=seed)
    cpu = time.process_time() - start
    wall = time.perf_counter() - wall
    z_t, z_a = run.deviation(k.exact.temperature, k.exact.a2)
    after = k.exact.times >= k.waiting_time
    dev = run.temperature[after] / t_st - 1.0
    err = run.temperature_error[after] / t_st
    if own_d2:  # compare deviations from T_st(D2), each method its own
        z_t = np.concatenate([z_t[~after], (dev - k.deviation()[1]) / err])
    i = int(np.argmin(np.abs(k.exact.times[after] - k.waiting_time - k.hump_time)))
    print(f"Kovacs DSMC, alpha = {alpha}, N = {n_particles}, {replicas} replicas "
          f"({cpu:.0f} CPU s, {wall:.0f} s wall); FEM at spacing {spacing}, rtol {rtol:g}")
    print(f"  FEM hump {k.hump:+.4e} at t - t_w = {k.hump_time:.3f}; DSMC at the nearest output "
          f"(t - t_w = {k.exact.times[after][i] - k.waiting_time:.3f}): {dev[i]:+.4e} "
          f"+- {err[i]:.1e}; min over outputs {dev.min():+.4e}")
    print(f"  at that time: {dev[i] / err[i]:+.1f} sigma from 0, "
          f"{(dev[i] - k.deviation()[1][i]) / err[i]:+.2f} sigma from FEM, "
          f"{(dev[i] - k.sonine_hump) / err[i]:+.1f} sigma from the first-Sonine extremum "
          f"{k.sonine_hump:+.4e}")
    print(f"  max |z| over {z_t.size} times: T {np.max(np.abs(z_t)):.2f}, "
          f"a2 {np.max(np.abs(z_a)):.2f}; times with |z_T| > 3: {int(np.sum(np.abs(z_t) > 3))}")


def mpemba_part(alpha: float, spacing: float, rtol: float, n_particles: int, replicas: int,
                seed: int, exact: float | None = None) -> None:
    """Mpemba threshold: first Sonine, exact (unless given) and DSMC."""
    son = mpemba_threshold(alpha)
    son_inf = mpemba_threshold(alpha, horizon=12.0)
    print(f"Mpemba, hard rods, alpha = {alpha}: hot 1.5 T_st (a2 = ?) against cold 1.4 T_st "
          f"(a2 = 0), below the cold curve at 4 relaxation times")
    print(f"  first Sonine threshold {son:.5f} (horizon 12: {son_inf:.5f})")
    start = time.perf_counter()
    if exact is None:
        exact = mpemba_threshold(alpha, method="exact", spacing=spacing, rtol=rtol, xtol=1e-4)
        assert exact is not None
        print(f"  exact (FEM, spacing {spacing}, rtol {rtol:g}) threshold {exact:.5f} "
              f"({time.perf_counter() - start:.0f} s)", flush=True)
    else:
        print(f"  exact threshold (given) {exact:.5f}")
    import kinetic_fem as kf

    t_st = kf.solve_heated(alpha).temperature
    t_h = 4.0 / sonine_relaxation_rates(alpha)[0]
    times = np.array([0.0, t_h])
    cold = simulate_protocol(alpha, n_particles, times=times,
                             initial=sonine_distribution(1.4 * t_st, 0.0), replicas=replicas,
                             seed=seed)
    a2s = np.array([exact - 0.15, exact, exact + 0.15])
    gaps, errs = [], []
    for j, a2 in enumerate(a2s):
        hot = simulate_protocol(alpha, n_particles, times=times,
                                initial=sonine_distribution(1.5 * t_st, float(a2)),
                                replicas=replicas, seed=seed + 1 + j)
        gaps.append((hot.temperature[-1] - cold.temperature[-1]) / t_st)
        errs.append(math.hypot(hot.temperature_error[-1], cold.temperature_error[-1]) / t_st)
    g, e = np.array(gaps), np.array(errs)
    # weighted line through the three points; the cold run is common to all: its error
    # moves the line up or down as a whole, added to the intercept's error
    w = 1.0 / e**2
    slope, icpt = np.polyfit(a2s, g, 1, w=np.sqrt(w))
    root = -icpt / slope
    cold_err = cold.temperature_error[-1] / t_st
    hot_err = math.sqrt(max(float(np.mean(e**2)) - cold_err**2, 0.0) / len(a2s))
    root_err = math.hypot(cold_err, hot_err) / abs(slope)
    for a2, gi, ei in zip(a2s, g, e, strict=True):
        print(f"  DSMC a2 = {a2:.4f}: (T_hot - T_cold)/T_st at t_H = {gi:+.5f} +- {ei:.5f}")
    print(f"  DSMC threshold {root:.4f} +- {root_err:.4f} (N = {n_particles}, {replicas} "
          f"replicas); exact - DSMC = {(exact - root) / root_err:+.2f} sigma")


def mpemba_exact(alpha: float, spacing: float, rtol: float, guess: float, xtol: float = 2e-4,
                 step: float = 0.02, cutoff: float | None = None) -> float:
    """Exact Mpemba threshold by a secant started at ``guess`` (each gap one FEM run).

    The gap :math:`(T_{hot} - T_{cold})(t_H)/T_{st}` is nearly linear in the hot
    :math:`a_2` (the initial state is linear in it), so from a guess within a few
    1e-2 the secant needs two or three runs besides the cold one.
    """
    import kinetic_fem as kf
    from kinetic_fem.analysis.memory_effects import exact_curves

    t_st = kf.solve_heated(alpha).temperature
    times = np.array([0.0, 4.0 / sonine_relaxation_rates(alpha)[0]])
    opts = {"spacing": spacing, "rtol": rtol, **({} if cutoff is None else {"cutoff": cutoff})}

    def final_t(temp: float, a2: float) -> float:
        start = time.process_time()
        curve, _ = exact_curves(alpha, 1.0, times, 1.0, sonine_distribution(temp, a2), None,
                                opts, t_min=t_st)
        print(f"    T({times[-1]:.4f}) from ({temp / t_st:.2f} T_st, a2 = {a2:.6f}): "
              f"{curve.temperature[-1]:.10f} ({time.process_time() - start:.0f} CPU s)",
              flush=True)
        return float(curve.temperature[-1])

    t_cold = final_t(1.4 * t_st, 0.0)

    def gap(a2: float) -> float:
        return (final_t(1.5 * t_st, a2) - t_cold) / t_st

    x0, x1 = guess, guess + step
    f0, f1 = gap(x0), gap(x1)
    for _ in range(8):
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        print(f"  secant: a2 = {x2:.6f} (gaps {f0:+.3e} at {x0:.6f}, {f1:+.3e} at {x1:.6f})",
              flush=True)
        if abs(x2 - x1) < xtol:
            print(f"  exact threshold (spacing {spacing}, rtol {rtol:g}, cutoff {cutoff}): "
                  f"{x2:.5f}")
            return float(x2)
        x0, f0, x1, f1 = x1, f1, x2, gap(x2)
    raise RuntimeError("secant did not converge")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", required=True,
                        choices=["kovacs", "kovacs-dsmc", "mpemba", "mpemba-exact"])
    parser.add_argument("--alpha", type=float, default=0.3)
    parser.add_argument("--grid", nargs="+",
                        default=["0.5:1e-4", "0.5:1e-5", "0.5:1e-6", "0.35:1e-5", "0.35:1e-6",
                                 "0.25:1e-5", "0.25:1e-6"],
                        help="spacing:rtol pairs of the Kovacs table (convergence in both)")
    parser.add_argument("--spacing", type=float, default=0.25)
    parser.add_argument("--rtol", type=float, default=1e-6)
    parser.add_argument("--particles", type=int, default=100_000)
    parser.add_argument("--replicas", type=int, default=64)
    parser.add_argument("--seed", type=int, default=20261125)
    parser.add_argument("--own-d2", action="store_true",
                        help="kovacs-dsmc: D2 from the DSMC ensemble's own T(t_w)")
    parser.add_argument("--cutoff", type=float, help="FEM cutoff option (thermal velocities)")
    parser.add_argument("--save", help="pickle the last Kovacs result here")
    parser.add_argument("--load", help="Kovacs result (pickle) for the DSMC part")
    parser.add_argument("--threshold", type=float,
                        help="exact Mpemba threshold (skips the FEM secant); with "
                        "--part mpemba-exact the secant's first guess")
    args = parser.parse_args()
    if args.part == "kovacs":
        grid = [(float(a), float(b)) for a, b in (g.split(":") for g in args.grid)]
        kovacs_table(args.alpha, grid, args.save)
    elif args.part == "kovacs-dsmc":
        kovacs_dsmc(args.alpha, args.spacing, args.rtol, args.particles, args.replicas,
                    args.seed, args.load, args.own_d2)
    elif args.part == "mpemba-exact":
        mpemba_exact(args.alpha, args.spacing, args.rtol,
                     0.4575 if args.threshold is None else args.threshold,
                     cutoff=args.cutoff)
    else:
        mpemba_part(args.alpha, args.spacing, args.rtol, args.particles, args.replicas,
                    args.seed, args.threshold)


if __name__ == "__main__":
    main()
