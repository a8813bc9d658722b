"""Convergence of the gamma = 2 cooling state from the anchored start (issue 16).

For each alpha, :func:`kinetic_fem.solvers.fem.cooling_gamma2.anchored_state` on the
default mesh (``refine`` 1) and on meshes ``refine`` = 2, 4, ... times finer (the default
HCS mesh's spacing at eps >= 3e-3; below, the e-folds per element, the core and the
largest element of the near-elastic mesh), P2: zeta, a2 and the energy identity,
the errors of each level against the finest and the observed orders
log2(e_h / e_{h/2}); CPU s and Newton steps of each solve (a level whose anchored start
fails starts from the coarser level's state).

    python benchmarks/convergence_gamma2_cooling.py [--alphas 0.7 0.9 ...] [--levels 4]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

from kinetic_fem.model import CoolingProblem  # noqa: E402
from kinetic_fem.solvers.fem.cooling import cooling_distribution  # noqa: E402
from kinetic_fem.solvers.fem.cooling_gamma2 import AnchoredStart, anchored_state  # noqa: E402
from kinetic_fem.solvers.fem.cooling_newton import CoolingState, newton_cooling  # noqa: E402
from kinetic_fem.solvers.fem.cooling_quasi import (  # noqa: E402
    QUASI_CORE,
    QUASI_FINAL,
    QUASI_MAX_SIZE,
    efold_vertices,
)
from kinetic_fem.solvers.fem.heated import FEMDiscretisation  # noqa: E402


def from_coarser(problem: CoolingProblem, coarse: CoolingState, refine: float):
    """Newton on the ``refine`` mesh from the coarser level's state (where the anchored
    start took more than its step limit: alpha 0.9995 at refine 4)."""
    eps = problem.gas.epsilon
    efolds, depth, cutoff_depth = QUASI_FINAL
    verts = efold_vertices(AnchoredStart(eps), eps, efolds=efolds / refine, depth=depth,
                           cutoff_depth=cutoff_depth, core=QUASI_CORE * refine,
                           max_size=QUASI_MAX_SIZE / refine)
    disc = FEMDiscretisation(problem.gas.alpha, verts, 2, 5, gamma=2.0)
    state = newton_cooling(disc, coarse.log_f(disc.dof_locations), coarse.zeta, tol=1e-11,
                           max_iter=40, pseudo_time=math.inf)
    return state if state.info.converged else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="*",
                        default=[0.7, 0.9, 0.95, 0.99, 0.995, 0.999])
    parser.add_argument("--levels", type=int, default=4)
    args = parser.parse_args()
    print("| alpha | refine | dofs | Newton | CPU s | zeta | a2 | energy identity | "
          "dzeta vs finest | order | da2 vs finest | order |")
    print("|---" * 12 + "|")
    for alpha in args.alphas:
        problem = CoolingProblem.from_parameters(alpha, kernel=2.0)
        rows = []
        for level in range(args.levels):
            refine = 2.0 ** level
            t0 = time.process_time()
            state = anchored_state(problem, order=2, intorder=None, tol=1e-11, max_iter=40,
                                   refine=refine)
            if state is None and rows and rows[-1][1] is not None:
                state = from_coarser(problem, rows[-1][1][0], refine)
            cpu = time.process_time() - t0
            if state is None:
                rows.append((refine, None, cpu))
                break
            dist = cooling_distribution(problem, state)
            rows.append((refine, (state, dist.a2, state.energy_identity()), cpu))
        good = [r for r in rows if r[1] is not None]
        zeta_f, a2_f = good[-1][1][0].zeta, good[-1][1][1]
        errs = [(abs(r[1][0].zeta / zeta_f - 1.0), abs(r[1][1] - a2_f)) for r in good]
        for i, (refine, res, cpu) in enumerate(rows):
            if res is None:
                print(f"| {alpha} | {refine:g} | - | failed | {cpu:.2f} | | | | | | | |")
                continue
            state, a2, ident = res
            ez, ea = errs[i]
            order = ["", ""]
            if i + 1 < len(good) - 1:
                for k in (0, 1):
                    nxt = errs[i + 1][k]
                    order[k] = f"{math.log2(errs[i][k] / nxt):.2f}" if nxt > 0 and \
                        errs[i][k] > 0 else ""
            print(f"| {alpha} | {refine:g} | {state.u.size} | {state.info.iterations} | "
                  f"{cpu:.2f} | {state.zeta:.14g} | {a2:.12g} | "
                  f"{abs(ident / state.zeta - 1):.1e} | {ez:.1e} | {order[0]} | {ea:.1e} | "
                  f"{order[1]} |", flush=True)


if __name__ == "__main__":
    main()
