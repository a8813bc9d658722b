"""Mesh convergence of the FEM cooling state of a hard-rod mixture: the cut outer rule.

The pair sums of two species integrate the outer velocity with the element rule of the
outer mesh; the inner integral has the kernel's kink at y = x, which crosses the kinks of
the inner species' :math:`P_i = e^{u_h}` at its vertices, so that on two different meshes
the outer integrand is not smooth inside an outer element
(:func:`kinetic_fem.solvers.fem.mixture.merged_rule`).  The cooling state cuts the outer
elements at the inner species' vertices within ``SPLIT_REACH`` thermal velocities.

Tables (hard rods, P3, the largest T_s error (relative), a2_s error (absolute) and zeta
error (relative) against the same rule at spacing 0.1, with the observed order between
consecutive spacings):

1. identical species (alpha 0.5, x 0.5/0.5) on meshes of bulk spacings h and 1.2 h: the
   element rule against the cut rule;
2. masses 1:3 and 1:10 at alpha 0.5 (their own meshes), both rules.

    OMP_NUM_THREADS=1 python benchmarks/convergence_fem_mixture_cooling.py
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.solvers.fem import mixture as fem_mixture

SPACINGS = (0.5, 0.4, 0.3, 0.25, 0.2, 0.15)
REFERENCE = 0.1


def error(state: Any, ref: Any) -> float:
    """Largest relative T_s and zeta error and absolute a2_s error."""
    t = np.max(np.abs(np.asarray(state.temperatures) / np.asarray(ref.temperatures) - 1.0))
    a2 = np.max(np.abs(np.asarray(state.a2) - np.asarray(ref.a2)))
    return float(max(t, a2, abs(state.zeta / ref.zeta - 1.0)))


def column(mixture: kf.Mixture, cut: bool, stretch: float) -> list[float]:
    """Errors over :data:`SPACINGS` with the cut rule (``cut``) or the element rule; the
    second species' bulk spacing ``stretch`` times the first's."""
    reach = fem_mixture.SPLIT_REACH
    meshes = fem_mixture.mixture_meshes

    def stretched(mix: Any, variances: Any, cutoffs: Any, *, spacing: float = 0.25,
                  cooling: bool = False) -> tuple[Any, ...]:
        first = meshes(mix, variances, cutoffs, spacing=spacing, cooling=cooling)
        second = meshes(mix, variances, cutoffs, spacing=spacing * stretch, cooling=cooling)
        return (first[0], *second[1:])

    fem_mixture.SPLIT_REACH = reach if cut else 0.0
    fem_mixture.mixture_meshes = stretched  # type: ignore[assignment]
    try:
        ref = kf.solve_cooling(mixture, order=3, spacing=REFERENCE)
        return [error(kf.solve_cooling(mixture, order=3, spacing=h), ref) for h in SPACINGS]
    finally:
        fem_mixture.SPLIT_REACH = reach
        fem_mixture.mixture_meshes = meshes  # type: ignore[assignment]


def table(title: str, mixture: kf.Mixture, stretch: float) -> None:
    print(f"\n{title}\n")
    print("| spacing | element rule | order | cut rule | order |")
    print("|---|---|---|---|---|")
    plain, cut = column(mixture, False, stretch), column(mixture, True, stretch)
    for i, h in enumerate(SPACINGS):
        cells = []
        for errs in (plain, cut):
            order = "" if i == 0 else \
                f"{math.log(errs[i - 1] / errs[i]) / math.log(SPACINGS[i - 1] / h):.1f}"
            cells += [f"{errs[i]:.2e}", order]
        print(f"| {h:g} | " + " | ".join(cells) + " |", flush=True)


def main() -> None:
    warnings.simplefilter("ignore", ResolutionWarning)
    table("Identical species, alpha 0.5, meshes h and 1.2 h",
          kf.Mixture((1.0, 1.0), (0.5, 0.5), alpha=0.5), 1.2)
    for m in (3.0, 10.0):
        table(f"Masses 1:{m:g}, alpha 0.5", kf.Mixture((1.0, m), (0.5, 0.5), alpha=0.5),
              1.0)


if __name__ == "__main__":
    main()
