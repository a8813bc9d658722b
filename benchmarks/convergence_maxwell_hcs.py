"""Convergence of the FEM cooling state of the inelastic Maxwell model to the closed form.

The exact state is f(c) = 2/(pi (1+c^2)^2) at unit temperature for every alpha
(Baldassarri, Marini Bettolo Marconi and Puglisi 2002), zeta = (1 - alpha^2)/4.  For each
alpha and bulk spacing h0 (the whole mesh refines with it) this prints the number of
dofs, the zeta error, the largest relative error of f over |c| <= 10 for the recovered
values (the distribution ``kf.solve_cooling`` returns) and for the raw Galerkin ln f_h
at the element nodes, and the observed orders.

``--mesh tail`` (the default since issue 16): P3 (``--order``) on the mesh of
:func:`kinetic_fem.solvers.fem.cooling_maxwell.maxwell_tail_vertices` to c = 200 with the
analytic tail beyond; ``--mesh truncated``: P2 on
:func:`kinetic_fem.solvers.fem.cooling_tail.power_tail_vertices` to c = 1e8 (the former
default, reached with ``cutoff=1e8``).

Usage::

    python benchmarks/convergence_maxwell_hcs.py [--alphas 0.3 0.5 0.9]
        [--spacings 0.16 0.08 0.04] [--mesh tail|truncated] [--order 3]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem import cooling_maxwell as fem_cooling_maxwell
from kinetic_fem.solvers.fem import cooling_tail as fem_cooling_tail


def errors(alpha: float, spacing: float, mesh: str = "tail",
           order: int = 3) -> tuple[int, float, float, float, float]:
    """(dofs, zeta error, recovered f error, raw nodal f error, CPU s) over |c| <= 10."""
    problem = kf.CoolingProblem.from_parameters(alpha, kernel=0.0)
    start = time.process_time()
    if mesh == "tail":
        state = fem_cooling.cooling_state(problem, spacing=spacing, order=order)
    else:
        state = fem_cooling.cooling_state(problem, spacing=spacing, cutoff=1e8)
    cpu = time.process_time() - start
    # what kf.solve_cooling(alpha, kernel=0.0, spacing=spacing) returns
    dist = (state.distribution() if isinstance(state, fem_cooling_maxwell.MaxwellTailState)
            else fem_cooling_tail.recovered_distribution(state.disc, state.u))
    zeta_err = abs(state.zeta / ((1.0 - alpha**2) / 4.0) - 1.0)
    c = np.linspace(0.0, 10.0, 4001)
    rec = float(np.abs(dist.f(c) / fem_cooling.maxwell_hcs(c) - 1.0).max())
    verts = state.disc.vertices
    nodes = np.union1d(verts, np.concatenate([verts[:-1] + k / state.disc.order * np.diff(verts)
                                              for k in range(1, state.disc.order)]))
    nodes = nodes[(nodes >= 0.0) & (nodes <= 10.0)]
    raw = float(np.abs(state.disc.evaluate(state.u, nodes)
                       / fem_cooling.maxwell_hcs(nodes) - 1.0).max())
    return int(state.u.size), zeta_err, rec, raw, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+", default=[0.3, 0.5, 0.9])
    parser.add_argument("--spacings", type=float, nargs="+", default=[0.16, 0.08, 0.04])
    parser.add_argument("--mesh", choices=["tail", "truncated"], default="tail")
    parser.add_argument("--order", type=int, default=3, help="degree on the tail mesh")
    args = parser.parse_args()
    print("| alpha | h0 | dofs | zeta error | f error, recovered | order | f error, raw "
          "nodal | order | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for alpha in args.alphas:
        prev = None
        for h0 in args.spacings:
            n, ez, rec, raw, cpu = errors(alpha, h0, args.mesh, args.order)
            o_rec = o_raw = ""
            if prev is not None:
                ratio = math.log(prev[0] / h0)
                o_rec = f"{math.log(prev[1] / rec) / ratio:.2f}"
                o_raw = f"{math.log(prev[2] / raw) / ratio:.2f}"
            print(f"| {alpha:g} | {h0:g} | {n} | {ez:.1e} | {rec:.2e} | {o_rec} | {raw:.2e} "
                  f"| {o_raw} | {cpu:.1f} |", flush=True)
            prev = (h0, rec, raw)


if __name__ == "__main__":
    main()
