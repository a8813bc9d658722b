r"""
Near-elastic cooling state on a mesh that follows the humps
===========================================================

Near elastic collisions, :math:`\varepsilon = 1 - \alpha \to 0`, the homogeneous cooling
state (``kf.solve_cooling(alpha)``, Galerkin FEM on :math:`\ln f`) is two humps at
:math:`c = \pm 1` of width :math:`w = \varepsilon^{1/3}`; on
:math:`y = (1 - c)/w` each tends to the solution :math:`\psi` of the quasi-elastic
equation (claims C11, C12).  The default mesh
(:func:`kinetic_fem.operators.adaptive.hump_vertices`) is built from these scales:
elements of ``resolution`` hump widths over the humps; in the outer edge
(:math:`\ln f \simeq -|y|^3/3`) at most ``EDGE_EFOLDS`` e-folds of :math:`f` per element,
following the slope of the starting guess (coarser edge elements make the Galerkin drift
unstable), with a 5-point Gauss rule (``HUMP_INTORDER``: the 3-point rule's error on
:math:`e^{u_h}` over the exponential edge, amplified by :math:`\varepsilon^{-2/3}`, was
the whole error of :math:`\ln f` there); growing geometrically along the exponential
inner tail and shrinking again at :math:`c = 0` where the two inner tails meet.  The
state is reached by continuation in :math:`\varepsilon` from 0.1 (measured down to
:math:`\varepsilon = 10^{-6}`).

Two error estimates of :math:`\ln f_h` are plotted per element:

* the local recovery indicator :math:`\eta_K = h_K^3 |u'''|/(72\sqrt3)`
  (:meth:`~kinetic_fem.solvers.fem.cooling.CoolingState.indicator`), which misses the
  error the cooling drift carries outward (it underestimates the true error by 10^3 at
  :math:`\varepsilon = 10^{-4}`);
* the two-level estimate (:meth:`~kinetic_fem.solvers.fem.cooling.CoolingState.error_estimate`):
  one Newton step of the equations on the mesh with every element bisected, a solve of
  the global linearised problem, so transported error is included
  (``benchmarks/results/fem_cooling.md`` compares both with the true error).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import kinetic_fem as kf
from kinetic_fem.solvers.fem import cooling as fem_cooling

TEST_KWARGS = {"eps": 0.07, "resolution": 0.14}


def main(eps: float = 1e-3, resolution: float = 0.07) -> kf.VelocityDistribution:
    """The cooling state at ``alpha = 1 - eps`` on the hump mesh.

    Parameters
    ----------
    eps : float
        Inelasticity, below ``fem_cooling.HUMP_EPS`` = 0.1.
    resolution : float
        Element size in the humps, in hump widths eps^(1/3).

    Returns
    -------
    VelocityDistribution
        ``info.extra``: ``zeta``, the mesh ``vertices``, the per-element recovery
        ``indicator`` and two-level ``estimate`` of the error of ln f, and the two-level
        estimate ``zeta_estimate`` of the relative error of zeta.
    """
    problem = kf.CoolingProblem.from_parameters(1.0 - eps)
    state = fem_cooling.cooling_state(problem, resolution=resolution)
    estimate, zeta_estimate = state.error_estimate()
    info = replace(state.info, extra={"zeta": state.zeta, "vertices": state.disc.vertices,
                                      "indicator": state.indicator(), "estimate": estimate,
                                      "zeta_estimate": zeta_estimate})
    return state.disc.distribution(state.u, method="fem", info=info)


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    dist = main()
    verts, eta = dist.info.extra["vertices"], dist.info.extra["indicator"]
    mid = 0.5 * (verts[1:] + verts[:-1])
    right = mid > 0
    fig, (ax0, ax1) = plt.subplots(2, 1, sharex=True)
    c = np.linspace(0.0, verts[-1], 4001)
    ax0.semilogy(c, dist.f(c))
    ax0.set(ylabel="f(c)", title=f"HCS, eps = 1e-3: zeta = {dist.info.extra['zeta']:.12f}")
    ax1.semilogy(mid[right], np.diff(verts)[right], label="element size h")
    ax1.semilogy(mid[right], eta[right], label="recovery indicator")
    ax1.semilogy(mid[right], dist.info.extra["estimate"][right], label="two-level estimate")
    ax1.set(xlabel="c", ylim=(1e-16, 1))
    ax1.legend()
    plt.show()
