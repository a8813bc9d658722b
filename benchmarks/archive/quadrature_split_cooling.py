"""Issue 16 (i16c2): the Gauss degree-9 rule only on the outer-edge elements of the hump mesh?

The near-elastic cooling state (hard rods, default P3 at 0.2 hump widths, Gauss degree
``HUMP_INTORDER = 9`` on every element) is re-solved by Newton's method from itself with
the collision's outer quadrature points of degree ``LOW`` (the ``2 * order + 1`` rule) on
the elements where :math:`\\ln f_h` falls less than a threshold per element and degree 9
on the others (the kernels take the outer points as flattened arrays with their element
indices, so no kernel change is needed); ``inner LOW``: the inner pieces and the scikit-fem
forms at degree ``LOW`` as well.  Prints how many elements keep degree 9, the moves of
zeta, a2 and ln f (f > 1e-30) against the degree-9 state and the time of one collision
call with the Jacobian.

    python benchmarks/quadrature_split_cooling.py EPS [LOW]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from skfem.quadrature import get_quadrature  # noqa: E402
from skfem.refdom import RefLine  # noqa: E402

from kinetic_fem.model import CoolingProblem  # noqa: E402
from kinetic_fem.solvers import fem_cooling as fc  # noqa: E402
from kinetic_fem.solvers.fem import FEMDiscretisation  # noqa: E402
from kinetic_fem.solvers.fem_cooling_newton import newton_cooling  # noqa: E402


def split(full: FEMDiscretisation, edge: np.ndarray, low: int, inner: int):
    """A discretisation whose collision outer points are of degree ``low`` off ``edge``."""
    verts = full.vertices
    disc = FEMDiscretisation(full.alpha, verts, full.order, inner, gamma=full.gamma)
    xq9, wq9, eq9 = full.points
    xr, wr = get_quadrature(RefLine, low)
    h = np.diff(verts)
    lo = ~edge
    x5 = verts[:-1][lo][:, None] + h[lo][:, None] * xr[0][None, :]
    w5 = h[lo][:, None] * wr[None, :]
    e5 = np.repeat(np.flatnonzero(lo), xr.shape[1]).reshape(x5.shape)
    keep = edge[eq9]
    x = np.concatenate([xq9[keep], x5.ravel()])
    w = np.concatenate([wq9[keep], w5.ravel()])
    e = np.concatenate([eq9[keep], e5.ravel()])
    o = np.argsort(x, kind="stable")
    disc.__dict__["points"] = (x[o].copy(), w[o].copy(), e[o].copy())  # the cached property
    return disc


def call_time(disc: FEMDiscretisation, u: np.ndarray) -> float:
    t0 = time.process_time()
    for _ in range(3):
        disc.collision(u, jacobian=True, even=True)
    return (time.process_time() - t0) / 3


def main(eps: float, low: int) -> None:
    state = fc.cooling_state(CoolingProblem.from_parameters(1.0 - eps))
    full = state.disc
    verts = full.vertices
    fall = np.abs(np.diff(np.log(full.evaluate(state.u, verts))))
    xq, wq, _ = full.points

    def a2(st) -> float:
        return float(np.sum(wq * xq**4 * st.disc.evaluate(st.u, xq))) / 3.0 - 1.0

    t9 = call_time(full, state.u)
    print(f"eps {eps:g}: P{full.order}, {state.u.size} dofs, {verts.size - 1} elements; "
          f"degree-9 collision call with Jacobian {t9:.4f} CPU s")
    mon = state.u > np.log(1e-30)
    for thresh, inner in [(0.3, 9), (0.1, 9), (0.03, 9), (0.3, low), (0.1, low)]:
        edge = fall > thresh
        disc = split(full, edge, low, inner)
        st = newton_cooling(disc, state.u, state.zeta, tol=1e-11, pseudo_time=np.inf)
        t = call_time(disc, state.u)
        print(f"ln f falls > {thresh} per element: {edge.sum()}/{edge.size} elements at "
              f"degree 9, inner {inner}: converged {st.info.converged}, dzeta "
              f"{abs(st.zeta / state.zeta - 1):.1e}, da2 {abs(a2(st) - a2(state)):.1e}, "
              f"d ln f {np.abs(st.u - state.u)[mon].max():.1e}, call {t:.4f} s "
              f"({t9 / t:.2f}x)", flush=True)


if __name__ == "__main__":
    main(float(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 7)
