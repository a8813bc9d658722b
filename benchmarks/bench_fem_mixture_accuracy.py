"""CPU time of a binary FEM mixture state against one species *at the same accuracy*.

Issue 27, item 5: a binary FEM state at most 4 times a one-species state at the same
accuracy.  Hard rods, heated (white noise) or with ``--cooling`` the homogeneous cooling
state, P3, masses 1:1, 1:3, 1:10 at equal fractions.  The error of a state is the largest
of its T_s errors (relative), a2_s errors (absolute) and, cooling, the cooling rate's
(relative) against the same solver at spacing 0.08 (cooling: 0.1); the mixture runs at its default
spacing 0.25 (each species' bulk spacing scaled by
:func:`kinetic_fem.solvers.fem.mixture.species_spacing`), the one-species state at
spacings 0.5 ... 0.15, and its CPU time at the mixture's error is interpolated in
log-log.  "same spacing": the plain ratio to one species at spacing 0.25.  CPU time,
best of 3, the one-species starts of the mixture cleared before each call (a first
call).  Problem sizes: one species 50-170 dofs (half line), mixture 2 x 80-330.

    OMP_NUM_THREADS=1 python benchmarks/bench_fem_mixture_accuracy.py [--alphas 0.9] [--cooling]
"""

from __future__ import annotations

import argparse
import warnings
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
from bench_fem_mixture import cold
from numpy.typing import NDArray
from yardstick import best_cpu

import kinetic_fem as kf
from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.exceptions import ConvergenceError, ResolutionWarning

ONE_SPACINGS = (0.5, 0.4, 0.35, 0.3, 0.25, 0.2, 0.15)
REFERENCE_SPACING = 0.08
REPEATS = 3


def observables(state: Any) -> tuple[NDArray, NDArray]:
    """(values compared relatively, values compared absolutely) of a state: T_s (and the
    cooling rate) against a2_s; one species (a VelocityDistribution) or a mixture."""
    if isinstance(state, VelocityDistribution):
        zeta = state.info.extra.get("zeta")
        rel = [state.temperature] if zeta is None else [float(zeta)]
        return np.array(rel, dtype=float), np.array([state.a2])
    rel = list(state.temperatures) + ([state.zeta] if state.zeta is not None else [])
    return np.array(rel, dtype=float), np.asarray(state.a2, dtype=float)


def state_error(state: Any, ref: Any) -> float:
    """Largest relative (T_s, cooling rate) and absolute (a2_s) error."""
    (rel, ab), (rel_ref, ab_ref) = observables(state), observables(ref)
    return float(max(np.max(np.abs(rel / rel_ref - 1.0)), np.max(np.abs(ab - ab_ref))))


def one_species_curve(alpha: float, solve: Callable[..., Any], reference: float
                      ) -> list[tuple[float, float, float]]:
    """(spacing, error, CPU s) of the one-species state (spacings whose Newton fails
    are left out)."""
    ref = solve(alpha, spacing=reference, order=3)
    rows = []
    for h in ONE_SPACINGS:
        try:
            cpu, state = best_cpu(partial(solve, alpha, spacing=h, order=3), REPEATS)
        except ConvergenceError:
            print(f"(one species, alpha {alpha:g}, spacing {h:g}: no convergence)")
            continue
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
    parser.add_argument("--cooling", action="store_true", help="the cooling states")
    args = parser.parse_args()
    solve = kf.solve_cooling if args.cooling else kf.solve_heated
    # the one-species cooling Newton at alpha 0.9 does not converge at spacing 0.08
    reference = 0.1 if args.cooling else REFERENCE_SPACING
    model = kf.Mixture if args.cooling else kf.Mixture.white_noise
    warnings.simplefilter("ignore", ResolutionWarning)
    print("| alpha | m2/m1 | mixture error | mixture CPU s | one species CPU s at that "
          "error | ratio | same-spacing ratio |")
    print("|---|---|---|---|---|---|---|")
    for alpha in (float(a) for a in args.alphas.split(",")):
        one = one_species_curve(alpha, solve, reference)
        one_025 = dict((r[0], r[2]) for r in one)[0.25]
        for m in (float(x) for x in args.masses.split(",")):
            mix = model((1.0, m), (0.5, 0.5), alpha=alpha, kernel=1.0)
            ref = solve(mix, spacing=reference, order=3)
            cpu, state = best_cpu(partial(cold, solve, mix, order=3), REPEATS)
            err = state_error(state, ref)
            c1 = cost_at(one, err)
            print(f"| {alpha:g} | {m:g} | {err:.2e} | {cpu:.4f} | {c1:.4f} | {cpu / c1:.2f} "
                  f"| {cpu / one_025:.2f} |", flush=True)


if __name__ == "__main__":
    main()
