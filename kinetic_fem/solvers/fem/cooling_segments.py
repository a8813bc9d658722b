"""Segments of the free-cooling transient: remaps and mesh extents.

Helpers of :mod:`kinetic_fem.solvers.fem.cooling_transient` (see there for the method)
and of the mixture's :mod:`kinetic_fem.solvers.fem.mixture_cooling_transient` (one
species at a time): :func:`segment_vertices`, :func:`remap_log_density`,
:func:`remap_vertices` and :func:`normalise` (the state in a new velocity unit on a new
mesh, unit mass and its temperature restored),
:func:`usable_extent` and :func:`steepest_drop` (where a mesh may end and when a segment
must end), :func:`padded_outputs` (outputs of different meshes as one array).
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ...exceptions import ConvergenceError
from ...operators.fem_discretisation import FEMDiscretisation
from ...operators.fem_kernels import evaluate_field

__all__ = ["normalise", "remap_log_density", "usable_extent", "segment_vertices",
           "steepest_drop", "remap_vertices", "padded_outputs", "HasMasses", "TAIL_LEVEL",
           "EDGE_DROP", "MAX_ELEMENT_DROP", "GRADE_DROP",
           "CONTINUE_WIDTH", "EDGE_ELEMENTS", "MIN_EXTENT"]

TAIL_LEVEL = 1e-30
"""The mesh of a segment ends where :math:`P` has fallen to this fraction of its peak
(or at ``cutoff`` thermal velocities, if nearer)."""

EDGE_DROP = 3.0
"""A segment ends early when :math:`\\ln P_h` falls by more than this over an element
(the far tail steepens as it decays at the loss rate :math:`\\nu(v)`): with P2 elements a
vertex mass :math:`\\int\\varphi_i P_h` is then dominated by the negative lobes of
:math:`\\varphi_i`, and Newton's method fails (measured: the edge dof ran away by 10 in
ln P at t = 3.6 for hard rods, alpha 0.8; gamma = 2 stopped at t = 0.62 when only the
outermost element was watched).  The remap then ends the mesh where the fall is below
:data:`MAX_ELEMENT_DROP`."""

MAX_ELEMENT_DROP = 2.0
"""A new mesh ends before :math:`\\ln P_h` falls by more than this over an element:
steeper, the vertex masses of P2 elements lose positivity and the tail oscillates
(measured: a Gaussian start at 0.25 per element beyond 11 thermal velocities)."""

GRADE_DROP = 1.0
"""A new mesh is refined where :math:`\\ln P` would fall by more than this over an element
of the nominal size (:func:`remap_vertices`): the steep tails of nearly elastic states
(a viscoelastic gas late in its cooling, :math:`\\ln f` falling like :math:`c^3`) then
stay resolved, where a uniform mesh ended them below :data:`MIN_EXTENT` (measured:
viscoelastic delta 0.2 at t = 70-111 for spacings 0.5 and 0.25)."""

CONTINUE_WIDTH = 0.25
"""Width (old units, about thermal velocities) over which the slope of :math:`\\ln P` is
taken to continue it beyond the resolved part at a remap (:func:`remap_log_density`)."""

GRADE_MIN = 1.0 / 16.0
"""Smallest element of a graded mesh, as a fraction of the nominal size."""

EDGE_ELEMENTS = 2
"""Outermost elements dropped at a remap."""

MIN_EXTENT = 4.0
"""Smallest mesh half-width (thermal velocities) a remap may leave."""


class HasMasses(Protocol):
    """What :func:`normalise` reads: the dof locations and the Galerkin masses.

    Attributes
    ----------
    x : ndarray
        The dof locations.
    """

    x: NDArray

    def masses(self, u: NDArray) -> NDArray:
        """:math:`\\int\\varphi_i e^u`."""


def normalise(integ: HasMasses, u: NDArray, temperature: float = 1.0) -> NDArray:
    """``u + a + b x^2`` with unit mass and the variance ``temperature`` (Newton on ``b``).

    Parameters
    ----------
    integ : HasMasses
        Holds the discretisation (masses): a
        :class:`~kinetic_fem.solvers.fem.transient.BDF2`, or one species' view.
    u : ndarray
        ln P at the dofs.
    temperature : float
        :math:`\\langle x^2\\rangle` to restore (units of the mesh).

    Returns
    -------
    ndarray
    """
    x2 = integ.x**2
    for _ in range(50):
        m = integ.masses(u)
        m0, m2, m4 = m.sum(), x2 @ m, (x2 * x2) @ m
        u = u - math.log(m0)
        if abs(m2 / m0 - temperature) < 1e-15 * temperature:
            break
        u = u - (m2 / m0 - temperature) / (m4 / m0 - (m2 / m0) ** 2) * x2
    return u - math.log(integ.masses(u).sum())


def remap_log_density(old: FEMDiscretisation, u: NDArray, x_new: NDArray,
                      ratio: float, resolved: float = math.inf) -> NDArray:
    """``ln(ratio) + u_h(ratio x)`` at the points ``x_new`` (``ratio x`` inside the mesh).

    Beyond the speed ``resolved`` (old units) :math:`u_h` is continued linearly with its
    slope over the last :data:`CONTINUE_WIDTH` thermal velocities before it.

    Parameters
    ----------
    old : FEMDiscretisation
        The mesh of ``u``.
    u : ndarray
        ln P at the dofs of ``old``.
    x_new : ndarray
        Points in the new unit.
    ratio : float
        New unit over the old one.
    resolved : float
        Where the linear continuation starts (old units; ``inf``: nowhere).

    Returns
    -------
    ndarray
    """
    verts, dofs = old.mesh_arrays
    at = np.abs(x_new) * ratio
    inner = np.minimum(at, resolved)
    order = np.argsort(inner, kind="stable")
    vals = evaluate_field(verts, dofs, old.order, np.ascontiguousarray(u),
                          np.ascontiguousarray(inner[order]))
    out = np.empty_like(x_new)
    out[order] = vals
    if math.isfinite(resolved):
        edge = np.array([resolved - CONTINUE_WIDTH, resolved])
        lo, hi = evaluate_field(verts, dofs, old.order, np.ascontiguousarray(u), edge)
        out += min(hi - lo, 0.0) / CONTINUE_WIDTH * (at - inner)
    return out + math.log(ratio)


def usable_extent(disc: FEMDiscretisation, u: NDArray) -> float:
    """Largest speed of the mesh where :math:`\\ln P_h` is above the tail level.

    and where it falls by less than :data:`MAX_ELEMENT_DROP` per element; the outermost
    :data:`EDGE_ELEMENTS` elements are never used (their values are the ones the edge
    trigger watches).

    Parameters
    ----------
    disc : FEMDiscretisation
        The mesh.
    u : ndarray
        ln P at its dofs.

    Returns
    -------
    float
    """
    xs, us = _half_line(disc, u)
    verts = disc.mesh_arrays[0]
    limit = float(verts[-1 - EDGE_ELEMENTS])
    low = np.flatnonzero(us < us.max() + math.log(TAIL_LEVEL))
    if low.size:
        limit = min(limit, float(xs[low[0]]))
    # resolution: ln P may fall by at most MAX_ELEMENT_DROP per element (its own size)
    sizes = np.diff(verts)
    local = sizes[np.clip(np.searchsorted(verts, 0.5 * (xs[1:] + xs[:-1])) - 1, 0,
                          sizes.size - 1)]
    steep = np.flatnonzero(-np.diff(us) > MAX_ELEMENT_DROP * np.diff(xs) / local)
    if steep.size:
        limit = min(limit, float(xs[steep[0]]))
    return limit


def segment_vertices(old: FEMDiscretisation, u: NDArray, ratio: float, *, cutoff: float,
                     h: float, t: float, spacing: float, scale: float = 1.0
                     ) -> tuple[NDArray, float]:
    """The mesh of the next segment (unit ``ratio`` times the old one) and where the old
    state stops being resolved.

    Inside the resolved part of the old mesh (:func:`usable_extent`) the Galerkin field
    itself; beyond, out to the old mesh's end or the tail level, its linear continuation
    in ln P: the mesh keeps its physical extent, which the cut of the unresolved edge
    would otherwise erode remap after remap (nearly elastic states, whose segments end by
    the edge before T has fallen much).

    Parameters
    ----------
    old : FEMDiscretisation
        The mesh of ``u``.
    u : ndarray
        ln P at the dofs of ``old``.
    ratio : float
        New velocity unit over the old one.
    cutoff : float
        Largest half-width of the new mesh (thermal velocities).
    h : float
        Nominal element size (thermal velocities).
    t : float
        Time of the remap (for the error).
    spacing : float
        The run's ``spacing`` (for the error).
    scale : float
        The thermal velocity in the new unit (1 for one species; a mixture's species
        differ).

    Returns
    -------
    vertices : ndarray
        Symmetric vertices (new unit).
    resolved : float
        Old units, for :func:`remap_log_density`.

    Raises
    ------
    ConvergenceError
        If the new mesh would end before :data:`MIN_EXTENT` thermal velocities.
    """
    resolved = usable_extent(old, u)
    end = float(old.mesh_arrays[0][-1])
    if resolved < end:
        probe = np.array([resolved - CONTINUE_WIDTH, resolved])
        lo, hi = remap_log_density(old, u, probe, 1.0)
        fall = (lo - hi) / CONTINUE_WIDTH
        if fall > 0.0:
            end = min(end, resolved + (hi - float(u.max()) - math.log(TAIL_LEVEL)) / fall)
    extent = min(cutoff * scale, max(end, resolved) / ratio)
    if extent < MIN_EXTENT * scale:
        raise ConvergenceError(
            f"the cooling state at t={t:.6g} is resolved only to {extent / scale:.3g} thermal "
            f"velocities: refine the mesh (spacing={spacing:g})")
    return remap_vertices(old, u, ratio, extent, h * scale, resolved), resolved


def steepest_drop(disc: FEMDiscretisation, u: NDArray) -> float:
    """Largest fall of :math:`\\ln P_h` over one element (dof differences times the
    order), on :math:`v \\ge 0`.

    Parameters
    ----------
    disc : FEMDiscretisation
        The mesh.
    u : ndarray
        ln P at its dofs.

    Returns
    -------
    float
    """
    return float(-np.diff(_half_line(disc, u)[1]).min()) * disc.order


def _half_line(disc: FEMDiscretisation, u: NDArray) -> tuple[NDArray, NDArray]:
    """The dofs at :math:`v \\ge 0` and ``u`` there, in increasing :math:`v`."""
    x = disc.dof_locations
    keep = np.flatnonzero(x >= 0)
    order = keep[np.argsort(x[keep], kind="stable")]
    return x[order], u[order]


def remap_vertices(old: FEMDiscretisation, u: NDArray, ratio: float, extent: float,
                    h: float, resolved: float = math.inf) -> NDArray:
    """Symmetric vertices on ``[-extent, extent]`` for the state ``u`` in the unit
    ``ratio`` times the old one: elements of size ``h``, smaller where :math:`\\ln P` falls
    by more than :data:`GRADE_DROP` over one (down to :data:`GRADE_MIN` ``h``).

    Parameters
    ----------
    old : FEMDiscretisation
        The mesh of ``u``.
    u : ndarray
        ln P at the dofs of ``old``.
    ratio : float
        New velocity unit over the old one.
    extent : float
        Half-width of the new mesh (new units, inside the old mesh).
    h : float
        Nominal element size (new units).
    resolved : float
        As :func:`remap_log_density`.

    Returns
    -------
    ndarray
    """
    probe = np.linspace(0.0, extent, 4001)
    fall = np.maximum(-np.diff(remap_log_density(old, u, probe, ratio, resolved)),
                      0.0) / np.diff(probe)
    edges, x = [0.0], 0.0
    while x < extent:
        lo, hi = np.searchsorted(probe, [x, x + h])
        slope = float(fall[min(lo, fall.size - 1):max(hi, lo + 1)].max())
        x += h if slope * h <= GRADE_DROP else max(GRADE_DROP / slope, GRADE_MIN * h)
        edges.append(x)
    pos = np.array(edges)
    if pos.size > 2 and pos[-1] - extent > 0.5 * (pos[-1] - pos[-2]):
        pos = pos[:-1]   # a short last element: merge it
    pos *= extent / pos[-1]
    return np.concatenate([-pos[:0:-1], pos])


def padded_outputs(outputs: list[tuple[NDArray, NDArray, NDArray]]
                   ) -> tuple[NDArray, NDArray, NDArray]:
    """Stack outputs of different meshes: shorter ones get zero-weight points outside.

    Parameters
    ----------
    outputs : list of (grid, values, weights)
        One triple of 1-d arrays per output time.

    Returns
    -------
    grid, values, weights : ndarray, shape (n_t, width)
    """
    width = max(g.size for g, _, _ in outputs)
    grid, values, weights = (np.zeros((len(outputs), width)) for _ in range(3))
    for i, (g, p, w) in enumerate(outputs):
        pad = (width - g.size) // 2
        step = g[-1] - g[-2]
        ext = g[-1] + step * np.arange(1, pad + 1)
        grid[i] = np.concatenate([-ext[::-1], g, ext])
        values[i, pad:pad + g.size] = p
        weights[i, pad:pad + g.size] = w
    return grid, values, weights
