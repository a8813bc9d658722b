"""CPU time of a binary FEM mixture state against one species *at the same accuracy*.

Issue 27, item 5: a binary FEM state at most 4 times a one-species state at the same
accuracy.  Hard rods, heated (white noise), P3, masses 1:1, 1:3, 1:10 at equal fractions.
The error of a state is the largest of its T_s errors (relative) and a2_s errors
(absolute) against the same solver at spacing 0.08; the mixture runs at its default
spacing 0.25 (each species' bulk spacing scaled by
:func:`kinetic_fem.solvers.fem.mixture.species_spacing`), the one-species state at
spacings 0.5 ... 0.15, and its CPU time at the mixture's error is interpolated in
log-log.  "same spacing": the plain ratio to one species at spacing 0.25.  CPU time,
best of 3, the one-species starts of the mixture cleared before each call (a first
call).  Problem sizes: one species 50-170 dofs (half line), mixture 2 x 80-330.

    OMP_NUM_THREADS=1 python benchmarks/bench_fem_mixture_accuracy.py [--alphas 0.9]
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.solvers.fem import mixture as fem_mixture

ONE_SPACINGS = (0.5, 0.4, 0.35, 0.3, 0.25, 0.2, 0.15)
REFERENCE_SPACING = 0.08


def first_call_cpu(solve: Callable[[], Any], repeats: int = 3) -> tuple[float, Any]:
    """Best CPU time of ``solve()`` with the kept one-species starts cleared."""
    best, out = np.inf, None
    for _ in range(repeats):
        fem_mixture._one_species_heated.cache_clear()
        fem_mixture._one_species_cooling.cache_clear()
        cpu = time.process_time()
        out = solve()
        best = min(best, time.process_time() - cpu)
    return best, out


def state_error(state: Any, ref: Any) -> float:
    """Largest relative T_s and absolute a2_s error (one species or a mixture)."""
    temps = np.atleast_1d(getattr(state, "temperatures", getattr(state, "temperature", None)))
    ref_t = np.atleast_1d(getattr(ref, "temperatures", getattr(ref, "temperature", None)))
    return float(max(np.max(np.abs(temps / ref_t - 1.0)),
                     np.max(np.abs(np.atleast_1d(state.a2) - np.atleast_1d(ref.a2)))))


def one_species_curve(alpha: float) -> list[tuple[float, float, float]]:
    """(spacing, error, CPU s) of the one-species heated state."""
    ref = kf.solve_heated(alpha, spacing=REFERENCE_SPACING, order=3)
    rows = []
    for h in ONE_SPACINGS:
        cpu, state = first_call_cpu(lambda h=h: kf.solve_heated(alpha, spacing=h, order=3))
        rows.append((h, state_error(state, ref), cpu))
    return rows


def cost_at(rows: list[tuple[float, float, float]], error: float) -> float:
    """CPU time of the one-species curve at ``error`` (log-log interpolation)."""
    pts = sorted(rows, key=lambda r: r[1])
    return float(np.exp(np.interp(np.log(error), np.log([p[1] for p in pts]),
                                  np.log([p[2] for p in pts]))))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", default="0.5,0.7,0.9")
    parser.add_argument("--masses", default="1,3,10")
    args = parser.parse_args()
    warnings.simplefilter("ignore", ResolutionWarning)
    print("| alpha | m2/m1 | mixture error | mixture CPU s | one species CPU s at that "
          "error | ratio | same-spacing ratio |")
    print("|---|---|---|---|---|---|---|")
    for alpha in (float(a) for a in args.alphas.split(",")):
        one = one_species_curve(alpha)
        one_025 = dict((r[0], r[2]) for r in one)[0.25]
        for m in (float(x) for x in args.masses.split(",")):
            mix = kf.Mixture.white_noise((1.0, m), (0.5, 0.5), alpha=alpha, kernel=1.0)
            ref = kf.solve_heated(mix, spacing=REFERENCE_SPACING, order=3)
            cpu, state = first_call_cpu(lambda mix=mix: kf.solve_heated(mix, order=3))
            err = state_error(state, ref)
            c1 = cost_at(one, err)
            print(f"| {alpha:g} | {m:g} | {err:.2e} | {cpu:.4f} | {c1:.4f} | {cpu / c1:.2f} "
                  f"| {cpu / one_025:.2f} |", flush=True)


if __name__ == "__main__":
    main()
