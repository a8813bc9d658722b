"""FEM transient of a heated granular mixture: the species relax from Gaussians.

The semi-discrete system of every species :math:`s` (its own mesh and basis, the weak
forms of :mod:`kinetic_fem.solvers.fem.mixture`),

.. math::

    \\frac{d}{dt}\\int\\varphi^s_i P_s = C^s_i[P_1, \\dots, P_k]
    - D_s\\int\\varphi^{s\\prime}_i P_s' - \\xi_s\\int\\varphi^{s\\prime}_i v P_s,

is integrated by the one-species adaptive integrator
(:class:`~kinetic_fem.solvers.fem.transient.BDF2`: variable-order BDF up to BDF4,
simplified Newton, tail closure, backtrack) over the stacked unknowns
:math:`u = (\\ln P_1, \\dots, \\ln P_k)`: :class:`MixtureBDF` is that integrator with
the collision term and Jacobian of the coupled
:class:`~kinetic_fem.solvers.fem.mixture.MixtureDiscretisation`, block-diagonal masses,
thermostats, tail closures and Newton norms (one per species), each species' mass
kept to round-off, and the error measured on every :math:`T_s` (relative) and
:math:`a_{2,s}` (absolute) per collision time of the species that collides fastest.

Meshes: each species' as the one-species heated transient's
(:func:`~kinetic_fem.solvers.fem.transient_setup.build_mesh`), over the range of
:math:`\\langle v^2\\rangle_s` that the Gaussian approximation of the same relaxation
visits (:func:`kinetic_fem.solvers.mixture_gaussian.relaxation`), its
steady state and the start.  A mixture of identical species is the one-species transient
(``evolve_heated(alpha, method="fem")``) on the same mesh to round-off.

Free cooling (no thermostat) is this integrator on segments of fixed velocity unit:
:mod:`kinetic_fem.solvers.fem.mixture_cooling_transient`.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...model.mixture import Mixture
from ...options import gather
from .. import mixture_gaussian
from .evolution import default_transient_cutoff, default_transient_spacing
from .heated import EquilibratedLU
from .mixture import (
    MixtureDiscretisation,
    check_mixture_model,
    check_mixture_vertices,
    gaussian_variances,
)
from .options import EvolveOptions
from .transient import BDF2, Level, MeshView, TransientOptions, factor_with_tail
from .transient_setup import LOG_SMALLEST, SCHEMES, build_mesh, default_newton_tol, floor_log

__all__ = ["MixtureBDF", "evolve_mixture_fem", "transient_meshes"]

logger = logging.getLogger(__name__)


class _Species(MeshView):
    """One species' view of the stacked system: what :class:`BDF2`'s per-state methods
    (``moments``, ``moments_change``, ``newton_weights``, ``tail_closure``) read."""

    def __init__(self, disc: Any) -> None:
        self.bind_mesh(disc)


class _StackedForms:
    """:meth:`Forms.mass` of the stacked unknowns (what :meth:`BDF2.solve_step` reads)."""

    def __init__(self, species: Sequence[_Species], full: Sequence[slice]) -> None:
        self.species, self.full = species, full

    def mass(self, u: NDArray) -> NDArray:
        """:math:`\\int\\varphi^s_i e^{u_s}` of every species, stacked."""
        return np.concatenate([sp.forms.mass(u[sl]) for sp, sl in
                               zip(self.species, self.full, strict=True)])


class MixtureBDF(BDF2):
    """:class:`BDF2` on the stacked species of a heated mixture (see the module).

    Parameters
    ----------
    mdisc : MixtureDiscretisation
        The species' meshes and the pair sums.
    options : TransientOptions
        Tolerances and step limits.
    """

    def __init__(self, mdisc: MixtureDiscretisation, *, options: TransientOptions) -> None:
        mix = mdisc.mixture
        self.thermostats = [(t.diffusion, t.friction) for t in mix.thermostats]  # type: ignore[union-attr]
        super().__init__(mdisc, None, options=options)  # type: ignore[arg-type]

    def set_disc(self, disc: Any) -> None:
        """Use the mixture discretisation ``disc``.

        Parameters
        ----------
        disc : MixtureDiscretisation
            The species' meshes.
        """
        self.disc = self.mdisc = disc
        self.species = [_Species(d) for d in disc.discs]
        ends = np.cumsum([0] + [sp.x.size for sp in self.species])
        self.full = [slice(int(a), int(b)) for a, b in zip(ends[:-1], ends[1:], strict=True)]
        red = disc.offsets
        self.reduced = [slice(int(a), int(b)) for a, b in zip(red[:-1], red[1:], strict=True)]
        self.sym = scipy.sparse.block_diag([sp.sym for sp in self.species], format="csr")
        self.x = np.concatenate([sp.x for sp in self.species])
        self.keep = np.flatnonzero(self.x >= 0)
        self.forms = _StackedForms(self.species, self.full)  # type: ignore[assignment]
        self._jacobian = None
        self._lu = None

    def split(self, u: NDArray) -> list[NDArray]:
        """The species' coefficients of the stacked ``u``."""
        return [u[sl] for sl in self.full]

    # ------------------------------------------------------------------ the system
    def species_moments(self, u: NDArray) -> NDArray:
        """Mass, :math:`\\langle v^2\\rangle_s` and :math:`a_{2,s}` of each species, shape
        (k, 3)."""
        return np.array([BDF2.moments(sp, u[sl])  # type: ignore[arg-type]
                         for sp, sl in zip(self.species, self.full, strict=True)])

    def observables(self, u: NDArray) -> NDArray:
        """Every :math:`\\langle v^2\\rangle_s`, then every :math:`a_{2,s}`."""
        mom = self.species_moments(u)
        return np.concatenate([mom[:, 1], mom[:, 2]])

    def moments_change(self, u: NDArray, du: NDArray) -> NDArray:
        """First-order change of :meth:`observables` by ``du``."""
        ch = np.array([BDF2.moments_change(sp, u[sl], du[sl])  # type: ignore[arg-type]
                       for sp, sl in zip(self.species, self.full, strict=True)])
        return np.concatenate([ch[:, 0], ch[:, 1]])

    def error_norm(self, level: Level, diff: NDArray) -> float:
        """The largest relative change of a :math:`T_s` and absolute one of an
        :math:`a_{2,s}`.

        Parameters
        ----------
        level : Level
            The new level.
        diff : ndarray
            Absolute changes of :meth:`observables`.
        """
        k = len(self.species)
        return float(max(np.max(diff[:k] / level.obs[:k]), np.max(diff[k:])))

    def time_unit(self, level: Level) -> float:
        """The shortest mean free time :math:`1/(n B(\\sigma_s))` of the species.

        Parameters
        ----------
        level : Level
            The new level.
        """
        return collision_time(self.mdisc, level.obs[:len(self.species)])

    def renormalised(self, u: NDArray, m_last: NDArray) -> NDArray:
        """Each species shifted to its mass of the last level.

        Parameters
        ----------
        u : ndarray
            The step's solution.
        m_last : ndarray
            Masses of the last level.
        """
        out = u.copy()
        m_new = self.masses(u)
        for sl in self.full:
            out[sl] += math.log(float(m_last[sl].sum()) / float(m_new[sl].sum()))
        return out

    def history_target(self, c_old: NDArray, m_last: NDArray, c_new: float,
                       force: bool = False) -> NDArray:
        """:meth:`BDF2.history_target` species by species (each keeps its mass).

        Parameters
        ----------
        c_old, m_last : ndarray
            History term of the step and the masses of the last level.
        c_new : float
            Coefficient of the new masses.
        force : bool
            Also without ``positive_history``.
        """
        return np.concatenate([super(MixtureBDF, self).history_target(
            c_old[sl], m_last[sl], c_new, force) for sl in self.full])

    def _reduced_rhs(self, u: NDArray) -> NDArray:
        coll = self.mdisc.collision(self.split(u))[0]
        self.stats.residuals += 1
        return np.concatenate([
            c - sp.sym.T @ sp.forms.thermostat(u[sl], d, xi) for c, sp, sl, (d, xi) in
            zip(coll, self.species, self.full, self.thermostats, strict=True)])

    def rhs(self, u: NDArray, t: float, left: bool = True) -> NDArray:
        """A full vector whose even reduction is the reduced right-hand side (the
        reduced values at the dofs ``v >= 0``, zero at their mirrors)."""
        out = np.zeros(self.x.size)
        out[self.keep] = self._reduced_rhs(u)
        return out

    def _reduced_mass(self, u: NDArray) -> scipy.sparse.csr_matrix:
        return scipy.sparse.block_diag(
            [sp.sym.T @ sp.forms.weighted_mass(u[sl]) @ sp.sym
             for sp, sl in zip(self.species, self.full, strict=True)], format="csc")

    def derivative(self, u: NDArray, t: float) -> NDArray:
        """:math:`\\dot u` (reduced system, expanded)."""
        return self.sym @ scipy.sparse.linalg.spsolve(self._reduced_mass(u),
                                                      self._reduced_rhs(u))

    def _evaluate_jacobian(self, u: NDArray, t: float) -> None:
        """The reduced Jacobian and mass matrix at ``u``, as derivatives in P."""
        blocks = self.mdisc.collision(self.split(u), jacobian=True)[1]
        self.stats.jacobians += 1
        jac = np.block(blocks)
        for sp, sl, rs, (d, xi) in zip(self.species, self.full, self.reduced,
                                       self.thermostats, strict=True):
            jac[rs, rs] -= (sp.sym.T @ sp.forms.thermostat_jacobian(u[sl], d, xi)
                            @ sp.sym).toarray()
        # kept as derivatives in P; a far-tail ln P below LOG_SMALLEST (the linear tail
        # closure of a wide mesh: a Maxwell mixture reached ln P = -1100 at the edge,
        # where e^u underflows and 1/e^u overflows) is scaled as if it were there: those
        # columns are ~e^u and only meet the tail rows
        inv = np.exp(-np.maximum(u[self.keep], LOG_SMALLEST))[None, :]
        self._jacobian = (jac * inv, self._reduced_mass(u).toarray() * inv, None)
        self._lu = None

    def _factor(self, c_new: float, h: float, tail: tuple, u: NDArray
                ) -> EquilibratedLU | None:
        """LU of the reduced ``c_new M - h J`` with the tail rows (cached by its key);
        None if it is not finite (the step fails and is retried smaller, as
        :meth:`BDF2._factor`)."""
        idx, in1, in2, coef = tail
        key = (c_new, h, idx.tobytes(), in1.tobytes() + in2.tobytes(), coef.tobytes(),
               u.tobytes())
        if self._lu is not None and self._lu[0] == key:
            return self._lu[1]
        assert self._jacobian is not None
        jac, mw, _ = self._jacobian
        with np.errstate(over="ignore", invalid="ignore"):
            red = (c_new * mw - h * jac) * np.exp(np.maximum(u[self.keep],
                                                             LOG_SMALLEST))[None, :]
        lu = factor_with_tail(red, tail)
        if lu is not None:
            self.stats.factorisations += 1
            self._lu = (key, lu)
        return lu

    def filtered(self, du: NDArray) -> NDArray:
        """``(c_new M - h J)^{-1} c_new M du`` with the step's factorisation."""
        assert self._jacobian is not None and self._lu is not None
        key, lu = self._lu
        mw = self._jacobian[1] * np.exp(np.maximum(np.frombuffer(key[5])[self.keep],
                                                   LOG_SMALLEST))[None, :]
        rhs = key[0] * (mw @ du[self.keep])
        rhs[np.frombuffer(key[2], dtype=np.int64)] = 0.0
        return self.sym @ lu.solve(rhs)

    def newton_weights(self, u: NDArray) -> NDArray:
        """:meth:`BDF2.newton_weights` of each species, block-diagonal."""
        rows = [BDF2.newton_weights(sp, u[sl])  # type: ignore[arg-type]
                for sp, sl in zip(self.species, self.full, strict=True)]
        out = np.zeros((sum(r.shape[0] for r in rows), self.keep.size))
        start = 0
        for r, rs in zip(rows, self.reduced, strict=True):
            out[start:start + r.shape[0], rs] = r
            start += r.shape[0]
        return out

    def tail_closure(self, u: NDArray) -> tuple[NDArray, Any, Any, NDArray]:
        """Every species' far tail (:meth:`BDF2.tail_closure`), stacked: the inner dofs
        are arrays, one per tail dof."""
        idx, in1, in2, coef = [], [], [], []
        for sp, sl, rs in zip(self.species, self.full, self.reduced, strict=True):
            i, a, b, c = BDF2.tail_closure(sp, u[sl])  # type: ignore[arg-type]
            if i.size:
                idx.append(i + rs.start)
                in1.append(np.full(i.size, a + rs.start, dtype=np.int64))
                in2.append(np.full(i.size, b + rs.start, dtype=np.int64))
                coef.append(c)
        if not idx:
            empty = np.zeros(0, dtype=np.int64)
            return empty, empty, empty, np.zeros(0)
        return (np.concatenate(idx), np.concatenate(in1), np.concatenate(in2),
                np.concatenate(coef))


LAYER_TRIGGER = 1.0
"""A start has a far-tail layer where its derivative predicts a change of ln P above this
in the first step, at a dof off the tail closure (:func:`layer_start`; starts without
one predict 2e-2 to 0.2 at the default first step)."""

LAYER_CHANGE = 0.1
"""The change of ln P the first step after a filled layer predicts (:func:`layer_start`)."""

LAYER_TIME = 1e-3
"""The far-tail layer of a start is filled with the gain of ``LAYER_TIME`` first steps
(:func:`layer_start`)."""


def layer_start(integ: MixtureBDF, u: NDArray, h0: float) -> tuple[NDArray, float]:
    """The start and the first step, with the initial layer of the far tails.

    A partner heavier than a species (:math:`\\mu(1 + \\alpha) > 1`) throws it beyond the
    heavier partner's velocity, so a Gaussian start's far tail gains, per unit time, up
    to 1e15 times its own value (hard rods alpha 0.8, masses 1:3 from T_s = (1, 3)): ln P
    rises there by tens within 1e-15 collision times, and no implicit step (from 1e-4
    down to 1e-16 collision times) converged.  Where the start's derivative predicts a
    change of ln P above :data:`LAYER_TRIGGER` in the first step ``h0``, the dofs that
    the gain of :math:`\\delta` = ``LAYER_TIME * h0`` would raise by more than a factor 2
    start there, :math:`\\ln(P + \\delta \\dot P)`, what the collisions put there in
    the time :math:`\\delta` (the moments change by that gain: 7e-13 relative in T_1 for
    the inelastic Maxwell mixture, masses 1:3 from T_s = (1, 3), rtol 1e-4; the
    free-cooling transient restores the start's temperatures), and the first step is
    kept to a predicted change of :data:`LAYER_CHANGE`.  Starts without such a layer
    are returned as they are.

    Parameters
    ----------
    integ : MixtureBDF
        The integrator, not started.
    u : ndarray
        The start.
    h0 : float
        The first step wanted.

    Returns
    -------
    u : ndarray
    h0 : float
    """
    def fastest(u: NDArray) -> tuple[NDArray, float]:
        du = integ.derivative(u, 0.0)
        red = du[integ.keep]
        red[integ.tail_closure(u)[0]] = 0.0
        top = float(np.abs(red).max())
        return du, top if math.isfinite(top) else math.inf

    du, top = fastest(u)
    if top * h0 <= LAYER_TRIGGER:
        return u, h0
    gain = LAYER_TIME * h0 * np.maximum(np.nan_to_num(du, posinf=0.0), 0.0)
    u = np.where(gain > 1.0, u + np.log1p(gain), u)
    top = fastest(u)[1]
    logger.debug("far-tail layer at the start: ln P raised by up to %.3g, first step %.3g",
                 float(np.log1p(gain).max()), min(h0, LAYER_CHANGE / top))
    return u, min(h0, LAYER_CHANGE / top)


def collision_time(mdisc: MixtureDiscretisation, variances: NDArray) -> float:
    """The shortest mean free time :math:`1/(n B(\\sigma_s))` over the species.

    Parameters
    ----------
    mdisc : MixtureDiscretisation
        The model and density.
    variances : ndarray
        :math:`\\langle v^2\\rangle_s`.

    Returns
    -------
    float
    """
    kernel = mdisc.mixture.collision_kernel
    return min(1.0 / (mdisc.density * float(kernel.rate(math.sqrt(v)))) for v in variances)


def transient_meshes(mixture: Mixture, variances: NDArray, *, spacing: float,
                     cutoff: float | None = None) -> tuple[NDArray, ...]:
    """Each species' mesh over the range of its :math:`\\langle v^2\\rangle_s`.

    As the one-species heated transient's
    (:func:`~kinetic_fem.solvers.fem.transient_setup.build_mesh`): ``cutoff`` thermal
    velocities of the hottest state, elements of ``spacing`` thermal velocities of the
    coldest, refined where the coldest Gaussian is steep.

    Parameters
    ----------
    mixture : Mixture
        The model (its kernel sets the default cut-off).
    variances : ndarray, shape (n, k)
        :math:`\\langle v^2\\rangle_s` met by the transient (rows: samples).
    spacing : float
        Element size in thermal velocities of the coldest state.
    cutoff : float, optional
        Half-width in thermal velocities of the hottest state (default
        :func:`~kinetic_fem.solvers.fem.evolution.default_transient_cutoff`).

    Returns
    -------
    tuple of ndarray
    """
    c_cut = default_transient_cutoff(mixture.collision_kernel.tail_growth[1]) \
        if cutoff is None else cutoff
    hot, cold = np.max(variances, axis=0), np.min(variances, axis=0)
    return tuple(build_mesh(c_cut * math.sqrt(h), spacing * math.sqrt(c), math.sqrt(c))
                 for h, c in zip(hot, cold, strict=True))


def _visited_variances(mixture: Mixture, density: float, var0: NDArray,
                       times: NDArray) -> NDArray:
    """:math:`\\langle v^2\\rangle_s` of the Gaussian approximation of the relaxation
    (41 samples and the output times) and the start."""
    t_end = float(times[-1])
    samples = np.union1d(np.linspace(0.0, t_end, 41), times)
    # the Gaussian steady state too, as the one-species transient's mesh
    steady = gaussian_variances(mixture, density, False)[None, :]
    if t_end == 0.0:
        return np.vstack([var0[None, :], steady])
    gauss = mixture_gaussian.relaxation(mixture, var0, samples, density=density, rtol=1e-8)
    return np.vstack([var0[None, :], steady, gauss])


def evolve_mixture_fem(mixture: Mixture, *, times: NDArray, density: float,
                       initial_temperatures: NDArray, vertices: object = None,
                       options: EvolveOptions | None = None, **option_keywords: Any
                       ) -> tuple[NDArray, NDArray, tuple[tuple[VelocityDistribution, ...], ...],
                                  dict[str, Any]]:
    """Species temperatures, :math:`a_{2,s}` and distributions of a heated mixture from
    Gaussians.

    Parameters
    ----------
    mixture : Mixture
        Every species forced; a restitution law per pair (constant or
        velocity-dependent).
    times : ndarray, shape (n_t,)
        Output times (checked).
    density : float
        Total number density.
    initial_temperatures : ndarray, shape (k,)
        :math:`T_s(0)`.
    vertices : array_like or sequence of array_like, optional
        Explicit meshes (one for every species or one each; physical velocities,
        symmetric with a vertex at 0); override ``spacing`` and ``cutoff``.
    options : EvolveOptions, optional
        The numerical options of the one-species heated transient (``rtol`` default
        1e-4, ``order`` 1 or 2, ``spacing``, ``cutoff``, ``scheme`` default ``"bdf4"``, ...).
    **option_keywords
        Fields of :class:`~kinetic_fem.solvers.fem.options.EvolveOptions` by keyword.

    Returns
    -------
    temperatures, a2 : ndarray, shape (n_t, k)
    distributions : tuple of tuple of VelocityDistribution
        ``distributions[i][s]``: species ``s`` at ``times[i]`` (quadrature points and
        weights of its mesh).
    info : dict
        The integrator's counters, ``rtol``, the meshes (``vertices``), ``n_dofs``,
        ``cpu_time``.

    Raises
    ------
    ValueError
        For a free-cooling mixture, bad options or meshes; relative speeds on the meshes
        beyond a law's range.
    """
    cpu = time.process_time()
    mixture = check_mixture_model(mixture, "the FEM mixture transient (method='fem')",
                           cooling=False)
    o = gather(EvolveOptions, options, option_keywords, "evolve_heated")
    if o.order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {o.order!r}")
    if o.scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got {o.scheme!r}")
    masses = np.asarray(mixture.masses, dtype=float)
    var0 = np.asarray(initial_temperatures, dtype=float) / masses
    spacing = default_transient_spacing(o.rtol) if o.spacing is None else o.spacing
    visited = _visited_variances(mixture, density, var0, times)
    if vertices is not None:
        verts = check_mixture_vertices(vertices, mixture.n_species)
    else:
        verts = transient_meshes(mixture, visited, spacing=spacing, cutoff=o.cutoff)
    mdisc = MixtureDiscretisation(mixture, verts, density, o.order)
    tol = default_newton_tol(o.rtol, o.scheme) if o.newton_tol is None else o.newton_tol
    opt = TransientOptions(o.rtol, 0.0, o.order, spacing, o.cutoff, o.first_step, o.max_step,
                           o.max_steps, tol, o.max_newton,
                           moment_norm=o.newton_norm == "moments", scheme=o.scheme)
    integ = MixtureBDF(mdisc, options=opt)
    u = np.concatenate([floor_log(sp.x, -0.5 * sp.x**2 / v - 0.5 * math.log(2.0 * math.pi * v))
                        for sp, v in zip(integ.species, var0, strict=True)])
    for sl, mom in zip(integ.full, integ.species_moments(u), strict=True):
        u[sl] -= math.log(mom[0])
    # first step: rtol collision times of the coldest state met (as for one species),
    # shorter where a far tail starts with a layer
    h0 = o.rtol * collision_time(mdisc, np.min(visited, axis=0))
    u, h0 = layer_start(integ, u, h0) if o.first_step is None else (u, o.first_step)
    integ.start(integ.level(0.0, u), h0)
    outputs, dists = [], []
    params = {"problem": "mixture heated transient", "density": density,
              "masses": list(mixture.masses), "fractions": list(mixture.fractions)}
    for stop in times:
        if stop > 0.0:
            integ.advance_to(float(stop))
        u_out = integ.hist[-1].u
        outputs.append(integ.species_moments(u_out))
        dists.append(tuple(VelocityDistribution.from_values(
            sp.xq, sp.disc.values(us), weights=sp.wq, method="fem", params=params)
            for sp, us in zip(integ.species, integ.split(u_out), strict=True)))
    mom = np.array(outputs)
    st = integ.stats
    info = {**st.as_dict(), "rtol": o.rtol, "order": o.order, "scheme": o.scheme,
            "n_dofs": [int(sp.x.size) for sp in integ.species],
            "vertices": [np.asarray(v) for v in verts], "density": density,
            "cpu_time": time.process_time() - cpu}
    logger.info("FEM mixture transient, rtol=%g: %d steps (%d rejected, %d Newton failures), "
                "%d Jacobians", o.rtol, st.accepted, st.rejected, st.newton_failures,
                st.jacobians)
    return mom[:, :, 1] * masses[None, :], mom[:, :, 2], tuple(dists), info
