"""Meshes for the near-elastic cooling state and an a posteriori error indicator.

Near elastic collisions, :math:`\\varepsilon = 1 - \\alpha \\to 0`, the scaled homogeneous
cooling state is two humps at :math:`c = \\pm 1` of width :math:`w = \\varepsilon^{1/3}`
(claims C11, C12): with :math:`y = (1 - c)/w`,
:math:`f(c) \\approx [\\psi(y) + \\psi((1 + c)/w)]/(2w)`, where :math:`\\psi` solves the
quasi-elastic equation of :mod:`kinetic_fem.solvers.scaling_psi`.  Its tails fix the
mesh: outside the hump :math:`\\ln\\psi \\simeq y^3/3` (:math:`y < 0`), so
:math:`(\\ln f)''' \\simeq -2/w^3` is constant and the elements stay of size
:math:`k w` out to the cut-off (where :math:`|y|^3/3` reaches ``decades`` decades, or
where a starting guess has fallen as far: at moderate eps the edge is slower); inside,
:math:`\\ln\\psi \\simeq -\\langle y^2\\rangle y` is linear and the elements grow
linearly with the distance from the hump (geometric grading), down to the centre
:math:`c = 0`, where the two inner tails meet in a :math:`\\ln\\cosh` of width
:math:`w/\\langle y^2\\rangle` and the elements shrink again to :math:`k w`.

Error indicator.  For P2 elements the interpolation error of :math:`u = \\ln f` on an
element :math:`K` of length :math:`h_K` is
:math:`|u'''|\\, h_K^3/(72\\sqrt3)` at most (the maximum of
:math:`|t(t^2 - h^2/4)|/6` on :math:`|t| \\le h/2`); :math:`u'''` is recovered from the
jumps of the element-wise constant :math:`u_h''` between neighbours,

.. math::

    \\eta_K = \\frac{h_K^3}{72\\sqrt3}\\,
    \\max\\Big(\\frac{|u''_{K+1} - u''_K|}{(h_K + h_{K+1})/2},
               \\frac{|u''_K - u''_{K-1}|}{(h_{K-1} + h_K)/2}\\Big),

an estimate of the relative error of :math:`f_h` on :math:`K` (the error of
:math:`\\ln f`).  Its reliability against the true error on refinement sequences is
measured in ``benchmarks/convergence_fem_cooling.py``.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from .mesher import log_drop_size, march

__all__ = ["hump_vertices", "element_indicator", "refined_vertices", "HUMP_DECADES",
           "PSI_Y2", "EDGE_EFOLDS"]

HUMP_DECADES = 45.0
"""The cut-off is where the outer edge :math:`e^{-|y|^3/3}` of the humps reaches
:math:`10^{-45}` (or where the far tail :math:`e^{-c/\\zeta}` does, if farther)."""
EDGE_EFOLDS = 1.0
"""Largest fall of the outer edge :math:`e^{-|y|^3/3}` of the humps over one element, in
e-folds.  Coarser elements there make the Galerkin drift unstable: the linearised
discrete operator has eigenvalues with positive real part localised at the cut-off
(about :math:`+290\\varepsilon` at :math:`\\varepsilon = 10^{-4}` and
:math:`+860\\varepsilon` at :math:`10^{-5}` on elements of 0.07 hump widths, 3 e-folds
each at the cut-off; none with this rule), and Newton's method diverges."""
PSI_Y2 = 1.2097
""":math:`\\langle y^2\\rangle_\\psi`, the decay rate of the inner tail of the humps."""


def _check(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return value


def hump_vertices(eps: float, zeta: float, *, resolution: float = 0.1,
                  growth: float = 0.2, max_size: float = 0.1, core: float = 3.0,
                  decades: float = HUMP_DECADES,
                  cutoff: float | None = None, efolds: float = EDGE_EFOLDS,
                  edge_slope: Callable[[float], float] | None = None
                  ) -> NDArray[np.float64]:
    """Symmetric vertices that follow the two humps of the near-elastic cooling state.

    Parameters
    ----------
    eps : float
        Inelasticity :math:`1 - \\alpha`, in (0, 1).
    zeta : float
        Cooling rate estimate (unit temperature); sets the far-tail cut-off.
    resolution : float
        Element size in the humps and at the centre, in hump widths :math:`w =
        \\varepsilon^{1/3}` (the P2 error of :math:`\\ln f` there scales as its cube).
    growth : float
        Linear growth rate of the element size with the distance from the hump core
        and from the centre, in units of ``resolution`` per hump width.
    max_size : float
        Largest element (thermal velocities).
    core : float
        Half-width of the inner side of the hump core, in hump widths (beyond it the
        inner tail is exponential and the elements grow).
    decades : float
        The cut-off is where the outer edge of the humps falls by this many decades.
    cutoff : float, optional
        An explicit cut-off (thermal velocities), e.g. where a starting guess has fallen
        ``decades`` decades; at least the core's outer edge :math:`1 + w (3 \\ln
        10^{d})^{1/3}`.  The mesh ends at the first vertex at or beyond it.
    efolds : float
        Largest fall of :math:`f` over one element of the outer edge, in e-folds
        (:data:`EDGE_EFOLDS`).
    edge_slope : callable, optional
        :math:`|d\\ln f/dc|` at :math:`c > 1` of a starting guess; default that of
        :math:`\\psi`, :math:`y^2/w` with :math:`y = (c - 1)/w`, out to where it has
        fallen ``decades`` decades, and :math:`1/\\zeta` (the far tail) beyond.

    Returns
    -------
    ndarray, shape (2 E + 1,)
        Increasing vertices, symmetric about 0, with a vertex at 0.

    Examples
    --------
    >>> v = hump_vertices(1e-3, 1e-3)
    >>> bool(v[0] == -v[-1] and np.all(np.diff(v) > 0) and 0.0 in v)
    True
    >>> bool(1.677 < v[-1] < 1.678)  # just beyond 1 + w (3 ln 10^45)^(1/3) = 1.6771
    True
    """
    eps = _check("eps", eps)
    if eps >= 1.0:
        raise ValueError(f"eps must be in (0, 1), got {eps!r}")
    zeta, resolution = _check("zeta", zeta), _check("resolution", resolution)
    growth, max_size = _check("growth", growth), _check("max_size", max_size)
    efolds = _check("efolds", efolds)
    w = eps ** (1.0 / 3.0)
    log_drop = decades * math.log(10.0)
    outer = (3.0 * log_drop) ** (1.0 / 3.0)
    if cutoff is None:
        cutoff = max(1.0 + w * outer, 1.0 + zeta * log_drop)
    else:
        cutoff = max(_check("cutoff", cutoff), 1.0 + w * outer)
    lo_core = max(1.0 - core * w, 0.0)
    h0 = resolution * w
    if edge_slope is None:
        def edge_slope(c: float) -> float:
            # psi's outer edge, then the far tail e^(-c/zeta)
            y = (c - 1.0) / w
            return y * y / w if y < outer else 1.0 / zeta

    def size(c: float) -> float:
        if c > 1.0:  # the outer edge: at most ``efolds`` e-folds per element
            return log_drop_size(float(edge_slope(c)), efolds, largest=min(h0, max_size))
        if c >= lo_core:  # the hump
            return min(h0, max_size)
        dist = min(c, lo_core - c)  # the inner tail: geometric grading
        return min(h0 * (1.0 + growth * dist / w), max_size)

    # the mesh ends at the first vertex beyond the cut-off: a last element stretched to
    # end exactly there falls 3 to 4 e-folds and is unstable (a growing mode of the
    # linearised discrete operator at the cut-off, +3.7 eps at eps = 2.4e-5)
    return march(size, cutoff)


def _second_derivatives(vertices: NDArray[np.float64], u_vertices: NDArray[np.float64],
                        u_midpoints: NDArray[np.float64]) -> NDArray[np.float64]:
    h = np.diff(vertices)
    return 4.0 * (u_vertices[:-1] - 2.0 * u_midpoints + u_vertices[1:]) / h**2


def element_indicator(vertices: NDArray[np.float64], u_vertices: NDArray[np.float64],
                      u_midpoints: NDArray[np.float64]) -> NDArray[np.float64]:
    """The recovery indicator :math:`\\eta_K` of the module notes, per element.

    Parameters
    ----------
    vertices : ndarray, shape (E + 1,)
        Increasing mesh vertices.
    u_vertices : ndarray, shape (E + 1,)
        :math:`u_h = \\ln f_h` at the vertices.
    u_midpoints : ndarray, shape (E,)
        :math:`u_h` at the element midpoints.

    Returns
    -------
    ndarray, shape (E,)
        Estimated maximum error of :math:`\\ln f_h` on each element.

    Examples
    --------
    >>> x = np.linspace(0.0, 2.0, 21); m = 0.5 * (x[1:] + x[:-1])
    >>> eta = element_indicator(x, x**3, m**3)  # u''' = 6: eta = 6 h^3/(72 sqrt 3)
    >>> bool(np.allclose(eta, 6 * 0.1**3 / (72 * np.sqrt(3))))
    True
    """
    vertices = np.asarray(vertices, dtype=float)
    u_vertices = np.asarray(u_vertices, dtype=float)
    u_midpoints = np.asarray(u_midpoints, dtype=float)
    if vertices.ndim != 1 or vertices.size < 3 or np.any(np.diff(vertices) <= 0):
        raise ValueError("vertices must be an increasing 1-D array of at least 3 points")
    if u_vertices.shape != vertices.shape or u_midpoints.shape != (vertices.size - 1,):
        raise ValueError(f"u_vertices must have shape {vertices.shape} and u_midpoints "
                         f"({vertices.size - 1},), got {u_vertices.shape} and "
                         f"{u_midpoints.shape}")
    h = np.diff(vertices)
    d2 = _second_derivatives(vertices, u_vertices, u_midpoints)
    d3 = np.abs(np.diff(d2)) / (0.5 * (h[1:] + h[:-1]))
    third = np.empty_like(h)
    third[0], third[-1] = d3[0], d3[-1]
    third[1:-1] = np.maximum(d3[1:], d3[:-1])
    return third * h**3 / (72.0 * math.sqrt(3.0))


def refined_vertices(vertices: NDArray[np.float64], indicator: NDArray[np.float64],
                     target: float) -> NDArray[np.float64]:
    """Split each element whose indicator exceeds ``target`` into equal pieces.

    An element is cut into :math:`\\lceil(\\eta_K/\\mathrm{target})^{1/3}\\rceil` pieces
    (P2: the error of :math:`\\ln f` falls as :math:`h^3`), so a symmetric indicator
    keeps a symmetric mesh.

    Parameters
    ----------
    vertices : ndarray, shape (E + 1,)
        Increasing vertices.
    indicator : ndarray, shape (E,)
        Per-element error estimates (:func:`element_indicator`).
    target : float
        Largest acceptable indicator.

    Returns
    -------
    ndarray
        The refined vertices (the old ones included).

    Examples
    --------
    >>> refined_vertices(np.array([0.0, 1.0, 2.0]), np.array([8e-6, 1e-7]), 1e-6)
    array([0. , 0.5, 1. , 2. ])
    """
    vertices = np.asarray(vertices, dtype=float)
    indicator = np.asarray(indicator, dtype=float)
    target = _check("target", target)
    if indicator.shape != (vertices.size - 1,):
        raise ValueError(f"indicator must have shape ({vertices.size - 1},), got "
                         f"{indicator.shape}")
    pieces = np.maximum(np.ceil((indicator / target) ** (1.0 / 3.0) - 1e-9), 1).astype(int)
    out = [vertices[:1]]
    for a, b, m in zip(vertices[:-1], vertices[1:], pieces, strict=True):
        out.append(np.linspace(a, b, m + 1)[1:])
    return np.concatenate(out)
