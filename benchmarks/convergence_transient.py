"""Convergence of the adaptive transient in its tolerance ``rtol``.

Heated hard rods (alpha = 0.5, n = D = 1) from a Gaussian at T = 0.5, a step of the
noise strength D: 1 -> 2 at t = 1, output at t = 0.5, 1, 1.5, 2, 3; fixed coarse mesh
(spacing 0.5, cut-off 12), so the time error is isolated.  The reference is the same
run at rtol = 1e-9.  Prints, per rtol, the maximum over the output times of the
relative error of T and the absolute error of a2, the steps taken (rejected, forced at
the minimum step) and the wall time (on a shared machine: compare within one run).

    python benchmarks/convergence_transient.py [--quick]
"""

import sys
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.model.protocol import Protocol, steps

TIMES = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0]
MESH = {"spacing": 0.5, "cutoff": 12.0}


def run(rtol: float):
    start = time.perf_counter()
    ev = kf.evolve_heated(0.5, times=TIMES, initial_temperature=0.5,
                          protocol=Protocol(diffusion=steps([1.0], [1.0, 2.0])), rtol=rtol,
                          **MESH)
    return ev, time.perf_counter() - start


def main(quick: bool = False) -> list[tuple]:
    rtols = [1e-3, 1e-4, 1e-5] if quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7]
    ref, _ = run(1e-8 if quick else 1e-9)
    rows = []
    print(f"reference rtol={'1e-8' if quick else '1e-9'}: {ref.info.message}")
    print(f"{'rtol':>8} {'max dT/T':>10} {'max |da2|':>10} {'steps':>6} {'rejected':>8} "
          f"{'forced':>6} {'wall s':>7}")
    for rtol in rtols:
        ev, wall = run(rtol)
        e_t = float(np.max(np.abs(ev.temperature / ref.temperature - 1.0)))
        e_a = float(np.max(np.abs(ev.a2 - ref.a2)))
        x = ev.info.extra
        rows.append((rtol, e_t, e_a, x["accepted"], x["rejected"], x["forced"], wall))
        print(f"{rtol:8.0e} {e_t:10.2e} {e_a:10.2e} {x['accepted']:6d} {x['rejected']:8d} "
              f"{x['forced']:6d} {wall:7.1f}")
    return rows


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
