"""FEM transient of a heated mixture: steps, CPU time, and the Maxwell errors.

    python benchmarks/bench_mixture_transient.py [--quick]

The Maxwell mixture (kernel 0, masses 1 and 3, alpha 0.7, same diffusion, from T_s = 1)
by ``kf.evolve_heated(mix, method="fem")`` against the exact moment equations
(``method="maxwell"``) at each rtol: the largest relative error of T_s and absolute one
of a2_s over the output times, the accepted steps and the CPU time, also in units of one
steady FEM mixture solve (``kf.solve_heated(mix)``) of the same model.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import kinetic_fem as kf


def main(quick: bool = False) -> None:
    """Print the table.

    Parameters
    ----------
    quick : bool
        Only rtol 1e-3 to t = 1 (else rtol 1e-4 to t = 5).
    """
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7, kernel=0.0)
    cpu = time.process_time()
    kf.solve_heated(mix)
    steady = time.process_time() - cpu
    times = np.array([0.0, 0.5, 1.0]) if quick else np.array([0.0, 0.5, 1.0, 2.0, 5.0])
    exact = kf.evolve_heated(mix, times=times, method="maxwell", initial_temperature=1.0)
    print(f"steady FEM mixture solve: {steady:.2f} s CPU")
    print("rtol     steps  rejected  CPU s   /steady  max|dT/T|  max|da2|")
    for rtol in ((1e-3,) if quick else (1e-4,)):
        cpu = time.process_time()
        ev = kf.evolve_heated(mix, times=times, method="fem", initial_temperature=1.0,
                              rtol=rtol)
        took = time.process_time() - cpu
        dt = float(np.max(np.abs(ev.temperatures / exact.temperatures - 1.0)))
        da = float(np.max(np.abs(ev.a2 - exact.a2)))
        print(f"{rtol:<8g} {ev.info['accepted']:5d}  {ev.info['rejected']:8d}  {took:6.1f}  "
              f"{took / steady:7.1f}  {dt:9.2e}  {da:9.2e}")


if __name__ == "__main__":
    main("--quick" in sys.argv[1:])
