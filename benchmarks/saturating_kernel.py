"""FEM against DSMC for a kernel that is not a power law: |g|/(1 + |g|/g0) (issue 9).

The saturating kernel was added as one class (``kinetic_fem/model/kernel_saturating.py``)
plus its rate in the FEM pair rule and its acceptance in the DSMC.  This table compares
the heated steady state of both methods: FEM with default options (its own error from a
halved spacing), DSMC with N = 25000, 2000 collisions per particle, several seeds (batch
errors; the mean over seeds and its standard error).

Usage::

    python benchmarks/saturating_kernel.py [--seeds 4] [--out table.md]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.model import SaturatingKernel, ViscoelasticRestitution
from particles import dsmc

CASES = [
    ("g0 = 1, white noise", 0.6, dict(kernel=SaturatingKernel(1.0))),
    ("g0 = 1, white noise", 0.9, dict(kernel=SaturatingKernel(1.0))),
    ("g0 = 0.3, bath xi = 1", 0.6, dict(kernel=SaturatingKernel(0.3), friction=1.0)),
    ("g0 = 2, n = 2, D = 3", 0.6, dict(kernel=SaturatingKernel(2.0), density=2.0,
                                       diffusion=3.0)),
    ("g0 = 2, viscoelastic 0.2", ViscoelasticRestitution(0.2),
     dict(kernel=SaturatingKernel(2.0))),
]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--n", type=int, default=25_000)
    p.add_argument("--cpp", type=float, default=2000.0)
    p.add_argument("--out")
    args = p.parse_args()
    lines = ["| model | alpha | FEM T | FEM a2 | DSMC T | DSMC a2 | z(T) | z(a2) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, alpha, kw in CASES:
        fem = kf.solve_heated(alpha, **kw)
        temps, a2s, zt, za = [], [], [], []
        start = time.process_time()
        for seed in range(1, args.seeds + 1):
            run = dsmc.simulate_heated(alpha, args.n, seed=seed,
                                       collisions_per_particle=args.cpp, **kw)
            t_err = run.distribution.observable_error(lambda d: d.temperature)
            temps.append(run.temperature)
            a2s.append(run.a2)
            zt.append((run.temperature - fem.temperature) / t_err)
            za.append((run.a2 - fem.a2) / run.a2_error)
        t_mean, a_mean = float(np.mean(temps)), float(np.mean(a2s))
        t_se = float(np.std(temps, ddof=1)) / math.sqrt(len(temps))
        a_se = float(np.std(a2s, ddof=1)) / math.sqrt(len(a2s))
        a_label = alpha if isinstance(alpha, float) else repr(alpha)
        line = (f"| {name} | {a_label} | {fem.temperature:.6f} | {fem.a2:+.6f} | "
                f"{t_mean:.5f} +- {t_se:.5f} | {a_mean:+.5f} +- {a_se:.5f} | "
                f"{(t_mean - fem.temperature) / t_se:+.2f} | {(a_mean - fem.a2) / a_se:+.2f} |")
        lines.append(line)
        print(line, f"(per-seed |z| max {max(map(abs, zt)):.2f}, {max(map(abs, za)):.2f};"
              f" {time.process_time() - start:.0f} s)", flush=True)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
