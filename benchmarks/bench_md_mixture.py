"""MD of a mixture against the one-species MD: collisions per CPU second in one run.

Target (issue 27): the mixture at least 0.8 times the one-species rate.  Same N, same
run length, the same inelasticity; CPU time (``time.process_time``), best of
``--repeat`` runs of each, interleaved.  Usage::

    python benchmarks/bench_md_mixture.py [--n 5000] [--cpp 200] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

from kinetic_fem.model.mixture import Mixture
from particles import md
from particles.md_mixture import simulate_mixture


def _rate(func) -> float:
    t0 = time.process_time()
    run = func()
    return run.n_collisions / (time.process_time() - t0)


def main(n: int = 5000, cpp: float = 200.0, repeat: int = 3, alpha: float = 0.9) -> dict:
    """Collisions per CPU second of one-species and mixture MD, heated and cooling."""
    heated = Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=alpha)
    cooling = Mixture((1.0, 2.0), (0.5, 0.5), alpha=alpha)
    cases = {
        "heated one": lambda: md.simulate_heated(alpha, n, seed=1, collisions_per_particle=cpp),
        "heated mixture": lambda: simulate_mixture(heated, n, seed=1,
                                                   collisions_per_particle=cpp),
        "cooling one": lambda: md.simulate_cooling(alpha, n, seed=1, threshold=1e-4,
                                                   collisions_per_particle=cpp),
        "cooling mixture": lambda: simulate_mixture(cooling, n, seed=1, threshold=1e-4,
                                                    collisions_per_particle=cpp),
    }
    best = {k: 0.0 for k in cases}
    for _ in range(repeat):
        for key, func in cases.items():
            best[key] = max(best[key], _rate(func))
    return best


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=5000)
    parser.add_argument("--cpp", type=float, default=200.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    rates = main(args.n, args.cpp, args.repeat)
    for key, rate in rates.items():
        print(f"{key:16s} {rate / 1e6:7.3f} M collisions / CPU s")
    for kind in ("heated", "cooling"):
        ratio = rates[f"{kind} mixture"] / rates[f"{kind} one"]
        print(f"{kind}: mixture / one species = {ratio:.3f} (target >= 0.8)")
