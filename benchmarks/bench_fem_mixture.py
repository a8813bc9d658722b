"""CPU time of a binary FEM mixture state against one species, and where it goes.

Hard rods, alpha = 0.7 (then 0.5 and 0.9), P3, the same bulk spacing in thermal
velocities (0.25, the mixture's default; at 0.5 the heated Newton of masses 1:3 and
1:10 does not converge): the heated state (white noise) and the cooling state, one
species (``kf.solve_heated(alpha)``, ``kf.solve_cooling(alpha)``) against a binary
mixture of identical species (x 0.5/0.5,
equal masses: the accuracy is the one-species one) and of masses 1:3 and 1:10.  For the mixtures
the CPU time is split into the pair sums (``MixtureDiscretisation.collision``, with and
without Jacobian), the start (``_start_profiles``: the one-species state of each distinct
restitution coefficient and thermostat, P3 at spacing 0.4 heated and 0.25 cooling on an
interval past the mixture's cut-off) and the rest
(transport forms, LU solves, Newton driver), with the number of pair-sum evaluations per
solve (with Jacobian + residual only).  Target of issue 27: a binary state at most 4 times
one species.  The one-species states of the starts are kept between calls
(``START_CACHE``): the mixture's time is that of a first call (the kept starts cleared
before each call), and "warm" that of a further state at the same restitution
coefficient and thermostat (a sweep over masses or fractions).

Run with one BLAS thread::

    OMP_NUM_THREADS=1 python benchmarks/bench_fem_mixture.py
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from functools import partial
from typing import Any

from yardstick import best_cpu

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.solvers.fem import mixture as fem_mixture


def timed_collision(record: list[float], jacobians: list[bool]) -> Callable[..., Any]:
    """The pair sums of the mixture, their CPU time appended to ``record`` (and whether
    with Jacobian to ``jacobians``)."""
    plain = fem_mixture.MixtureDiscretisation.collision

    def collision(self, us, *, jacobian=False):
        cpu = time.process_time()
        out = plain(self, us, jacobian=jacobian)
        record.append(time.process_time() - cpu)
        jacobians.append(jacobian)
        return out

    return collision


def timed_start(record: list[float]) -> Callable[..., Any]:
    """The start profiles of the mixture, their CPU time appended to ``record``."""
    plain = fem_mixture._start_profiles

    def start(*args, **kwargs):
        cpu = time.process_time()
        out = plain(*args, **kwargs)
        record.append(time.process_time() - cpu)
        return out

    return start


def cold(solve: Callable[..., Any], mixture: Any, **options: Any) -> Any:
    """``solve(mixture, **options)`` with the kept one-species starts cleared first."""
    fem_mixture._one_species_heated.cache_clear()
    fem_mixture._one_species_cooling.cache_clear()
    return solve(mixture, **options)


def main(spacing: float = 0.25, repeats: int = 5, alphas: tuple[float, ...] = (0.7, 0.5, 0.9)
         ) -> None:
    """Print the table (``repeats``: calls per state, the smallest CPU time kept)."""
    warnings.simplefilter("ignore", ResolutionWarning)
    print(f"| state | dofs | CPU s (best of {repeats}) | ratio to one species | "
          "pair sums share | start share | pair sums per solve (J + r) | warm CPU s (ratio) |")
    print("|---|---|---|---|---|---|---|---|")
    for alpha in alphas:
        for cooling in (False, True):
            table_rows(alpha, cooling, spacing, repeats)


def table_rows(alpha: float, cooling: bool, spacing: float, repeats: int) -> None:
    """The rows of one restitution coefficient and problem: one species, then binary
    mixtures of masses 1:1, 1:3 and 1:10."""
    name = f"{'cooling' if cooling else 'heated'} alpha {alpha:g}"
    solve = kf.solve_cooling if cooling else kf.solve_heated
    one_t, one = best_cpu(partial(solve, alpha, order=3, spacing=spacing), repeats)
    print(f"| {name}, one species | {one.info.extra['n_dofs']} | {one_t:.3f} | 1 | | | | |")
    for masses in ((1.0, 1.0), (1.0, 3.0), (1.0, 10.0)):
        mix = (kf.Mixture(masses, (0.5, 0.5), alpha=alpha) if cooling else
               kf.Mixture.white_noise(masses, (0.5, 0.5), alpha=alpha))
        record: list[float] = []
        jacobians: list[bool] = []
        starts: list[float] = []
        plain = fem_mixture.MixtureDiscretisation.collision
        plain_start = fem_mixture._start_profiles
        fem_mixture.MixtureDiscretisation.collision = timed_collision(record, jacobians)  # type: ignore[method-assign]
        fem_mixture._start_profiles = timed_start(starts)
        try:
            solve(mix, order=3, spacing=spacing)  # numba compiles outside the record
            for kept in (record, jacobians, starts):
                kept.clear()
            total = time.process_time()
            mix_t, state = best_cpu(partial(cold, solve, mix, order=3, spacing=spacing),
                                    repeats)
        except kf.exceptions.ConvergenceError as err:
            print(f"| {name}, binary m {masses[0]:g}:{masses[1]:g} | | failed: "
                  f"{str(err)[:70]} | | | | | |", flush=True)
            continue
        finally:
            fem_mixture.MixtureDiscretisation.collision = plain  # type: ignore[method-assign]
            fem_mixture._start_profiles = plain_start
        total = time.process_time() - total  # the shares: of all repeats
        share = sum(record) / total
        start_share = sum(starts) / total
        n_jac = sum(jacobians) / repeats
        n_res = (len(jacobians) - sum(jacobians)) / repeats
        warm_t, _ = best_cpu(partial(solve, mix, order=3, spacing=spacing), repeats)
        print(f"| {name}, binary m {masses[0]:g}:{masses[1]:g} | "
              f"{state.info.extra['n_dofs']} | {mix_t:.3f} | {mix_t / one_t:.2f} | "
              f"{share:.0%} | {start_share:.0%} | {n_jac:g} + {n_res:g} | "
              f"{warm_t:.3f} ({warm_t / one_t:.2f}) |", flush=True)


if __name__ == "__main__":
    main()
