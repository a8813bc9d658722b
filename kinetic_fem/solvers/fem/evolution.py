"""FEM transients of the heated and the freely cooling gas (method ``"fem"``).

Sets up the velocity mesh, the initial state and the protocol for the adaptive
integrator of :mod:`kinetic_fem.solvers.fem.transient`, and collects the output as an
:class:`~kinetic_fem.evolution.Evolution`.

* Heated gas: physical velocities; the mesh covers ``cutoff`` thermal velocities of
  the hottest state met (initial state or a Gaussian-closure steady temperature
  :meth:`HeatedProblem.temperature_estimate` of any protocol value) with elements of
  ``spacing`` thermal velocities of the coldest, refined where a Gaussian at the
  coldest temperature falls by more than 2 in ln P per element (down to 1e-30 of its
  peak; :func:`~kinetic_fem.solvers.fem.transient_setup.build_mesh`).  The error is
  controlled per collision time of the current state.  The integrator stops exactly at the
  output times and restarts (backward Euler, small step) at the protocol's
  discontinuities.
* Free cooling: :mod:`kinetic_fem.solvers.fem.cooling_transient` (physical velocities on
  segments of fixed velocity scale).
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
from ...model import (
    HeatedProblem,
    InelasticGas,
    as_thermostat,
)
from ...model.protocol import Protocol
from ...options import gather
from ...solve import register_solver
from .options import EvolveOptions
from .transient import BDF2, TransientOptions, build_mesh, floor_log, make_discretisation
from .transient_setup import (
    SCHEMES,
    default_newton_tol,
    distribution_log_density,
    progress_bar,
)

__all__ = ["evolve_heated_fem", "default_transient_cutoff", "default_transient_spacing"]

logger = logging.getLogger(__name__)

def default_transient_cutoff(gamma: float) -> float:
    """Half-width of the mesh in thermal velocities: :math:`\\max(10, 26 - 11\\gamma)`.

    Covers the steady tails to about 1e-20 relative (exponential for Maxwell
    molecules, :math:`e^{-A c^{3/2}}` for hard rods), enough for moments up to
    :math:`\\langle v^{12}\\rangle` at the tolerances of the tests.

    Parameters
    ----------
    gamma : float
        Kernel exponent.

    Returns
    -------
    float
    """
    return max(10.0, 26.0 - 11.0 * gamma)


def default_transient_spacing(rtol: float) -> float:
    """Element size in thermal velocities of the coldest state, chosen from ``rtol``:
    :math:`0.5\\,(r_{tol}/10^{-4})^{1/4}` within [0.25, 0.5].

    The spatial error then stays near ``rtol / 10``: measured on the heated Maxwell
    transient (alpha 0.5, friction 0.5, from T = 1, default cut-off) against its exact
    moments, the error of a2 left at rtol 1e-6 (the time error removed) is 1.1e-5 at
    spacing 0.5 and below 8e-7 at 0.25, about :math:`\\propto` spacing^4 (P2); T's
    below 1e-6 at both.  Hard rods (alpha 0.6 from T = 0.5): spacing 0.5 moves T(5)
    by 1.5e-7 and a2 by 5e-7 from spacing 0.25.  Coarser than 0.5 saves few nodes (the
    mesh is graded where the coldest Gaussian is steep, :func:`build_mesh`); below
    rtol 6.25e-6 the spacing is 0.25 (the earlier fixed default).

    Parameters
    ----------
    rtol : float
        The transient's tolerance.

    Returns
    -------
    float
    """
    return min(0.5, max(0.25, 0.5 * (rtol / 1e-4) ** 0.25))


def _temperatures(problem: HeatedProblem, protocol: Protocol, t_end: float,
                  times: NDArray) -> list[float]:
    """Gaussian-closure steady temperatures of the protocol's states."""
    samples = set(times.tolist()) | {0.0, t_end} | set(protocol.breakpoints(t_end))
    samples |= set(np.linspace(0.0, t_end, 41).tolist())
    gas = problem.gas
    out = []
    for t in sorted(samples):
        d = protocol.diffusion_at(t, problem.diffusion)
        xi = protocol.friction_at(t, problem.friction)
        law = protocol.restitution_at(t, gas.restitution)
        try:
            state = HeatedProblem(InelasticGas(law, gas.density, gas.kernel),
                                  as_thermostat(d, xi))
        except ValueError as err:
            raise ValueError(f"the protocol at t={t:g} (D={d:g}, friction={xi:g}, "
                             f"{law!r}) is not a valid heated problem: {err}") from None
        out.append(state.temperature_estimate())
    return out


def _evolution(outputs: list, integ: BDF2, times: NDArray, params: dict, start: float,
               message: str, series: dict) -> Evolution:
    xq, wq = integ.xq, integ.wq
    grid = np.array([xq for _ in outputs])
    values = np.array([integ.disc.values(u) for u in outputs])
    weights = np.array([wq for _ in outputs])
    st = integ.stats
    info = RunInfo(converged=True, iterations=st.accepted, residual=float("nan"),
                   wall_time=time.perf_counter() - start, message=message,
                   extra={**st.as_dict(), "rtol": integ.opt.rtol,
                          "n_dofs": int(integ.x.size), "order": integ.opt.order})
    series = {**series, "mass": np.array([integ.moments(u)[0] for u in outputs])}
    return Evolution(times, grid, values, weights, method="fem", params=params, info=info,
                     series=series)


@register_solver("fem", problem="transient-heated")
def evolve_heated_fem(problem: HeatedProblem, *, times: NDArray, protocol: Protocol,
                      initial: VelocityDistribution | None,
                      initial_temperature: float | None, options: EvolveOptions | None = None,
                      progress: bool = False, **option_keywords: Any) -> Evolution:
    """Transient of the heated gas under ``protocol`` by adaptive BDF2 (see the module).

    Parameters
    ----------
    problem : HeatedProblem
        The gas and thermostat at ``t = 0``.
    times : ndarray, shape (n_t,)
        Output times, checked by :func:`kinetic_fem.evolve.check_times`.
    protocol : Protocol
        Time dependence of the thermostat and the restitution.
    initial : VelocityDistribution or None
        Initial state (normalised), or None for a Gaussian.
    initial_temperature : float or None
        Temperature of the Gaussian start.
    options : EvolveOptions, optional
        The numerical options as one object
        (:class:`~kinetic_fem.solvers.fem.options.EvolveOptions`: ``rtol`` default 1e-4,
        ``order``, ``spacing`` default :func:`default_transient_spacing`, ``cutoff``,
        ``first_step``, ``max_step``, ``max_steps``, ``newton_tol`` default
        :func:`default_newton_tol`, ``max_newton``, ``scheme``: ``"bdf4"`` by default,
        ``"bdf3"`` or ``"bdf2"``).
    progress : bool
        Show a progress bar over time (tqdm).
    **option_keywords
        Fields of :class:`~kinetic_fem.solvers.fem.options.EvolveOptions` by keyword
        (over ``options``; an unknown keyword raises :class:`TypeError`).

    Returns
    -------
    Evolution
    """
    o = gather(EvolveOptions, options, option_keywords, "evolve_heated")
    rtol, order, spacing, cutoff = o.rtol, o.order, o.spacing, o.cutoff
    first_step, newton_tol, scheme = o.first_step, o.newton_tol, o.scheme
    start = time.perf_counter()
    gas = problem.gas
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got {scheme!r}")
    t_end = float(times[-1])
    if spacing is None:
        spacing = default_transient_spacing(rtol)
    temps = _temperatures(problem, protocol, t_end, times)
    t_init = initial.temperature if initial is not None else (
        initial_temperature if initial_temperature is not None else temps[0])
    hot, cold = max(max(temps), t_init), min(min(temps), t_init)
    c_cut = default_transient_cutoff(gas.kernel.tail_growth[1]) if cutoff is None else cutoff
    verts = build_mesh(c_cut * math.sqrt(hot), spacing * math.sqrt(cold), math.sqrt(cold))
    laws = {}

    def disc_at(t: float):
        law = protocol.restitution_at(t, gas.restitution)
        if law not in laws:
            laws[law] = make_discretisation(law, gas.kernel, verts, order)
        return laws[law]

    def coefficients(t: float, left: bool = True) -> tuple[float, float, float]:
        # implicit steps end at t: the value on the step is the left limit at a switch
        return (gas.density, protocol.diffusion_at(t, problem.diffusion, left=left),
                protocol.friction_at(t, problem.friction, left=left))

    t_coll = 1.0 / (gas.density * float(gas.kernel.rate(math.sqrt(cold))))
    # first step (and after a switch): backward Euler's error per unit step is about
    # h/t_coll, so rtol collision times; the step control grows it
    h0 = first_step if first_step is not None else rtol * t_coll
    tol = default_newton_tol(rtol, scheme) if newton_tol is None else newton_tol
    opt = TransientOptions(rtol, 0.0, order, spacing, cutoff, first_step, o.max_step,
                           o.max_steps, tol, o.max_newton,
                           moment_norm=o.newton_norm == "moments", scheme=scheme)
    integ = BDF2(disc_at(0.0), coefficients, options=opt,
                 collision_time=lambda temp: 1.0 / (
                     gas.density * float(gas.kernel.rate(math.sqrt(temp)))))
    x = integ.x
    if initial is not None:
        u = distribution_log_density(initial, x)
    else:
        u = floor_log(x, -0.5 * x**2 / t_init - 0.5 * math.log(2.0 * math.pi * t_init))
    u = u - math.log(integ.moments(u)[0])
    integ.start(integ.level(0.0, u), h0)
    breaks = list(protocol.breakpoints(t_end))
    stops = sorted(set(times.tolist()) | set(breaks))
    outputs = [u] if times[0] == 0.0 else []
    bar, update = progress_bar(progress, t_end, "evolve_heated")
    with bar:
        for stop in stops:
            if stop == 0.0:
                continue
            integ.advance_to(stop, update)
            if times[np.searchsorted(times, stop)] == stop if stop <= t_end else False:
                outputs.append(integ.hist[-1].u)
            if stop in breaks:
                integ.set_disc(disc_at(stop))
                integ.restart(integ.level(stop, integ.hist[-1].u), h0)
    params = {**problem.as_dict(), "problem": "heated transient",
              "protocol": repr(protocol)}
    series = {"diffusion": np.array([coefficients(t, False)[1] for t in times]),
              "friction": np.array([coefficients(t, False)[2] for t in times])}
    st = integ.stats
    message = (f"adaptive {scheme.upper()}, rtol={rtol:g}: {st.accepted} steps "
               f"({st.forced} at the minimum "
               f"step {opt.min_step:.3g} above tolerance, {st.rejected} rejected, "
               f"{st.newton_failures} Newton failures), {st.newton_iterations} Newton "
               f"iterations, {st.jacobians} Jacobians, {st.factorisations} factorisations, "
               f"{st.restarts} restarts")
    logger.info(message)
    return _evolution(outputs, integ, times, params, start, message, series)
