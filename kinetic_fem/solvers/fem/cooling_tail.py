"""The power-law tail of the inelastic Maxwell model's cooling state: mesh and recovery.

The homogeneous cooling state of the Maxwell kernel (:math:`\\gamma = 0`) is
:math:`f(c) = 2/(\\pi(1+c^2)^2)` at unit temperature for every alpha (Baldassarri,
Marini Bettolo Marconi and Puglisi, Europhys. Lett. 58, 14 (2002)).  Its :math:`c^{-4}`
tail carries :math:`4/(\\pi V)` of the energy beyond :math:`|c| = V`: 4 % beyond
:math:`c = 30`, and the tail at :math:`c` is fed by collisions from
:math:`2c/(1-\\alpha)`, so the FEM state of :mod:`kinetic_fem.solvers.fem.cooling`
needs the tail resolved out to :math:`V = 10^8`.  Two things set its accuracy:

* **The far-tail mesh.**  P2 interpolates :math:`\\ln f \\simeq -4\\ln c` on an element
  :math:`[c, rc]` with error :math:`\\propto (r-1)^3`.  The former mesh (ratio 1.1 beyond
  :math:`c = 30`) put errors of 1e-4 into the tail, which the energy it carries fed back
  into the bulk (1.2e-4 at :math:`c \\le 10`, alpha = 0.5).  :func:`power_tail_vertices`
  ties every ratio to the bulk spacing :math:`h_0`: uniform :math:`h_0` up to
  :math:`c = 2`, geometric with ratio :math:`1 + h_0/2` up to :math:`c = 30` and
  :math:`1 + \\min(5h_0/4, 0.1)` beyond, so one parameter refines the whole mesh.

* **An element-wise oscillation of** :math:`\\ln f_h`.  For the Maxwell kernel the loss
  is local (rate 1) and the gain a smoothing integral; the Galerkin state then carries,
  on each element, a component :math:`s(2 - 12t(1-t))` (:math:`t` the element
  coordinate), +2s at the vertices and -s at the midpoint, of zero mean over the
  element, with :math:`s = O(h_0^2)` (measured 1.9e-4, 4.9e-5, 1.2e-5 at
  :math:`h_0` = 0.08, 0.04, 0.02, near :math:`c = 0.3`).  It vanishes at the two-point
  Gauss-Legendre points :math:`t = (1 \\pm 1/\\sqrt3)/2` of every element, where
  :math:`\\ln f_h` is superconvergent.  :func:`recovered_log_f` interpolates
  :math:`\\ln f_h` from those points (a cubic spline in :math:`\\operatorname{asinh} c`,
  so that the :math:`-4\\ln c` tail is nearly linear), and
  :func:`recovered_distribution` returns the state with the recovered values on the
  quadrature points (the oscillation has zero mean on each element, so mass and
  temperature are unchanged to the Newton tolerance).

Since issue 16 (eighth round) the default state ends its mesh at :math:`c = 200` and
continues the tail analytically (:mod:`kinetic_fem.solvers.fem.cooling_maxwell`, P3,
recovered from the three Gauss points of every element); the truncated mesh below is used
with ``cutoff``.

A discrete state with another power-law tail (infinite energy: the scaled equation
admits :math:`c^{-p}` tails with :math:`p < 3` in the continuum, and a truncated mesh
can mimic them) is excluded by the unit-temperature constraint on the whole mesh,
which is why :math:`V` must reach where the energy beyond is negligible
(:data:`POWER_TAIL_CUTOFF`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from ...distribution import VelocityDistribution
from ...operators.mesher import march

__all__ = ["maxwell_hcs", "POWER_TAIL_CUTOFF", "POWER_TAIL_SPACING", "FAR_RATIO_FACTOR",
           "FAR_RATIO_MAX", "power_tail_vertices", "superconvergent_points", "recovered_log_f",
           "recovered_distribution"]

POWER_TAIL_CUTOFF = 1e8
"""Cut-off :math:`V`: the energy beyond, :math:`4/(\\pi V)`, is 1.3e-8."""
POWER_TAIL_SPACING = 0.02
"""Default bulk element size :math:`h_0` (convergence study in :func:`power_tail_vertices`)."""
FAR_RATIO_FACTOR = 1.25
"""Geometric ratio beyond :math:`c = 30`: :math:`1 + ` this :math:`\\times h_0`, at most
:math:`1 +` :data:`FAR_RATIO_MAX`."""
FAR_RATIO_MAX = 0.1
"""The far ratio is at most :math:`1 + r` with :math:`r` this value (the coarse meshes
of the mesh sequencing: Newton from the Gaussian start fails at alpha = 0.9 on a far ratio
of 1.25)."""
_NEAR_END = 30.0
_BULK_END = 2.0


def power_tail_vertices(c_max: float, spacing: float, *, near_factor: float = 0.5,
                        far_factor: float = FAR_RATIO_FACTOR) -> NDArray[np.float64]:
    """Symmetric vertices for the :math:`c^{-4}` tail: uniform, then two geometric ratios.

    Element size :math:`h(c) = h_0` up to :math:`c = 2`, :math:`h_0 c/2` up to
    :math:`c = 30`, :math:`\\min(\\tfrac54 h_0, 0.1)\\, c` beyond (module notes).

    Parameters
    ----------
    c_max : float
        Half-width of the mesh (thermal velocities), e.g. :data:`POWER_TAIL_CUTOFF`.
    spacing : float
        Bulk element size :math:`h_0`.
    near_factor : float
        Ratio :math:`1 +` this :math:`\\times h_0` from :math:`c = 2` to 30.
    far_factor : float
        Ratio :math:`1 + \\min(` this :math:`\\times h_0,` :data:`FAR_RATIO_MAX`:math:`)`
        beyond :math:`c = 30`.

    Returns
    -------
    ndarray
        Vertices symmetric about 0, including 0.

    Examples
    --------
    >>> v = power_tail_vertices(1e8, 0.08)
    >>> bool(v[-1] == 1e8 and np.all(np.diff(v) > 0) and v[v.size // 2] == 0.0)
    True
    """
    if not spacing > 0.0 or not c_max > 0.0:
        raise ValueError(f"spacing={spacing!r} and c_max={c_max!r} must be > 0")
    near = near_factor * spacing
    far = min(far_factor * spacing, FAR_RATIO_MAX)

    def size(c: float) -> float:
        return max(spacing if c < _BULK_END else (near if c < _NEAR_END else far) * c,
                   spacing)

    return march(size, c_max, end="snap")


def superconvergent_points(vertices: NDArray, order: int = 2) -> NDArray[np.float64]:
    """The ``order`` Gauss-Legendre points of every element, sorted.

    The Galerkin oscillation of :math:`\\ln f_h` on an element is (to leading order) the
    Legendre polynomial of degree ``order`` in the element coordinate (P2: the
    :math:`s(2 - 12t(1-t))` of the module notes; P3 measured the same way, amplitude
    1e-5 at :math:`c` = 50-100 on the ratio-1.025 elements of the tail-closure mesh), so
    it vanishes at these points.

    Parameters
    ----------
    vertices : ndarray
        Increasing mesh vertices.
    order : int
        Element degree: the number of points per element.

    Returns
    -------
    ndarray
        For P2, :math:`a + (b - a)(1 \\pm 1/\\sqrt3)/2` for every element :math:`[a, b]`.
    """
    v = np.asarray(vertices, dtype=float)
    a, h = v[:-1], np.diff(v)
    gx = 0.5 * (np.polynomial.legendre.leggauss(order)[0] + 1.0)
    return np.sort((a[:, None] + h[:, None] * gx[None, :]).ravel())


def recovered_log_f(disc, u: NDArray, c: NDArray) -> NDArray[np.float64]:
    """:math:`\\ln f` at ``c`` recovered from the superconvergent points of ``u_h``.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation of the (even) state.
    u : ndarray
        Coefficients of :math:`u_h = \\ln f_h`.
    c : ndarray
        Points inside the mesh.

    Returns
    -------
    ndarray
        The cubic spline, in :math:`\\operatorname{asinh} c`, of :math:`\\ln f_h` at the
        ``disc.order`` Gauss points of every element (even in ``c``).
    """
    pts = superconvergent_points(disc.vertices, disc.order)
    pts = pts[pts > 0.0]
    log_f = np.log(disc.evaluate(u, pts))
    x = np.arcsinh(pts)
    spline = CubicSpline(np.concatenate([-x[::-1], x]), np.concatenate([log_f[::-1], log_f]))
    return np.asarray(spline(np.arcsinh(np.abs(np.asarray(c, dtype=float)))))


def recovered_distribution(disc, u: NDArray, **kwargs) -> VelocityDistribution:
    """The state on the quadrature points with the recovered values of :math:`f`.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation of the (even) state.
    u : ndarray
        Coefficients of :math:`u_h = \\ln f_h`.
    **kwargs
        Passed to :meth:`VelocityDistribution.from_values` (``method``, ``params``,
        ``info``).

    Returns
    -------
    VelocityDistribution
    """
    xq, wq, _ = disc.points
    values = np.exp(recovered_log_f(disc, u, xq))
    return VelocityDistribution.from_values(xq, values, weights=wq, **kwargs)


def maxwell_hcs(c: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`f(c) = 2/(\\pi(1+c^2)^2)`, the Maxwell-model HCS at unit temperature.

    Parameters
    ----------
    c : ndarray
        Scaled velocities.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> from scipy.integrate import quad
    >>> round(quad(lambda c: c**2 * maxwell_hcs(c), -np.inf, np.inf)[0], 12)
    1.0
    """
    c = np.asarray(c, dtype=float)
    return 2.0 / (math.pi * (1.0 + c * c) ** 2)
