"""Relaxation spectrum of the heated gas against alpha (issue 11 item 5, claim C2).

For each alpha: the slowest even (temperature) and odd rates of the linearised FEM system
(:func:`kinetic_fem.relaxation_spectrum`) at the default mesh and at a finer one (the
difference is the error bar), the rate times the C2 time scale
``tau = [D/(n(1-alpha^2))]^(2/3)/D`` and the local exponent of the even rate against
eps between successive alphas (C2 predicts 2/3 near elastic collisions).  The Maxwell
model's rates are compared with the exact moment rates first.

Run: ``python benchmarks/relaxation_spectrum.py [--alphas ...] [--refine 0.7]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem import sonine
from kinetic_fem.solvers.fem.defaults import default_spacing
from kinetic_fem.solvers.relaxation import maxwell_rates


def main(alphas: list[float], refine: float) -> None:
    print("Maxwell model (gamma = 0, white noise), alpha = 0.5: FEM rates against the exact")
    exact = maxwell_rates(0.5, 7)[1:]
    for h in (0.2, 0.1, 0.05):
        spec = kf.relaxation_spectrum(0.5, kernel=0.0, n_rates=6, spacing=h)
        err = np.abs(spec.rates / exact - 1)
        print(f"  spacing {h:5.3f} ({spec.n_dofs:4d} dofs): rel. errors "
              + " ".join(f"{e:.1e}" for e in err))
    print()
    print("Hard rods, white noise, n = D = 1")
    print("| alpha | dofs | even rate | +- (mesh) | odd rate | even rate x tau_C2 "
          "| local exponent | s |")
    print("|---|---|---|---|---|---|---|---|")
    prev = None
    for alpha in alphas:
        start = time.perf_counter()
        spec = kf.relaxation_spectrum(alpha, n_rates=6)
        fine = kf.relaxation_spectrum(alpha, n_rates=6,
                                      spacing=refine * default_spacing(alpha))
        even, odd = spec.slowest("even"), spec.slowest("odd")
        err = abs(fine.slowest("even") - even)
        local = "" if prev is None else \
            f"{math.log(prev[1] / even) / math.log(prev[0] / (1 - alpha)):.4f}"
        print(f"| {alpha} | {spec.n_dofs} | {even:.8g} | {err:.1e} | {odd:.8g} | "
              f"{even * sonine.relaxation_time(alpha):.5f} | {local} | "
              f"{time.perf_counter() - start:.1f} |", flush=True)
        prev = (1 - alpha, even)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+",
                        default=[0.0, 0.3, 0.6, 0.9, 0.99, 0.999, 0.9999])
    parser.add_argument("--refine", type=float, default=0.7)
    args = parser.parse_args()
    main(args.alphas, args.refine)
