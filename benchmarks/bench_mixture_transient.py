"""FEM transient of a heated mixture: steps, CPU time, and the Maxwell errors.

    python benchmarks/bench_mixture_transient.py [--quick] [--rtol 1e-4,1e-5]

The Maxwell mixture (kernel 0, masses 1 and 3, fractions 1/2, alpha 0.7, white noise of
the same strength 1 on both species, from T_s = 1) by ``kf.evolve_heated(mix,
method="fem")`` to t = 5 against the exact moment equations (``method="maxwell"``) at
each rtol: the largest relative error of T_s and absolute one of a2_s over the output
times (0.5, 1, 2, 5), the meshes' dofs, the steps and the CPU time, also in units of one
steady FEM mixture solve (``kf.solve_heated(mix)``) of the same model.  Beside it, for
the cost, two one-species heated Maxwell transients from T = 1 at rtol 1e-4 (default
meshes): alpha 0.5 with friction 0.5 (T ends at 1.45) and alpha 0.7 with D = 1 (T ends at
5.9, a temperature range nearer the mixture's: its species' <v^2> grow 13 and 20 times).
Markdown on stdout (``benchmarks/results/mixture_transient.md`` holds a run).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

import kinetic_fem as kf


def main(quick: bool = False, rtols: tuple[float, ...] = (1e-4,)) -> None:
    """Print the tables.

    Parameters
    ----------
    quick : bool
        Only rtol 1e-3 to t = 1, no one-species runs.
    rtols : tuple of float
        The tolerances of the full run.
    """
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7, kernel=0.0)
    kf.solve_heated(mix)   # compile the kernels outside the timings
    start = time.process_time()
    kf.solve_heated(mix)
    steady = time.process_time() - start
    times = np.array([0.0, 0.5, 1.0]) if quick else np.array([0.0, 0.5, 1.0, 2.0, 5.0])
    exact = kf.evolve_heated(mix, times=times, method="maxwell", initial_temperature=1.0)
    print(f"load average at the start: {os.getloadavg()[0]:.1f} "
          f"({os.cpu_count()} cores); CPU seconds by time.process_time\n")
    print(f"Maxwell mixture m 1:3, alpha 0.7, D_s = 1, T_s(0) = 1, to t = {times[-1]:g}; "
          f"steady FEM mixture solve: {steady:.2f} s CPU\n")
    print("| rtol | dofs | steps | rejected | Newton failures | Newton its | Jacobians | "
          "CPU s | / steady | max dT_s/T_s | max da2_s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for rtol in ((1e-3,) if quick else rtols):
        start = time.process_time()
        ev = kf.evolve_heated(mix, times=times, method="fem", initial_temperature=1.0,
                              rtol=rtol)
        took = time.process_time() - start
        dt = float(np.max(np.abs(ev.temperatures / exact.temperatures - 1.0)))
        da = float(np.max(np.abs(ev.a2 - exact.a2)))
        i = ev.info
        dofs = "+".join(str(n) for n in i["n_dofs"])
        print(f"| {rtol:g} | {dofs} | {i['accepted']} | {i['rejected']} | "
              f"{i['newton_failures']} | {i['newton_iterations']} | {i['jacobians']} | "
              f"{took:.1f} | {took / steady:.1f} | {dt:.2e} | {da:.2e} |", flush=True)
    if quick:
        return
    print("\nOne species, Maxwell, from T = 1 to t = 5 (times 0.25, 0.5, 1, 2, 5), rtol 1e-4:\n")
    print("| model | T(5) | dofs | steps | Newton its | CPU s |")
    print("|---|---|---|---|---|---|")
    for label, kw in (("alpha 0.5, friction 0.5, D 1", {"alpha": 0.5, "friction": 0.5}),
                      ("alpha 0.7, D 1", {"alpha": 0.7})):
        start = time.process_time()
        one = kf.evolve_heated(times=[0.25, 0.5, 1.0, 2.0, 5.0], initial_temperature=1.0,
                               kernel=0.0, **kw)
        took = time.process_time() - start
        e = one.info.extra
        print(f"| {label} | {one.temperature[-1]:.3f} | {e['n_dofs']} | {e['accepted']} | "
              f"{e['newton_iterations']} | {took:.1f} |", flush=True)


if __name__ == "__main__":
    args = sys.argv[1:]
    chosen: tuple[float, ...] = (1e-4,)
    if "--rtol" in args:
        chosen = tuple(float(r) for r in args[args.index("--rtol") + 1].split(","))
    main("--quick" in args, chosen)
