"""FEM transient of the freely cooling gas on segments of fixed velocity scale.

Free cooling :math:`\\partial_t P = n\\,Q_\\alpha[P]` has no transport term in physical
velocities: the Galerkin system is the collision term alone, and the adaptive BDF2
integrator of :mod:`kinetic_fem.solvers.fem_transient` advances it like a heated gas
with :math:`D = \\xi = 0` (mass conserved to round-off, :math:`P = e^{u} > 0`, local
error control on :math:`T` relative and :math:`a_2` absolute).  As :math:`T` falls by
many decades the distribution is kept resolved by working in segments: within a
segment velocities are measured in a fixed unit :math:`V` (the thermal speed at the
segment's start), :math:`P(v) = p(v/V)/V`, and for a kernel homogeneous of degree
:math:`d`

.. math::

    \\partial_t p(w) = n V^{d}\\, Q_\\alpha[p](w), \\qquad w = v/V,

on a mesh of fixed element size in :math:`w`.  When the temperature in these units has
fallen below ``1/rescale`` (or the far tail has become too steep, :data:`EDGE_DROP`),
the state is remapped to the new unit :math:`V' = \\sqrt{T}` on a new mesh that ends
inside the resolved part of the old one (:data:`TAIL_LEVEL`, :data:`MAX_ELEMENT_DROP`):
:math:`\\ln p'(w) = \\ln(V'/V) + u_h(wV'/V)` (evaluation of the Galerkin field inside
its own mesh: no extrapolation), followed by the correction :math:`u \\to u + a + b w^2`
that restores unit mass and the temperature exactly, so that :math:`T(t)` is continuous
across a remap to round-off; the integrator restarts (backward Euler) from there.  Far-tail
dofs that decay too fast for BDF2 take backward Euler steps (:class:`CoolingIntegrator`).

Why not the scaled variables :math:`c = v/\\sqrt{T}` with :math:`\\zeta` as an algebraic
unknown (``Integrator(cooling=True)``)?  Measured on it: the failures come from the
unresolved far tail (history masses :math:`\\le 0` on 182 of 285 dofs at the first step
for alpha 0.5 with its default cut-off 35; Newton divergent from the first step at alpha
0.8 with its default spacing 0.097), where the drift :math:`\\zeta\\partial_c(cf)` only
adds an outflow boundary; in physical variables the tail needs no drift and the remaps
keep the mesh inside its resolved part (docs: user guide, "Free cooling in time").

:math:`\\zeta(t)` is reported in the convention :math:`dT/dt = -2\\zeta n T^{1+d/2}`,
from the Galerkin energy balance of the collision term at each output time.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
from numpy.typing import NDArray

from ..distribution import RunInfo, VelocityDistribution
from ..evolution import Evolution
from ..exceptions import ConvergenceError
from ..model import CoolingProblem, UnsupportedModelError
from ..operators.fem_discretisation import FEMDiscretisation
from ..operators.fem_kernels import evaluate_field
from .fem_evolution import initial_log_density
from .fem_transient import (
    Integrator,
    Level,
    TransientOptions,
    build_mesh,
    floor_log,
    make_discretisation,
)

__all__ = ["evolve_cooling_fem", "default_cooling_cutoff", "DEFAULT_RESCALE"]

logger = logging.getLogger(__name__)

DEFAULT_RESCALE = 4.0
"""Temperature ratio over one segment (the thermal speed halves)."""

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

HISTORY_FLOOR = 0.3
"""A BDF2 history term below this fraction of ``c_new m^k`` is replaced by backward
Euler's (:class:`CoolingIntegrator`)."""

MAX_ELEMENT_DROP = 2.0
"""A new mesh ends before :math:`\\ln P_h` falls by more than this over an element:
steeper, the vertex masses of P2 elements lose positivity and the tail oscillates
(measured: a Gaussian start at 0.25 per element beyond 11 thermal velocities)."""

EDGE_ELEMENTS = 2
"""Outermost elements dropped at a remap."""

MIN_EXTENT = 4.0
"""Smallest mesh half-width (thermal velocities) a remap may leave."""


def default_cooling_cutoff(gamma: float) -> float:
    """Largest mesh half-width in thermal velocities: :math:`\\max(14, 30 - 12\\gamma)`.

    A little wider than the heated transient's
    (:func:`kinetic_fem.solvers.fem_evolution.default_transient_cutoff`): the cooling
    tails decay more slowly.  Meshes usually end earlier, where :math:`P` has fallen to
    :data:`TAIL_LEVEL` of its peak or :math:`\\ln P` falls by more than
    :data:`MAX_ELEMENT_DROP` per element.

    Parameters
    ----------
    gamma : float
        Degree of homogeneity of the kernel.

    Returns
    -------
    float
    """
    return max(14.0, 30.0 - 12.0 * gamma)


class CoolingIntegrator(Integrator):
    """:class:`~kinetic_fem.solvers.fem_transient.Integrator` whose BDF2 history term
    stays positive.

    A far-tail dof decaying by more than a factor ~4 per step (the loss rate grows with
    the speed, :math:`\\nu(v) \\approx n|v|` for hard rods) gets a negative BDF2 history
    term, ``c_old = (1+w) m^k - w^2/(1+w) m^{k-1} < 0``, and the step has no positive
    solution: measured, every Newton failure of a hard-rod run (alpha 0.3, 123 of 123)
    had one (with the floor 0.3: 1 Newton failure in 322 steps; 0.1: 45; 1e-3 and 0:
    the run stops at t = 2.66).  Such dofs (``c_old < HISTORY_FLOOR c_new m^k``) take a
    backward Euler step of length ``h/c_new`` instead (``c_old = c_new m^k``, positivity
    preserving).
    The rest of the history term is scaled by ``1 - delta`` to keep its sum, so the mass
    stays conserved; :attr:`mass_defect` sums the mass moved (those dofs hold the far
    tail: measured 1e-11 over a whole run, i.e. ``delta`` ~ 1e-14 per step).

    Parameters
    ----------
    *args, **kwargs
        As :class:`~kinetic_fem.solvers.fem_transient.Integrator`.
    """

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.limited = 0
        self.mass_defect = 0.0

    def history_target(self, c_old: NDArray, m_last: NDArray, c_new: float) -> NDArray:
        """``c_old`` with the dofs below ``HISTORY_FLOOR c_new m_last`` set to
        ``c_new m_last``.

        Parameters
        ----------
        c_old : ndarray
            BDF2 history term.
        m_last : ndarray
            Masses of the last level.
        c_new : float
            Coefficient of the new masses.

        Returns
        -------
        ndarray
        """
        low = c_old < HISTORY_FLOOR * c_new * m_last
        if not low.any():
            return c_old
        out = np.where(low, c_new * m_last, c_old)
        # the rest of the history term absorbs the change: the mass stays conserved
        rest = ~low
        out[rest] *= 1.0 - float(np.sum(out[low] - c_old[low])) / float(np.sum(c_old[rest]))
        self.limited += int(low.sum())
        self.mass_defect += float(np.sum(out[low] - c_old[low])) / c_new
        return out


def _normalise(integ: Integrator, u: NDArray) -> NDArray:
    """``u + a + b x^2`` with unit mass and unit temperature (Newton on ``b``)."""
    x2 = integ.x**2
    for _ in range(50):
        m = integ.masses(u)
        m0, m2, m4 = m.sum(), x2 @ m, (x2 * x2) @ m
        u = u - math.log(m0)
        if abs(m2 / m0 - 1.0) < 1e-15:
            break
        u = u - (m2 / m0 - 1.0) / (m4 / m0 - (m2 / m0) ** 2) * x2
    return u - math.log(integ.masses(u).sum())


def _remap(old: FEMDiscretisation, u: NDArray, x_new: NDArray, ratio: float) -> NDArray:
    """``ln(ratio) + u_h(ratio x)`` at the points ``x_new`` (``ratio x`` inside the mesh)."""
    verts, dofs = old.mesh_arrays
    order = np.argsort(x_new, kind="stable")
    vals = evaluate_field(verts, dofs, old.order, np.ascontiguousarray(u),
                          np.ascontiguousarray(x_new[order] * ratio))
    out = np.empty_like(x_new)
    out[order] = vals
    return out + math.log(ratio)


def _usable_extent(disc: FEMDiscretisation, u: NDArray) -> float:
    """Largest speed of the mesh where :math:`\\ln P_h` is above the tail level.

    and where it falls by less than :data:`MAX_ELEMENT_DROP` per element; the outermost
    :data:`EDGE_ELEMENTS` elements are never used (their values are the ones the edge
    trigger watches).
    """
    x = disc.dof_locations
    keep = x >= 0
    xs, us = x[keep], u[keep]
    order = np.argsort(xs, kind="stable")
    xs, us = xs[order], us[order]
    verts = disc.mesh_arrays[0]
    h_el = float(verts[-1] - verts[-2])
    limit = xs[-1] - EDGE_ELEMENTS * h_el
    low = np.flatnonzero(us < us.max() + math.log(TAIL_LEVEL))
    if low.size:
        limit = min(limit, float(xs[low[0]]))
    # resolution: ln P may fall by at most MAX_ELEMENT_DROP per element
    steep = np.flatnonzero(-np.diff(us) > MAX_ELEMENT_DROP * np.diff(xs) / h_el)
    if steep.size:
        limit = min(limit, float(xs[steep[0]]))
    return limit


def _steepest_drop(disc: FEMDiscretisation, u: NDArray) -> float:
    """Largest fall of :math:`\\ln P_h` over one element (dof differences times the
    order), on :math:`v \\ge 0`."""
    x = disc.dof_locations
    keep = np.flatnonzero(x >= 0)
    order = keep[np.argsort(x[keep], kind="stable")]
    return float(-np.diff(u[order]).min()) * disc.order


def evolve_cooling_fem(problem: CoolingProblem, *, times: NDArray,
                       initial: VelocityDistribution | None,
                       initial_temperature: float | None, rtol: float = 1e-6, order: int = 2,
                       spacing: float = 0.25, cutoff: float | None = None,
                       rescale: float = DEFAULT_RESCALE, first_step: float | None = None,
                       max_step: float = math.inf, max_steps: int = 20000,
                       newton_tol: float = 1e-11, max_newton: int = 12) -> Evolution:
    """Free cooling by adaptive BDF2 on segments of fixed velocity scale (see the module).

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, a homogeneous kernel.
    times : ndarray, shape (n_t,)
        Output times (physical), checked by :func:`kinetic_fem.evolve.check_times`.
    initial : VelocityDistribution or None
        Initial state (normalised), or None for a Gaussian.
    initial_temperature : float or None
        Temperature of the Gaussian start (default 1).
    rtol : float
        Local error tolerance per step (relative on T, absolute on a2).
    order : int
        Lagrange degree, 1 or 2.
    spacing : float
        Element size in thermal velocities at the end of a segment (the coarsest).
    cutoff : float, optional
        Largest half-width of a mesh in thermal velocities at a segment's start (default
        :func:`default_cooling_cutoff`; meshes end earlier where the tail is negligible
        or unresolved, see the module).
    rescale : float
        Temperature ratio after which the state is remapped to the current thermal
        speed (> 1).
    first_step, max_step, max_steps, newton_tol, max_newton
        Step-size and Newton options
        (:class:`kinetic_fem.solvers.fem_transient.TransientOptions`); ``first_step``
        and ``max_step`` in physical time.

    Returns
    -------
    Evolution
        ``series["zeta"]`` (:math:`dT/dt = -2\\zeta n T^{1+d/2}`), ``series["mass"]``,
        ``series["segments"]`` (remaps before each output).

    Raises
    ------
    UnsupportedModelError
        For a speed-dependent restitution law.
    ValueError
        For invalid numerical options.
    """
    start = time.perf_counter()
    gas = problem.gas
    if gas.restitution.constant is None:
        raise UnsupportedModelError(
            "evolve_cooling (method 'fem') needs a constant restitution coefficient: with a "
            f"speed-dependent law {gas.restitution!r} the gas has no scaling state; use "
            "evolve_heated with a protocol instead")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    if not (math.isfinite(rescale) and rescale > 1.0):
        raise ValueError(f"rescale must be a finite number > 1, got {rescale!r}")
    for name, val in (("spacing", spacing), ("rtol", rtol)):
        if not (math.isfinite(val) and val > 0.0):
            raise ValueError(f"{name} must be a finite positive number, got {val!r}")
    hom = gas.kernel.homogeneity_degree
    assert hom is not None  # CoolingProblem refuses kernels that are not homogeneous
    degree = float(hom)
    c_cut = default_cooling_cutoff(degree) if cutoff is None else float(cutoff)
    if not (math.isfinite(c_cut) and c_cut > MIN_EXTENT):
        raise ValueError(f"cutoff must be a finite number > {MIN_EXTENT}, got {cutoff!r}")
    h_el = spacing / math.sqrt(rescale)

    def discretise(extent: float) -> FEMDiscretisation:
        return make_discretisation(gas.restitution, gas.kernel, build_mesh(extent, h_el),
                                   order)

    unit = [1.0]  # velocity unit V of the current segment

    def coefficients(t: float, left: bool = True) -> tuple[float, float, float]:
        return gas.density * unit[0] ** degree, 0.0, 0.0

    rate0 = gas.density * float(gas.kernel.rate(1.0))
    opt = TransientOptions(rtol, 1e-9 / rate0, order, spacing, cutoff, first_step, max_step,
                           max_steps, newton_tol, max_newton)
    # error per collision time (as evolve_heated): the mean free time at the segment's
    # temperature ``temp`` (in units V^2), 1 / (n V^gamma rate(sqrt(temp)))
    integ = CoolingIntegrator(
        discretise(c_cut), coefficients, cooling=False, options=opt,
        collision_time=lambda temp: 1.0 / (coefficients(0.0)[0]
                                           * float(gas.kernel.rate(math.sqrt(temp)))))
    x = integ.x
    if initial is not None:
        t0 = initial.temperature
        unit[0] = math.sqrt(t0)
        u = initial_log_density(initial, x, scale=unit[0])
    else:
        t0 = 1.0 if initial_temperature is None else float(initial_temperature)
        unit[0] = math.sqrt(t0)
        u = floor_log(x, -0.5 * x**2 - 0.5 * math.log(2.0 * math.pi))
    zero = np.zeros(2)

    def level(t: float, u: NDArray) -> Level:
        return Level(t, u, integ.masses(u), 0.0, zero, integ.observables(u, zero))

    def remap(u: NDArray, ratio: float) -> NDArray:
        """The state in the unit ``ratio V`` on a new mesh inside the usable extent."""
        old = integ.disc
        extent = min(c_cut, _usable_extent(old, u) / ratio)
        if extent < MIN_EXTENT:
            raise ConvergenceError(
                f"the cooling state at t={hist[-1].s if hist else 0.0:.6g} is resolved only "
                f"to {extent:.3g} thermal velocities: refine the mesh (spacing={spacing:g})")
        integ.set_disc(discretise(extent))
        return _normalise(integ, _remap(old, u, integ.x, ratio))

    hist: list[Level] = []
    u = remap(u, 1.0)
    hist.append(level(0.0, u))
    h = first_step if first_step is not None else (
        0.1 * math.sqrt(rtol) / (gas.density * unit[0] ** degree * rate0))
    outputs: list[tuple[NDArray, NDArray, NDArray]] = []
    masses: list[float] = []
    zetas: list[float] = []
    segs: list[int] = []
    n_seg = n_edge = 0
    for stop in times.tolist():
        reached = stop <= 0.0
        while not reached:
            h, reached = integ.advance(hist, h, stop)
            temp_w = float(integ.x**2 @ hist[-1].m)
            edge = _steepest_drop(integ.disc, hist[-1].u) > EDGE_DROP
            if temp_w < 1.0 / rescale or edge:
                ratio = math.sqrt(temp_w)
                u_new = remap(hist[-1].u, ratio)
                unit[0] *= ratio
                hist[:] = [level(hist[-1].s, u_new)]
                integ.stats.restarts += 1
                n_seg += 1
                n_edge += int(edge)
                h = h * ratio ** (-degree)  # the collision time grew by ratio^-d
                logger.debug("remap at t=%.6g (edge %s): unit %.6g, extent %.4g, step %.3g",
                             hist[-1].s, edge, unit[0], float(integ.x.max()), h)
        u_out = hist[-1].u
        v = unit[0]
        outputs.append((integ.xq * v, integ.disc.values(u_out) / v, integ.wq * v))
        segs.append(n_seg)
        x2 = integ.x**2
        m = integ.masses(u_out)
        masses.append(float(m.sum()))
        temp_w = float(x2 @ m) / masses[-1]
        coll = integ.disc.collision(u_out, energy_power=None)[0]
        zetas.append(-float(x2 @ coll) / (2.0 * temp_w ** (1.0 + 0.5 * degree)))
    params = {**problem.as_dict(), "problem": "cooling transient"}
    st = integ.stats
    message = (f"adaptive BDF2 on {n_seg + 1} segments (rescale {rescale:g}, {n_edge} ended "
               f"by a steep tail), rtol={rtol:g}: "
               f"{st.accepted} steps ({st.rejected} rejected, {st.newton_failures} Newton "
               f"failures, {st.forced} forced), {st.newton_iterations} Newton iterations, "
               f"{integ.limited} dof-steps backward Euler (history mass "
               f"{integ.mass_defect:.1e})")
    logger.info(message)
    info = RunInfo(converged=True, iterations=st.accepted, residual=float("nan"),
                   wall_time=time.perf_counter() - start, message=message,
                   extra={**st.as_dict(), "rtol": rtol, "order": order, "segments": n_seg + 1,
                          "edge_remaps": n_edge, "history_limited": integ.limited,
                          "history_mass_defect": integ.mass_defect})
    grid, values, weights = _padded(outputs)
    return Evolution(times, grid, values, weights, method="fem", params=params, info=info,
                     series={"zeta": np.array(zetas), "mass": np.array(masses),
                             "segments": np.array(segs, dtype=float)})


def _padded(outputs: list[tuple[NDArray, NDArray, NDArray]]
            ) -> tuple[NDArray, NDArray, NDArray]:
    """Stack outputs of different meshes: shorter ones get zero-weight points outside."""
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
