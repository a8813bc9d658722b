"""FEM transient of the freely cooling gas on segments of fixed velocity scale.

Free cooling :math:`\\partial_t P = n\\,Q_\\alpha[P]` has no transport term in physical
velocities: the Galerkin system is the collision term alone, and the adaptive BDF2
integrator of :mod:`kinetic_fem.solvers.fem.transient` advances it like a heated gas
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
dofs that decay too fast for BDF2 take backward Euler steps
(:meth:`~kinetic_fem.solvers.fem.transient.BDF2.history_target`).  The remap is the
integrator's ``remap`` hook, checked after each accepted step.

**Any law, any kernel, restitution changes.**  In the unit :math:`V` the collision
term is that of the law :math:`g \\mapsto \\alpha(Vg)` (``law.rescaled(V)``,
:meth:`kinetic_fem.model.RestitutionLaw.rescaled`: a threshold :math:`g_*/V`, the
viscoelastic :math:`\\delta V^{1/5}`) and the kernel :math:`B(Vg) = V^d K_V(g)`
(:meth:`kinetic_fem.model.CollisionKernel.rescaled` with :math:`d` its
``scale_degree``: a power law is its own :math:`K_V`, the saturating kernel has
:math:`g_0/V`), so the discretisation is rebuilt at each remap; no scaling state is
needed, and kernels that are not homogeneous are allowed.  A restitution change of a
:class:`~kinetic_fem.model.protocol.Protocol` is a stop of the integrator exactly at its
time, a new discretisation on the same mesh and a restart (backward Euler, small step).

Why not the scaled variables :math:`c = v/\\sqrt{T}` with :math:`\\zeta` as an algebraic
unknown (an earlier ``Integrator(cooling=True)``, removed)?  Measured on it: the failures
come from the
unresolved far tail (history masses :math:`\\le 0` on 182 of 285 dofs at the first step
for alpha 0.5 with its default cut-off 35; Newton divergent from the first step at alpha
0.8 with its default spacing 0.097), where the drift :math:`\\zeta\\partial_c(cf)` only
adds an outflow boundary; in physical variables the tail needs no drift and the remaps
keep the mesh inside its resolved part (docs: user guide, "Free cooling in time").

:math:`\\zeta(t)` is reported in the convention :math:`dT/dt = -2\\zeta n T^{1+d/2}`
(:math:`d` the kernel's ``scale_degree``: :math:`\\gamma` for a power law), and
``cooling_rate`` :math:`= -d\\ln T/dt`, both from the Galerkin energy balance of the
collision term at each output time with the law in force at that time (at a change time
the new law: right-continuous, as :meth:`Protocol.restitution_at`).  For a constant
coefficient and a power law :math:`\\zeta` tends to the homogeneous cooling state's; for
a speed-dependent law it is the instantaneous rate of the current state (no constant).
"""

from __future__ import annotations

import logging
import math
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...distribution import RunInfo, VelocityDistribution
from ...evolution import Evolution
from ...model import CollisionKernel, InelasticGas, RestitutionLaw
from ...model.protocol import Protocol
from ...operators.fem_discretisation import FEMDiscretisation
from ...options import gather
from ...solve import register_solver
from .cooling_segments import (
    EDGE_DROP,
    MIN_EXTENT,
    normalise,
    padded_outputs,
    remap_log_density,
    segment_vertices,
    steepest_drop,
)
from .options import CoolingEvolveOptions
from .transient import (
    BDF2,
    TimeIntegrator,
    TransientOptions,
    build_mesh,
    floor_log,
    make_discretisation,
)
from .transient_setup import default_newton_tol, distribution_log_density, progress_bar

__all__ = ["evolve_cooling_fem", "default_cooling_cutoff", "check_free_cooling",
           "cooling_settings", "DEFAULT_RESCALE"]

logger = logging.getLogger(__name__)

DEFAULT_RESCALE = CoolingEvolveOptions.rescale
"""Temperature ratio over one segment (the thermal speed halves)."""


def default_cooling_cutoff(gamma: float) -> float:
    """Largest mesh half-width in thermal velocities: :math:`\\max(14, 30 - 12\\gamma)`.

    A little wider than the heated transient's
    (:func:`kinetic_fem.solvers.fem.evolution.default_transient_cutoff`): the cooling
    tails decay more slowly.  Meshes usually end earlier, where :math:`P` has fallen to
    :data:`~kinetic_fem.solvers.fem.cooling_segments.TAIL_LEVEL` of its peak or
    :math:`\\ln P` falls by more than
    :data:`~kinetic_fem.solvers.fem.cooling_segments.MAX_ELEMENT_DROP` per element.

    Parameters
    ----------
    gamma : float
        Growth exponent of the kernel (:math:`\\gamma` of a power law).

    Returns
    -------
    float
    """
    return max(14.0, 30.0 - 12.0 * gamma)


def check_free_cooling(gas: InelasticGas, protocol: Protocol) -> None:
    """Raise unless ``protocol`` describes free cooling of ``gas``.

    Free cooling has no thermostat: a protocol that sets :math:`D` or a non-zero
    :math:`\\xi` belongs to :func:`kinetic_fem.evolve_heated`.  Every kernel and every
    restitution law is allowed (the transient works in physical velocities and needs no
    scaling state), but at least one law in force must dissipate.

    Parameters
    ----------
    gas : InelasticGas
        The gas at ``t = 0``.
    protocol : Protocol
        Restitution changes.

    Raises
    ------
    TypeError
        If ``protocol`` is not a :class:`~kinetic_fem.model.protocol.Protocol`.
    ValueError
        For a protocol with a thermostat, or if every law is elastic.
    """
    if not isinstance(protocol, Protocol):
        raise TypeError(f"protocol must be a Protocol, got {type(protocol).__name__}")
    friction = protocol.friction
    if protocol.diffusion is not None or not (friction is None or (
            isinstance(friction, (int, float)) and friction == 0.0)):
        raise ValueError(
            "free cooling has no thermostat, but the protocol sets the noise strength "
            f"(diffusion={protocol.diffusion!r}) or the friction (friction={friction!r}); "
            "use kf.evolve_heated for a driven gas, or a Protocol(restitution=...) here")
    if all(law.is_elastic for law in protocol.restitution_laws(gas.restitution)):
        raise ValueError("elastic collisions (alpha = 1) do not change the distribution of "
                         "a one-dimensional gas: nothing cools; take alpha < 1")


def cooling_settings(o: CoolingEvolveOptions, kernel: CollisionKernel) -> tuple[float, float]:
    """The checked element size and cut-off of a free-cooling FEM transient.

    Parameters
    ----------
    o : CoolingEvolveOptions
        The numerical options.
    kernel : CollisionKernel
        Its growth sets the default cut-off (:func:`default_cooling_cutoff`).

    Returns
    -------
    spacing, cutoff : float

    Raises
    ------
    ValueError
        Naming the option: ``order`` not 1 or 2, ``rescale`` not > 1, ``spacing`` or
        ``rtol`` not positive, ``cutoff`` not above
        :data:`~kinetic_fem.solvers.fem.cooling_segments.MIN_EXTENT`.
    """
    if o.order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {o.order!r}")
    if not (math.isfinite(o.rescale) and o.rescale > 1.0):
        raise ValueError(f"rescale must be a finite number > 1, got {o.rescale!r}")
    for name, val in (("spacing", o.spacing), ("rtol", o.rtol)):
        if val is None or not (math.isfinite(val) and val > 0.0):
            raise ValueError(f"{name} must be a finite positive number, got {val!r}")
    c_cut = default_cooling_cutoff(kernel.tail_growth[1]) if o.cutoff is None \
        else float(o.cutoff)
    if not (math.isfinite(c_cut) and c_cut > MIN_EXTENT):
        raise ValueError(f"cutoff must be a finite number > {MIN_EXTENT}, got {o.cutoff!r}")
    return float(o.spacing or 0.0), c_cut


@register_solver("fem", problem="transient-cooling")
def evolve_cooling_fem(gas: InelasticGas, *, times: NDArray,
                       initial: VelocityDistribution | None = None,
                       initial_temperature: float | None = None, protocol: Protocol | None = None,
                       options: CoolingEvolveOptions | None = None, progress: bool = False,
                       **option_keywords: Any) -> Evolution:
    """Free cooling by adaptive BDF2 on segments of fixed velocity scale (see the module).

    Parameters
    ----------
    gas : InelasticGas
        Kernel, density and the restitution law at ``t = 0`` (any law, any kernel).
    times : ndarray, shape (n_t,)
        Output times (physical), checked by :func:`kinetic_fem.evolve.check_times`.
    initial : VelocityDistribution or None
        Initial state (normalised), or None for a Gaussian.
    initial_temperature : float or None
        Temperature of the Gaussian start (default 1).
    protocol : Protocol or None
        Restitution changes at given times (no thermostat: :func:`check_free_cooling`;
        None: none).
    options : CoolingEvolveOptions, optional
        The numerical options as one object
        (:class:`~kinetic_fem.solvers.fem.options.CoolingEvolveOptions`): ``rtol``
        (default 1e-6, local error per step, relative on T and absolute on a2),
        ``order`` (1 or 2), ``spacing`` (default 0.25, element size in thermal
        velocities at the end of a segment), ``cutoff`` (largest half-width of a mesh at
        a segment's start, default :func:`default_cooling_cutoff`; meshes end earlier
        where the tail is negligible or unresolved, see the module), ``rescale``
        (temperature ratio of a segment, > 1), and the step and Newton options
        ``first_step`` and ``max_step`` (physical time), ``max_steps``, ``newton_tol``
        (default :func:`~kinetic_fem.solvers.fem.transient_setup.default_newton_tol`),
        ``max_newton``, and ``scheme`` (``"bdf2"`` by default; ``"bdf3"``
        restarts after each remap like BDF2).
    progress : bool
        Show a progress bar over time (tqdm).
    **option_keywords
        Fields of ``options`` by keyword (over ``options``; an unknown keyword raises
        :class:`TypeError`).

    Returns
    -------
    Evolution
        ``series["zeta"]`` (:math:`dT/dt = -2\\zeta n T^{1+d/2}`),
        ``series["cooling_rate"]`` (:math:`-d\\ln T/dt`), ``series["mass"]``,
        ``series["segments"]`` (remaps before each output).

    Raises
    ------
    ValueError
        For invalid numerical options, a protocol with a thermostat, or relative
        speeds on the mesh beyond the range of a restitution law
        (:attr:`~kinetic_fem.model.RestitutionLaw.max_speed`: start colder or lower
        ``cutoff``).
    ConvergenceError
        If the state can no longer be resolved (a mesh below
        :data:`~kinetic_fem.solvers.fem.cooling_segments.MIN_EXTENT` thermal velocities).
    """
    start = time.perf_counter()
    o = gather(CoolingEvolveOptions, options, option_keywords, "evolve_cooling")
    rtol, order, cutoff, rescale, first_step = o.rtol, o.order, o.cutoff, o.rescale, o.first_step
    scheme = o.scheme
    protocol = Protocol() if protocol is None else protocol
    check_free_cooling(gas, protocol)
    kernel = gas.kernel
    degree = float(kernel.scale_degree)
    spacing, c_cut = cooling_settings(o, kernel)
    h_el = spacing / math.sqrt(rescale)
    t_end = float(times[-1])
    # restitution changes (also one at the last output time: right-continuous outputs)
    breaks = tuple(sorted(set(protocol.breakpoints(t_end))
                          | {t for t, _ in protocol.restitution if 0.0 < t <= t_end}))
    law_now: list[RestitutionLaw] = [protocol.restitution_at(0.0, gas.restitution)]
    unit = [1.0]  # velocity unit V of the current segment

    def discretise(verts: NDArray, t: float) -> FEMDiscretisation:
        """The collision term in the unit V: the law alpha(V g), the kernel B(V g)/V^d."""
        law = law_now[0]
        law.check_speed(2.0 * float(verts[-1]) * unit[0],
                        f"the FEM mesh at t={t:.6g} (relative speeds up to twice its extent, "
                        f"{verts[-1]:.3g} thermal velocities: start colder or lower cutoff)")
        return make_discretisation(law.rescaled(unit[0]), kernel.rescaled(unit[0]), verts,
                                   order)

    def rate_in_units(w: float) -> float:
        """n V^d K_V(w): the collision rate at the speed w (units V) per unit density."""
        return gas.density * unit[0] ** degree * float(kernel.rescaled(unit[0]).rate(w))

    def coefficients(t: float, left: bool = True) -> tuple[float, float, float]:
        return gas.density * unit[0] ** degree, 0.0, 0.0

    if initial is not None:
        t0 = initial.temperature
    else:
        t0 = 1.0 if initial_temperature is None else float(initial_temperature)
    unit[0] = math.sqrt(t0)
    tol = default_newton_tol(rtol, scheme) if o.newton_tol is None else o.newton_tol
    opt = TransientOptions(rtol, 1e-9 / rate_in_units(1.0), order, spacing, cutoff,
                           first_step, o.max_step, o.max_steps, tol, o.max_newton,
                           moment_norm=o.newton_norm == "moments", scheme=scheme)
    # error per collision time (as evolve_heated): the mean free time at the segment's
    # temperature ``temp`` (in units V^2)
    integ = BDF2(discretise(build_mesh(c_cut, h_el), 0.0), coefficients, options=opt,
                 collision_time=lambda temp: 1.0 / rate_in_units(math.sqrt(temp)),
                 positive_history=True)
    x = integ.x
    if initial is not None:
        u = distribution_log_density(initial, x, scale=unit[0])
    else:
        u = floor_log(x, -0.5 * x**2 - 0.5 * math.log(2.0 * math.pi))
    def remap(u: NDArray, ratio: float, t: float) -> NDArray:
        """The state in the unit ``ratio V`` on a new mesh (:func:`segment_vertices`)."""
        old = integ.disc
        verts, resolved = segment_vertices(old, u, ratio, cutoff=c_cut, h=h_el, t=t,
                                           spacing=spacing)
        unit[0] *= ratio
        integ.set_disc(discretise(verts, t))
        return normalise(integ, remap_log_density(old, u, integ.x, ratio, resolved))

    def first_h() -> float:
        return first_step if first_step is not None else 0.1 * math.sqrt(rtol) / rate_in_units(1.0)

    integ.start(integ.level(0.0, remap(u, 1.0, 0.0)), first_h())
    outputs: list[tuple[NDArray, NDArray, NDArray]] = []
    masses: list[float] = []
    zetas: list[float] = []
    rates: list[float] = []
    segs: list[int] = []
    count = {"segments": 0, "edge": 0}

    def remap_hook(integ: TimeIntegrator) -> None:
        """A new segment once T (units V^2) fell below 1/rescale or the tail is steep."""
        assert isinstance(integ, BDF2)
        last = integ.hist[-1]
        temp_w = float(integ.x**2 @ last.m)
        edge = steepest_drop(integ.disc, last.u) > EDGE_DROP
        if temp_w < 1.0 / rescale or edge:
            ratio = math.sqrt(temp_w)
            h_next = integ.h * ratio ** (-degree)  # the collision time grew by ratio^-d
            integ.restart(integ.level(last.s, remap(last.u, ratio, last.s)), h_next)
            count["segments"] += 1
            count["edge"] += int(edge)
            logger.debug("remap at t=%.6g (edge %s): unit %.6g, extent %.4g, step %.3g",
                         last.s, edge, unit[0], float(integ.x.max()), h_next)

    integ.remap = remap_hook
    output_set = set(times.tolist())
    bar, update = progress_bar(progress, t_end, "evolve_cooling")
    with bar:
        for stop in sorted(output_set | set(breaks)):
            if stop > 0.0:
                integ.advance_to(stop, update)
            if stop in breaks:
                # a restitution change: same mesh, new law, restart with backward Euler
                law_now[0] = protocol.restitution_at(stop, gas.restitution)
                verts = integ.disc.mesh_arrays[0]
                integ.set_disc(discretise(verts, stop))
                integ.restart(integ.level(stop, integ.hist[-1].u), first_h())
                logger.debug("restitution change at t=%.6g: %r", stop, law_now[0])
            if stop not in output_set:
                continue
            u_out = integ.hist[-1].u
            v = unit[0]
            outputs.append((integ.xq * v, integ.disc.values(u_out) / v, integ.wq * v))
            segs.append(count["segments"])
            x2 = integ.x**2
            m = integ.masses(u_out)
            masses.append(float(m.sum()))
            temp_w = float(x2 @ m) / masses[-1]
            loss = -float(x2 @ integ.disc.collision(u_out, energy_power=None)[0]) / masses[-1]
            zetas.append(loss / (2.0 * temp_w ** (1.0 + 0.5 * degree)))
            rates.append(coefficients(stop)[0] * loss / temp_w)
    n_seg, n_edge = count["segments"], count["edge"]
    params = {"problem": "cooling transient", **gas.as_dict(), "protocol": repr(protocol)}
    st = integ.stats
    message = (f"adaptive {scheme.upper()} on {n_seg + 1} segments (rescale {rescale:g}, "
               f"{n_edge} ended by a steep tail, {len(breaks)} restitution changes), "
               f"rtol={rtol:g}: "
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
    grid, values, weights = padded_outputs(outputs)
    return Evolution(times, grid, values, weights, method="fem", params=params, info=info,
                     series={"zeta": np.array(zetas), "cooling_rate": np.array(rates),
                             "mass": np.array(masses),
                             "segments": np.array(segs, dtype=float)})
