"""FEM transient of a freely cooling granular mixture on segments of fixed velocity unit.

The mixture's species cool together, :math:`\\partial_t P_s = C_s[P_1, \\dots, P_k]`
(:mod:`kinetic_fem.model.mixture`, no thermostat), in physical velocities.  The method
is the one-species free-cooling transient's
(:mod:`kinetic_fem.solvers.fem.cooling_transient`) on the stacked species of the heated
mixture transient (:class:`~kinetic_fem.solvers.fem.mixture_transient.MixtureBDF`:
variable-order BDF, simplified Newton on the coupled Galerkin system, each species' mass
kept to round-off, the error on every :math:`T_s` relative and :math:`a_{2,s}`
absolute per collision time of the fastest species):

* within a segment every species' velocity is measured in one unit :math:`V`,
  :math:`P_s(v) = p_s(v/V)/V`; for the power law :math:`|g|^\\gamma` the collision
  term in these units is that of the density :math:`nV^\\gamma`
  (:class:`~kinetic_fem.solvers.fem.mixture.MixtureDiscretisation` with that density),
  so a segment is the heated mixture integrator without thermostats;
* each species has its own mesh in the unit :math:`V`, of ``spacing`` /
  :math:`\\sqrt{\\text{rescale}}` of its thermal velocity :math:`\\sigma_s` at the start
  of a segment and at most ``cutoff`` :math:`\\sigma_s` wide;
* a segment ends when the mean variance :math:`\\sum_s x_s\\langle w^2\\rangle_s` or
  any species' :math:`\\langle w^2\\rangle_s` has fallen by ``rescale`` since its start,
  or when any species' far tail has become too steep
  (:data:`~kinetic_fem.solvers.fem.cooling_segments.EDGE_DROP`); the new unit is
  :math:`V' = V (\\sum_s x_s\\langle w^2\\rangle_s)^{1/2}`, and every species is remapped
  as one species is (:func:`~kinetic_fem.solvers.fem.cooling_segments.segment_vertices`,
  :func:`~kinetic_fem.solvers.fem.cooling_segments.remap_log_density`) and corrected by
  :math:`u_s \\to u_s + a_s + b_s w^2` to unit mass and its own
  :math:`\\langle w^2\\rangle_s` (:func:`~kinetic_fem.solvers.fem.cooling_segments.normalise`),
  so every :math:`T_s(t)` is continuous across a remap to round-off; the integrator
  restarts (backward Euler) with the step scaled by :math:`(V'/V)^{-\\gamma}`.

A mixture of identical species is the one-species transient
(``evolve_cooling(alpha, method="fem")``): the same meshes, operators and decisions, to
round-off.

Reported at each output time: :math:`T_s = m_s V^2\\langle w^2\\rangle_s`,
:math:`a_{2,s}`, each species' distribution (physical velocities), and from the
Galerkin energy balance of the collision term the mixture's cooling rate
:math:`\\zeta` (:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`, :math:`T = \\sum_s x_s T_s`),
``cooling_rate`` :math:`= -d\\ln T/dt` and each species' :math:`-d\\ln T_s/dt`
(equal in the homogeneous cooling state, :func:`kinetic_fem.solve_cooling` of the
mixture).

Accuracy at late times: the run settles on the homogeneous cooling state up to the
global error of the time integration, not the meshes.  Hard rods, masses 1:3, alpha 0.7
(rtol 1e-4, spacing 0.7): the temperature ratio within 4e-5 and :math:`a_{2,s}` within
-2.3e-4 / -2.7e-4 at t = 300-1000; one species (the same integrator) settles at -5.6e-4
(rtol 1e-4), -3.5e-4 (1e-5) and 6e-6 (1e-6) at t = 1000, while spacing 0.35 against 0.5
changes it by 4e-5 or less (benchmarks/results/mixture_transient.md).

**Any law per pair, any kernel** (as one species): in the unit :math:`V` the collision term
is that of the laws :math:`g \\mapsto \\alpha_{sr}(Vg)` and of the kernel
:math:`B(Vg)/V^d` at the density :math:`nV^d` (:func:`in_unit`), rebuilt at each remap;
no scaling state is needed (the reported :math:`\\zeta` is then a diagnostic of the
power-law definition).  Gaussian starts.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...model.mixture import Mixture
from ...options import gather
from .cooling_segments import (
    EDGE_DROP,
    normalise,
    remap_log_density,
    segment_vertices,
    steepest_drop,
)
from .cooling_transient import cooling_settings
from .mixture import MixtureDiscretisation, check_mixture_model
from .mixture_transient import MixtureBDF, collision_time, layer_start
from .options import CoolingEvolveOptions
from .transient import TimeIntegrator, TransientOptions, build_mesh, floor_log
from .transient_setup import SCHEMES, default_newton_tol

__all__ = ["MixtureCoolingRun", "evolve_mixture_cooling_fem", "in_unit"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class MixtureCoolingRun:
    """What :func:`evolve_mixture_cooling_fem` returns.

    Parameters
    ----------
    temperatures, a2 : ndarray, shape (n_t, k)
        :math:`T_s(t_i)` and :math:`a_{2,s}(t_i)`.
    distributions : tuple of tuple of VelocityDistribution
        ``distributions[i][s]``: species ``s`` at ``t_i`` (physical velocities).
    series : dict of ndarray
        ``"zeta"``, ``"cooling_rate"``, ``"segments"`` (shape (n_t,)) and
        ``"species_cooling_rates"`` (shape (n_t, k)).
    info : dict
        Counters, options, CPU time.
    """

    temperatures: NDArray[np.float64]
    a2: NDArray[np.float64]
    distributions: tuple[tuple[VelocityDistribution, ...], ...]
    series: dict[str, NDArray[np.float64]]
    info: dict[str, Any]


def in_unit(mixture: Mixture, unit: float) -> Mixture:
    """The mixture in velocities measured in ``unit``: every law
    :math:`g \\mapsto \\alpha(Vg)` (:meth:`~kinetic_fem.model.RestitutionLaw.rescaled`) and
    the kernel :math:`B(Vg)/V^d` (:meth:`~kinetic_fem.model.CollisionKernel.rescaled`);
    ``mixture`` itself for constant coefficients and a homogeneous kernel.

    Parameters
    ----------
    mixture : Mixture
    unit : float
        :math:`V > 0`.

    Returns
    -------
    Mixture
    """
    kernel = mixture.collision_kernel
    if kernel.homogeneity_degree is not None and all(
            law.constant is not None for row in mixture.laws for law in row):
        return mixture
    return replace(mixture, alpha=[[law.rescaled(unit) for law in row] for row in mixture.laws],
                   kernel=kernel.rescaled(unit))


class _SpeciesMasses:
    """One species of the stacked integrator as :func:`normalise` reads it."""

    def __init__(self, species: Any) -> None:
        self.x = species.x
        self.masses = species.forms.mass


def evolve_mixture_cooling_fem(mixture: Mixture, *, times: NDArray, density: float,
                               initial_temperatures: NDArray,
                               options: CoolingEvolveOptions | None = None,
                               **option_keywords: Any) -> MixtureCoolingRun:
    """Species temperatures, :math:`a_{2,s}` and distributions of a cooling mixture.

    Parameters
    ----------
    mixture : Mixture
        No forcing; any restitution law per pair; a kernel with a compiled rate.
    times : ndarray, shape (n_t,)
        Output times (physical; checked by the caller).
    density : float
        Total number density :math:`n`.
    initial_temperatures : ndarray, shape (k,)
        :math:`T_s(0)` of the Gaussian start.
    options : CoolingEvolveOptions, optional
        The one-species free-cooling options
        (:func:`~kinetic_fem.solvers.fem.cooling_transient.evolve_cooling_fem`): ``rtol``
        (default 1e-6), ``spacing`` (default 0.25, each species' thermal velocities at
        the end of a segment), ``cutoff``, ``rescale`` (default 4), ``order``,
        ``scheme`` (default ``"bdf2"``), step and Newton options.
    **option_keywords
        Fields of ``options`` by keyword (an unknown one raises :class:`TypeError`).

    Returns
    -------
    MixtureCoolingRun

    Raises
    ------
    ValueError
        For a forced mixture or bad options; relative speeds on a mesh beyond a law's
        range.
    ConvergenceError
        If a species can no longer be resolved (refine ``spacing``).
    """
    cpu = time.process_time()
    mixture = check_mixture_model(mixture, "the FEM mixture cooling transient "
                                  "(method='fem')", cooling=True, scaled=False)
    o = gather(CoolingEvolveOptions, options, option_keywords, "evolve_cooling")
    kernel = mixture.collision_kernel
    spacing, c_cut = cooling_settings(o, kernel)
    if o.scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got {o.scheme!r}")
    degree = float(kernel.scale_degree)
    h_el = spacing / math.sqrt(o.rescale)
    masses = np.asarray(mixture.masses, dtype=float)
    fractions = np.asarray(mixture.fractions, dtype=float)
    var0 = np.asarray(initial_temperatures, dtype=float) / masses
    unit = [math.sqrt(float(fractions @ var0))]   # the velocity unit V of the segment

    def discretise(verts: Any) -> MixtureDiscretisation:
        """The collision term in the unit V: the laws alpha(V g), the kernel B(V g)/V^d
        at the density n V^d (relative speeds checked in physical units)."""
        verts = tuple(verts)
        for s, row in enumerate(mixture.laws):
            for r, law in enumerate(row[s:], start=s):
                law.check_speed(float(verts[s][-1] + verts[r][-1]) * unit[0],
                                f"the FEM meshes of species {s} and {r} (relative speeds up "
                                f"to the sum of their extents: start colder or lower cutoff)")
        return MixtureDiscretisation(in_unit(mixture, unit[0]), verts,
                                     density * unit[0] ** degree, o.order)

    scales = var0 / unit[0] ** 2     # <w^2>_s at the segment's start
    mdisc = discretise(build_mesh(c_cut * math.sqrt(v), h_el * math.sqrt(v)) for v in scales)
    tol = default_newton_tol(o.rtol, o.scheme) if o.newton_tol is None else o.newton_tol
    t_coll = collision_time(mdisc, scales)
    opt = TransientOptions(o.rtol, 1e-9 * t_coll, o.order, spacing, o.cutoff, o.first_step,
                           o.max_step, o.max_steps, tol, o.max_newton,
                           moment_norm=o.newton_norm == "moments", scheme=o.scheme)
    integ = MixtureBDF(mdisc, options=opt)
    integ.positive_history = True   # far-tail dofs take backward Euler (as one species)
    u = np.concatenate([floor_log(sp.x, -0.5 * sp.x**2 / v - 0.5 * math.log(2.0 * math.pi * v))
                        for sp, v in zip(integ.species, scales, strict=True)])

    def variances(u: NDArray) -> NDArray:
        """:math:`\\langle w^2\\rangle_s` (unit V) from the Galerkin masses."""
        ms = [sp.forms.mass(us) for sp, us in zip(integ.species, integ.split(u), strict=True)]
        return np.array([float(sp.x**2 @ m) / float(m.sum())
                         for sp, m in zip(integ.species, ms, strict=True)])

    def remap(u: NDArray, ratio: float, targets: NDArray, t: float) -> NDArray:
        """Every species in the unit ``ratio V`` on a new mesh, with the variances
        ``targets`` (new unit)."""
        olds, us = integ.mdisc.discs, integ.split(u)
        meshes = [segment_vertices(d, us_, ratio, cutoff=c_cut, h=h_el, t=t, spacing=spacing,
                                   scale=math.sqrt(v))
                  for d, us_, v in zip(olds, us, targets, strict=True)]
        unit[0] *= ratio
        integ.set_disc(discretise(verts for verts, _ in meshes))
        return np.concatenate([
            normalise(_SpeciesMasses(sp), remap_log_density(d, us_, sp.x, ratio, resolved), v)
            for sp, d, us_, (_, resolved), v in
            zip(integ.species, olds, us, meshes, targets, strict=True)])

    u = remap(u, 1.0, scales, 0.0)
    h0 = 0.1 * math.sqrt(o.rtol) * t_coll
    if o.first_step is None:
        filled, h0 = layer_start(integ, u, h0)
        if filled is not u:   # the start's temperatures again, to round-off
            u = np.concatenate([normalise(_SpeciesMasses(sp), filled[sl], v) for sp, sl, v
                                in zip(integ.species, integ.full, scales, strict=True)])
    else:
        h0 = o.first_step
    # forced steps (below min_step) stay below a first step in a far tail's layer
    integ.opt = dataclasses.replace(opt, min_step=min(opt.min_step, 0.01 * h0))
    integ.start(integ.level(0.0, u), h0)
    start_scales = scales.copy()
    count = {"segments": 0, "edge": 0}

    def remap_hook(integ: TimeIntegrator) -> None:
        """A new segment once a variance fell by ``rescale`` or a tail is steep."""
        assert isinstance(integ, MixtureBDF)
        last = integ.hist[-1]
        var = variances(last.u)
        mean = float(fractions @ var)
        edge = any(steepest_drop(sp.disc, us) > EDGE_DROP
                   for sp, us in zip(integ.species, integ.split(last.u), strict=True))
        if mean < 1.0 / o.rescale or np.any(var < start_scales / o.rescale) or edge:
            ratio = math.sqrt(mean)
            targets = var / mean
            h_next = integ.h * ratio ** (-degree)   # the collision times grew
            integ.restart(integ.level(last.s, remap(last.u, ratio, targets, last.s)), h_next)
            start_scales[:] = targets
            count["segments"] += 1
            count["edge"] += int(edge)
            logger.debug("remap at t=%.6g (edge %s): unit %.6g, extents %s, step %.3g",
                         last.s, edge, unit[0], [float(sp.x.max()) for sp in integ.species],
                         h_next)

    integ.remap = remap_hook
    moments, dists, rates, units, segments = [], [], [], [], []
    params = {"problem": "mixture cooling transient", "density": density,
              "masses": list(mixture.masses), "fractions": list(mixture.fractions)}
    for stop in times:
        if stop > 0.0:
            integ.advance_to(float(stop))
        u_out = integ.hist[-1].u
        mom = integ.species_moments(u_out)         # mass, <w^2>, a2 of each species
        # d<w^2>_s/dt from the Galerkin energy balance (rhs: reduced values at v >= 0)
        rhs = integ.rhs(u_out, float(stop))
        rates.append([float(sp.x**2 @ rhs[sl]) / m0 for sp, sl, m0 in
                      zip(integ.species, integ.full, mom[:, 0], strict=True)])
        v = unit[0]
        dists.append(tuple(VelocityDistribution.from_values(
            sp.xq * v, sp.disc.values(us) / v, weights=sp.wq * v, method="fem", params=params)
            for sp, us in zip(integ.species, integ.split(u_out), strict=True)))
        moments.append(mom)
        units.append(v)
        segments.append(count["segments"])
    mom_t, unit_t = np.array(moments), np.array(units)
    var_w = mom_t[:, :, 1]
    temps = var_w * masses[None, :] * unit_t[:, None] ** 2
    dvar = np.array(rates)                        # d<w^2>_s/dt (physical time)
    temp_w, dtemp_w = var_w @ (fractions * masses), dvar @ (fractions * masses)
    series = {"zeta": -dtemp_w / (2.0 * density * unit_t**degree
                                  * temp_w ** (1.0 + 0.5 * degree)),
              "cooling_rate": -dtemp_w / temp_w,
              "species_cooling_rates": -dvar / var_w,
              "segments": np.array(segments, dtype=float)}
    st = integ.stats
    info = {**st.as_dict(), "rtol": o.rtol, "order": o.order, "scheme": o.scheme,
            "segments": count["segments"] + 1, "edge_remaps": count["edge"],
            "n_dofs": [int(sp.x.size) for sp in integ.species],
            "history_limited": integ.limited, "history_mass_defect": integ.mass_defect,
            "density": density, "cpu_time": time.process_time() - cpu}
    logger.info("FEM mixture cooling transient, rtol=%g: %d segments (%d ended by a steep "
                "tail), %d steps (%d rejected, %d Newton failures), %d Jacobians", o.rtol,
                count["segments"] + 1, count["edge"], st.accepted, st.rejected,
                st.newton_failures, st.jacobians)
    return MixtureCoolingRun(temps, mom_t[:, :, 2], tuple(dists), series, info)
