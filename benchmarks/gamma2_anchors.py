"""Generate ``kinetic_fem/solvers/fem_cooling_gamma2_table.py``: the gamma = 2 anchor states.

Each anchor is the cooling state at one inelasticity by the path the anchored start
replaces (at alpha <= 0.5 the pseudo-transient iteration from a Gaussian;
:func:`kinetic_fem.solvers.fem_cooling_alpha.alpha_chain` from alpha 0.5 on the default
mesh, :func:`~kinetic_fem.solvers.fem_cooling_quasi.quasi_elastic_chain` below eps 0.01),
reached through ``cooling_state(..., vertices=...)`` (an explicit mesh skips the anchored
start); the table stores :math:`\\varepsilon \\ln f` at ``--points`` velocities
(:func:`kinetic_fem.solvers.fem_cooling_gamma2.anchor_samples`).

    python benchmarks/gamma2_anchors.py [--count 36] [--points 65] [--eps-max 1]
        [--eps-min 5e-4]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from kinetic_fem.model import CoolingProblem  # noqa: E402
from kinetic_fem.solvers.fem_cooling import cooling_state  # noqa: E402
from kinetic_fem.solvers.fem_cooling_alpha import DIRECT_EPS, quasi_seed_vertices  # noqa: E402
from kinetic_fem.solvers.fem_cooling_gamma2 import anchor_table  # noqa: E402
from kinetic_fem.solvers.fem_cooling_mesh import (  # noqa: E402
    hcs_bulk,
    hcs_cutoff,
    hcs_spacing,
    hcs_vertices,
)

TABLE = Path(__file__).resolve().parents[1] / "kinetic_fem/solvers/fem_cooling_gamma2_table.py"


def chain_state(eps: float):
    """The state at ``eps`` by the continuation (explicit vertices: no anchored start)."""
    problem = CoolingProblem.from_parameters(1.0 - eps, kernel=2.0)
    if eps < DIRECT_EPS:
        verts = quasi_seed_vertices(2.0, 2)
    else:
        verts = hcs_vertices(hcs_cutoff(problem), hcs_spacing(problem), gamma=2.0,
                             bulk=hcs_bulk(eps))
    return cooling_state(problem, vertices=verts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=36)
    parser.add_argument("--points", type=int, default=65)
    parser.add_argument("--eps-max", type=float, default=1.0)
    parser.add_argument("--eps-min", type=float, default=5e-4)
    args = parser.parse_args()
    eps_values = [float(e) for e in np.geomspace(args.eps_max, args.eps_min, args.count)]
    states = []
    for eps in eps_values:
        t0 = time.process_time()
        state = chain_state(eps)
        states.append(state)
        print(f"eps {eps:.6g}: zeta/eps {state.zeta / eps:.12f}, {state.u.size} dofs, "
              f"cut-off {state.disc.vertices[-1]:.3f}, {time.process_time() - t0:.2f} CPU s",
              flush=True)
    TABLE.write_text(anchor_table(eps_values, states, args.points))
    print(f"wrote {TABLE}")


if __name__ == "__main__":
    main()
