"""Galerkin FEM for granular mixtures: the heated steady state and the cooling state.

The coupled homogeneous Boltzmann equations of a mixture (:mod:`kinetic_fem.model.mixture`)
in weak form, species :math:`s` with the Lagrange basis :math:`\\varphi^s_i` of its own
velocity mesh and the unknown :math:`u_s = \\ln P_s`:

.. math::

    0 = -\\int \\varphi^{s\\prime}_i (D_s P_s' + \\xi_s v P_s)
        + n \\sum_r x_r \\iint B(|x - y|) P_s(x) P_r(y)
        \\left[\\varphi^s_i(x') - \\varphi^s_i(x)\\right] dx\\, dy,
    \\qquad x' = x - \\mu_{sr}(1 + \\alpha_{sr})(x - y).

The collision rule is linear, :math:`x' = a x + b y`, as for one species, so each pair
of species is one pair sum of the one-species rule on two meshes
(:func:`kinetic_fem.operators.fem_pair_mixture.cross_collision`); the loss term is taken
half from the pairs where :math:`s` is the outer point and half from those where it is
the inner one, so that a mixture of identical species is the one-species discretisation
(:mod:`kinetic_fem.solvers.fem`) to round-off.

**Heated state.**  Newton's method on all :math:`u_s` together (even states: the
unknowns at :math:`v \\ge 0`; the collision sums visit :math:`x > 0` only), the
equation of the dof at :math:`v = 0` of each species replaced by
:math:`\\int P_s = 1`; dense block Jacobian, equilibrated LU, the update
:math:`\\ln(1+\\delta)` and chord steps of :mod:`kinetic_fem.solvers.fem.newton`.
Meshes: per species, graded in its thermal velocity :math:`\\sigma_s` (from the
Gaussian theory, :mod:`kinetic_fem.solvers.mixture_gaussian`) out to where the
larger of the Gaussian and the WKB tail :math:`e^{-S_s}`,
:math:`S_s' = (\\xi_s v + \\sqrt{\\xi_s^2 v^2 + 4 n D_s B(v)})/(2D_s)`, falls below
1e-33, widened by 15 % while :math:`f_s` at the cut-off exceeds 1e-30; if Newton fails
there, cut once where the last iterate's :math:`f_s\\sigma_s` falls below 1e-33 and
restarted from it (:data:`TRIM_LEVEL`; the cooling state too, when solved directly).

**Cooling state.**  In scaled variables (mixture temperature
:math:`T = \\sum_s x_s m_s\\langle v^2\\rangle_s = 1`) every species is stationary,

.. math::

    0 = -\\zeta n\\, \\partial_v (v P_s) + C_s[P]
    \\quad (\\text{weak: } \\zeta n\\int \\varphi^{s\\prime}_i v P_s + C^s_i),

with one common cooling rate :math:`\\zeta` (:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`):
the unknowns are the :math:`u_s` and :math:`\\zeta`, the equations those above with
:math:`\\int P_s = 1` for each species and :math:`T = 1` (homogeneous kernels
:math:`|g|^\\gamma` only: the scaling state needs :math:`B(\\lambda g) = \\lambda^\\gamma
B(g)`).  The meshes end where the one-species start has fallen 38 decades and, for
inelasticities of at least 0.2, grade the tail as the one-species HCS meshes do
(:func:`mixture_meshes`); Newton's step is measured where :math:`f_s > 10^{-15}`
(:data:`COOLING_MONITOR_LOG_F`; heated: :math:`10^{-30}`, :data:`HEATED_MONITOR_LOG_F`).
With a kernel :math:`|g|^\\gamma`, :math:`\\gamma > 0`, the pair sums of two species
integrate the outer velocity on the outer elements cut at the inner species' bulk
vertices (:func:`merged_rule`, :data:`SPLIT_REACH`: order 8 as one species, where the
element rule of two meshes erred at order 4).

Kernels with a compiled rate (power laws, the saturating kernel; the cooling state power
laws only).  **Restitution laws per pair** (heated state): a pair with a velocity-dependent
law :math:`\\alpha_{sr}(|g|)` collides by :math:`x' = x - \\mu_{sr}(1 + \\alpha_{sr}(|x -
y|))(x - y)` (the pair sums with the law's breakpoints,
:func:`~kinetic_fem.operators.fem_pair_mixture.cross_law_breaks`; self pairs with a law
by the same sums, not the constant-coefficient kernel); the meshes are graded on the
variances of the Gaussian theory with the laws
(:mod:`kinetic_fem.solvers.mixture_gaussian`) and the one-species starts solved at each
law's effective constant (:func:`constant_model`); the meshes' relative speeds must stay
in each law's range.
Identical species with a law are the one-species FEM state with that law to round-off.
The cooling state needs constant coefficients (a law has no scaling state): a law
raises :class:`~kinetic_fem.model.UnsupportedModelError`.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ...distribution import RunInfo, VelocityDistribution
from ...error import richardson_factor
from ...exceptions import ConvergenceError, ResolutionWarning
from ...mixture_error import MixtureError, MixtureErrorRecipe, compare_species
from ...mixture_state import MixtureState
from ...model import PowerLawKernel
from ...model.kernel_base import FAMILY_POWER_LAW
from ...model.mixture import Mixture
from ...model.restitution import CONSTANT
from ...model.validation import UnsupportedModelError, check_positive
from ...operators.fem_discretisation import LAGRANGE_ELEMENTS, FEMDiscretisation
from ...operators.fem_pair_mixture import cross_collision, self_collision
from ...operators.fem_transport import TransportArrays
from ...solve import register_solver
from ..newton import newton
from .cooling_forms import cooling_forms
from .cooling_mesh import BULK_EPS
from .grading import graded_vertices
from .newton import (
    CHORD_LEVEL,
    CHORD_RATE,
    PREDICT_MARGIN,
    STALL_LEVEL,
    EquilibratedLU,
    EvenFold,
    log_update,
    power_of_two_scales,
)

__all__ = ["MixtureDiscretisation", "solve_mixture_heated", "solve_mixture_cooling",
           "mixture_meshes", "check_mixture_model", "check_mixture_vertices",
           "gaussian_variances", "constant_model", "species_spacing", "merged_rule",
           "DEFAULT_ORDER", "DEFAULT_SPACING"]

logger = logging.getLogger(__name__)

DEFAULT_ORDER = 3
"""Lagrange degree of the default meshes."""
DEFAULT_SPACING = 0.25
"""Bulk element size of the default meshes in thermal velocities :math:`\\sigma_s`
(P3; measured on the Maxwell mixture against the exact moments: see
``benchmarks/convergence_fem_mixture.py``)."""
DECADES = 33.0
"""The default cut-off is where the start's :math:`f_s` falls by this many decades."""
CUTOFF_MARGIN = 2.0
"""Thermal velocities added to that cut-off (the gain lifts the tail above
:math:`e^{-S}`)."""
COOLING_MARGIN_DECADES = 5.0
"""In free cooling with a growing kernel (:math:`B(g) \\sim g^p`, p > 0) the margin is
these decades of the start instead of :data:`CUTOFF_MARGIN` thermal velocities.  The
scaled state's tail falls by about :math:`1/\\zeta` e-folds per velocity unit, so that two
thermal velocities were 9 decades at alpha 0.9 (identical species: f 1e-45 at the
edge, where Newton stagnated for 40 iterations before the trimmed restart: 8 s) and 15
for the light species of masses 1:10 at alpha 0.5 (25 s).  With 3 decades the heavy
species of masses 1:5 (x 0.3/0.7, alpha 0.8) fell short, widened, and Newton diverged
on the wider mesh; with 5 it converges at once.  Only from the P3 starts
(:data:`START_EPS`): the near-elastic ones continue their tails from the humps' steep
edge, and 38 decades of them fell 20 decades short (hard rods alpha 0.95, m 1:2, x
0.3/0.7: edges 6e-18, two widenings, then Newton stagnated).  Measured before and after in
``benchmarks/results/fem_mixture_cost.md``."""
SPLIT_REACH = 3.0
""":math:`|v|/\\sigma_s` up to which the cooling state's pair sums of two species cut the
outer elements at the vertices of the inner species' mesh (:func:`merged_rule`): its
uniform bulk (:func:`mixture_meshes` grades beyond 3 thermal velocities), where
:math:`u_h` is curved and its derivative jumps at the vertices; in the near-linear
exponential tails the jumps are small.  Measured (hard rods, P3, the largest T_s, a2_s and
zeta error against spacing 0.1, at spacing 0.25, and CPU s with the start kept): masses
1:3 alpha 0.5, no cut 2.2e-9 (0.130 s), every vertex 9.3e-11 (0.189 s), up to 3 / 6 / 10
thermal velocities 9.2e-11 / 9.3e-11 / 9.3e-11 (0.139 / 0.141 / 0.154 s); m 1:10 alpha 0.5
6.7e-10 -> 2.8e-10, m 1:3 alpha 0.7 5.1e-10 -> 1.0e-10 at every reach.  The heated state
keeps the element rule: its error is the discretisation's with either rule (identical
species on meshes of spacings 0.25 and 0.3: a2 6.5e-10 / 1.5e-9 both ways); so does the
Maxwell kernel (no kink at :math:`g = 0`; cut, its coarse cooling state's temperature
ratio moved from 1.3e-7 to 6.4e-7 off the exact one at spacing 1)."""

TAIL_FLOOR = 1e-30
""":math:`f_s(V)\\sigma_s` at the cut-off must be below this (else the interval widens)."""
MAX_WIDENINGS = 4
WIDEN_MIN = 1.15
WIDEN_MAX = 2.0
WIDEN_DECADES = 2.0
"""A widening of a cooling state's exponential tail (kernel :math:`|g|^\\gamma`,
:math:`\\gamma > 0`) moves a cut-off to where the iterate's tail, continued linearly in
:math:`\\ln f` from the cut-off, is this many decades below :data:`TAIL_FLOOR` (between
:data:`WIDEN_MIN` and :data:`WIDEN_MAX` times the old one; :func:`_widened`).  It was the
fixed factor 1.15 (kept for the heated states and the Maxwell kernel's power-law tails,
where the continued line overshoots: 16 times the cut-off in four widenings, and the
coarse Maxwell state's zeta 8.6e-7 off the exact one instead of 1.2e-7): hard rods alpha
0.9, masses 1:10 widened three times (edges 2e-21, 1.5e-25, 2.4e-30), a Newton solve
each; now once (0.27 -> 0.20 s)."""
START_ORDER = 3
START_SPACING = 0.25
"""The one-species cooling state of the start is solved with P3 at this bulk spacing
(thermal velocities) on an interval reaching past the mixture's cut-off (the default
mesh cost 2.5 - 3 one-species states at this spacing; at 0.5 its far tail is off by
30 decades, f 5e-64 at the cut-off, and the mixture's Newton wandered); the states equal to 1.2e-15
(``benchmarks/results/fem_mixture_cost.md``)."""
START_EPS = 0.1 - 1e-12
"""The starts are solved on those P3 meshes down to this inelasticity: the near-elastic
default one-species meshes begin at ``HUMP_EPS`` = 0.1, which alpha = 0.9 missed by
round-off (1 - 0.9 = 0.09999999999999998) and so took the near-elastic path (cooling:
0.42 s against 0.21 s, zeta equal to 3e-9; heated 0.12 s against 0.04 s).  Below it
the P3 start diverged in the mixture's first Newton step (hard rods alpha 0.95, m 1:2,
x 0.3/0.7, ``inf`` step; the near-elastic start converges)."""
HEATED_START_SPACING = 0.4
"""The same for the heated start (0.04 s against 0.1 - 0.15 s on the default mesh)."""
START_TOL = 1e-2
"""Newton tolerance of the heated one-species start (its state only starts the
mixture's Newton, as the coarse state of the one-species mesh sequencing,
:data:`~kinetic_fem.solvers.fem.heated.SEQUENCE_TOL`): one Jacobian fewer."""
START_CACHE = 64
"""The one-species states of the starts are kept for this many (restitution, thermostat,
kernel) combinations: a sweep over masses or fractions at one restitution coefficient
solves its start once (13-70 % of a binary state's CPU time,
``benchmarks/results/fem_mixture_cost.md``).  They are read, never changed."""
COOLING_MONITOR_LOG_F = math.log(1e-15)
"""The cooling state's Newton step is measured where :math:`f_s > 10^{-15}` (and on
:math:`\\zeta`): with the outflow at the cut-offs the drift-dominated outer decades carry
near-null modes of the Jacobian whose steps stay of order one at residuals of 1e-17
(measured, m 1:3 hard rods), changing nothing where f is above them.  It was
:math:`10^{-25}`; on the meshes graded like the one-species ones (:func:`mixture_meshes`)
the modes reach :math:`10^{-25}` (hard rods m 1:10 alpha 0.5: steps halving from 1.5e-7
to 1.9e-8 at c = 20, f = 1e-25, then flat, 10 Jacobians and the trimmed restart; with
:math:`10^{-15}` 4 Jacobians on the first meshes).  Where f is below the monitor the
tail is the one-species one's accuracy: ln f against spacing 0.125 within 4.5e-5 to
2.5e-4 where f > 1e-15 and 4e-4 to 1.5e-3 where f > 1e-25 (hard rods, alpha 0.5 and 0.7,
m 1:3 and 1:10; one species 2.9e-5 to 1.2e-4 and 3e-4 to 1.1e-3); T_s and zeta moved by
at most 3e-11 (``benchmarks/results/fem_mixture_cost.md``)."""
HEATED_MONITOR_LOG_F = math.log(1e-30)
"""The heated state's Newton step is measured where :math:`f_s > 10^{-30}` (the
:data:`TAIL_FLOOR` of the cut-offs).  It was :math:`10^{-40}` (the one-species monitor,
:data:`~kinetic_fem.solvers.fem.cooling_newton.MONITOR_LOG_F`): the mixture's cut-offs end
below :math:`10^{-40}` (33 decades of the start and 2 thermal velocities), where the
zero-flux layer at the edge, absent from the start, took one more Jacobian (hard rods,
alpha 0.5 / 0.7 / 0.9, m 1:1 / 1:3 / 1:10: 2-3 Jacobians instead of 3-4 in 8 of 9
states).  The states agree with those of :math:`10^{-40}` to 8e-13 in ln f where f >
1e-30, 3.5e-9 where f > 1e-35, and T_1/T_2 to round-off."""
COOLING_CHORD_CONTRACTED = 1e-2
"""The cooling Newton also reuses the Jacobian's factors after a full step below this
that contracts the one before by ``CHORD_RATE**2`` (:func:`~kinetic_fem.solvers.newton.newton`,
``chord_contracted``: the quadratic regime, where a chord step contracts by about the
square of that).  Measured (hard rods, P3, spacing 0.25): masses 1:10 at alpha 0.5 took
steps 0.97, 0.96, 1.4e-3 and a fourth Jacobian for the last; now a chord step (3
Jacobians, 0.232 -> 0.207 s on a first call, zeta equal to 1e-14).  The other eight
binary states of alpha 0.5, 0.7, 0.9 and masses 1:1, 1:3, 1:10 keep their Jacobian
counts and states (a chord level of 3e-3 instead lost the cooling state of alpha 0.9, m
1:3: its first step, 2e-3, has no contraction to show)."""
HEATED_CHORD_LEVEL = 1e-2
"""The heated Newton reuses the Jacobian's factors below this update (chord steps in
:math:`P`, with the row scales of the Jacobian, as the one-species
:func:`~kinetic_fem.solvers.fem.newton.newton_steady`; a chord step that does not
contract by :data:`~kinetic_fem.solvers.fem.newton.CHORD_RATE` refreshes the Jacobian).
Measured against 1e-3 (hard rods, P3, spacing 0.25, masses 1:1, 1:3 and 1:10 at alpha 0.5,
0.7 and 0.9): one Jacobian fewer at alpha 0.7 m 1:1 and alpha 0.5 m 1:3, the same count
elsewhere, T_s equal to 1e-15.  0.1 saved one more at alpha 0.7 m 1:3 but lost two
states at spacing 0.5 (m 1:2 and 1:3, alpha 0.9).  The cooling Newton keeps
:data:`~kinetic_fem.solvers.fem.newton.CHORD_LEVEL` (its line search and speculative
Jacobians, :func:`_solve`)."""
TRIM_LEVEL = 1e-33
"""When the heated state's Newton fails on the default meshes, each mesh is cut where the
last iterate's :math:`f_s\\sigma_s` falls below this and Newton restarts from that iterate
(once; the widening then keeps :math:`f_s\\sigma_s < 10^{-30}` at the cut-offs): a mesh
reaching far below it carries near-null modes at its edge whose full Newton steps grow
while the residual is at round-off (measured: same_power m 1:0.1 alpha 0.9 hard rods,
residual 5.5e-15 with steps 0.3 after 40 iterations at cut-offs of 14 thermal velocities,
:math:`f_s\\sigma_s \\sim 10^{-63}` at the light species' edge).  The cooling state solved
directly (not a step of the continuation) is trimmed the same way (measured: hard rods m
1:10 alpha 0.5, residual 4e-17 with steps 3e-4 at the monitor's edge, c = 21, for 36
iterations on cut-offs of 36 thermal velocities, :math:`f_s\\sigma_s \\sim 10^{-46}` at the
light species' edge)."""
STAGNATION_STEPS = 3
STAGNATION_LEVEL = 1e-2
STAGNATION_RATIO = 0.5
"""Newton stops, not converged, once its last ``STAGNATION_STEPS`` step sizes are each below
``STAGNATION_LEVEL`` (and above the round-off stall level, 1e-8, where the driver's stall
rule judges) and within a factor ``1/STAGNATION_RATIO`` of the one before: where Newton
converges its steps there contract quadratically, and a run of flat steps is the
near-null mode of a mesh reaching too far into the tail (:data:`TRIM_LEVEL`), which the
remaining iterations do not fix (measured: hard rods m 1:1 alpha 0.9, steps 2.8e-6,
2.3e-5, 3.8e-4, then 1.1e-6 for 30 iterations at a residual of 3e-17; m 1:10 alpha 0.5,
2.7e-4 for 36).  A converging Newton may take one flat step (hard rods m 1:2, x 0.3/0.7,
alpha 0.95: 2.7e-6, 2.0e-6, 4.2e-12), hence three; growing steps are left to the line
search.  The trimmed meshes are then tried at once instead of after ``max_iter``
Jacobians.  Only on the default meshes from the first start: on a caller's cut-off or
vertices (and in the continuation) Newton runs on, as before (an explicit cut-off of 30
at m 1:10 alpha 0.5 converges after such steps)."""
WANDER_STEPS = 8
"""Newton also stops, not converged, when none of its first ``WANDER_STEPS`` steps is
below 1 (in ln f where it is measured): it wanders from a start far from the state and
the next start (or the trimmed meshes) is tried at once (measured: the heated hard-rod
mixture m 1:10 at alpha 0.9 from the one-species start, steps 9.3e8, 6.5e4, 1e4, ... for
40 iterations, then 40 more on the trimmed meshes, before the Gaussian start converged
in 6; every converging run of ``benchmarks/results/fem_mixture_cost.md`` took a step
below 1 by its fourth)."""
CONTINUATION_TOL = 1e-6
"""Newton tolerance of the intermediate states of the cooling continuation."""
MIN_CONTINUATION_STEP = 1.0 / 256.0
"""Smallest step of the continuation parameter before it gives up."""


# ---------------------------------------------------------------- the discretisation
@dataclass(frozen=True, eq=False)
class MixtureDiscretisation:
    """One Lagrange discretisation per species and the pair sums between them.

    Parameters
    ----------
    mixture : Mixture
        Constant restitution per pair.
    vertices : sequence of ndarray
        Mesh vertices of each species (physical velocities), symmetric about 0 with a
        vertex at 0.
    density : float
        Total number density :math:`n`.
    order : int
        Lagrange degree (1, 2 or 3), the same for every species.
    intorder : int, optional
        Gauss degree (default ``2 * order + 1``).
    split_reach : tuple of float, optional
        Per species: the pair sums with another species cut their outer elements at
        this species' vertices with :math:`|v|` up to this speed
        (:func:`merged_rule`; default none: the element rule).
    """

    mixture: Mixture
    vertices: tuple[NDArray[np.float64], ...]
    density: float = 1.0
    order: int = DEFAULT_ORDER
    intorder: int | None = None
    split_reach: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if self.order not in LAGRANGE_ELEMENTS:
            raise ValueError(f"order must be one of {sorted(LAGRANGE_ELEMENTS)}, got "
                             f"{self.order!r}")
        if len(self.vertices) != self.mixture.n_species:
            raise ValueError(f"vertices must give one mesh per species "
                             f"({self.mixture.n_species}), got {len(self.vertices)}")

    @cached_property
    def discs(self) -> tuple[FEMDiscretisation, ...]:
        """The one-species discretisation of each mesh (basis, points, symmetry)."""
        return tuple(FEMDiscretisation(1.0, np.asarray(v, dtype=float), self.order,
                                       self.intorder or 2 * self.order + 1)
                     for v in self.vertices)

    @cached_property
    def folds(self) -> tuple[EvenFold, ...]:
        """The even reduction of each species."""
        return tuple(EvenFold(d.symmetry) for d in self.discs)

    @cached_property
    def sizes(self) -> tuple[int, ...]:
        """Even unknowns per species."""
        return tuple(int(f.counts.size) for f in self.folds)

    @cached_property
    def offsets(self) -> NDArray[np.int64]:
        """Start of each species' block in the stacked even unknowns."""
        return np.concatenate([[0], np.cumsum(self.sizes)]).astype(np.int64)

    @cached_property
    def zero_rows(self) -> tuple[int, ...]:
        """The even row of the dof at :math:`v = 0` of each species."""
        rows = []
        for disc, fold in zip(self.discs, self.folds, strict=True):
            red = np.zeros(fold.counts.size)
            red[fold.cols] = np.abs(disc.dof_locations)
            rows.append(int(np.argmin(red)))
        return tuple(rows)

    @cached_property
    def cross_points(self) -> dict[tuple[int, int], tuple[NDArray, NDArray, NDArray]]:
        """Outer points, weights and elements of the pair sums of species ``o`` (outer)
        with another species ``i``: the one-species rule on every piece of ``o``'s
        elements cut at the vertices of ``i``'s mesh within :attr:`split_reach` of 0
        (:func:`merged_rule`)."""
        ref_x, ref_w = self.discs[0].basis.quadrature
        k = self.mixture.n_species
        cut = [v[np.abs(v) <= reach] for v, reach in
               zip(self.vertices, self.split_reach or (0.0,) * k, strict=True)]
        return {(o, i): merged_rule(self.vertices[o], cut[i], ref_x[0], ref_w)
                for o in range(k) for i in range(k) if o != i}

    @cached_property
    def rules(self) -> NDArray[np.float64]:
        """``(a, b)`` of :math:`x' = a x + b y` for every pair, shape (k, k, 2) (NaN for a
        pair with a velocity-dependent law: :attr:`law_arguments`)."""
        k = self.mixture.n_species
        out = np.full((k, k, 2), np.nan)
        for s in range(k):
            for r in range(k):
                alpha = self.mixture.laws[s][r].constant
                if alpha is not None:
                    b = self.mixture.reduced_mass(s, r) * (1.0 + alpha)
                    out[s, r] = (1.0 - b, b)
        return out

    @cached_property
    def law_arguments(self) -> tuple[tuple[tuple[int, float, float, float, float] | None,
                                           ...], ...]:
        """``(code, p0, p1, mu, b_lo)`` of the compiled pair rule for every pair with a
        velocity-dependent law (None for a constant coefficient); checks that the
        relative speeds of the meshes, up to the sum of the two cut-offs, stay in the
        law's range."""
        k = self.mixture.n_species
        out = []
        for s in range(k):
            row: list[tuple[int, float, float, float, float] | None] = []
            for r in range(k):
                law = self.mixture.laws[s][r]
                if law.constant is not None:
                    row.append(None)
                    continue
                law.check_speed(float(self.vertices[s][-1] + self.vertices[r][-1]),
                                f"the FEM meshes of species {s} and {r} (cut-offs "
                                f"{float(self.vertices[s][-1]):.4g} and "
                                f"{float(self.vertices[r][-1]):.4g})")
                p0, p1 = law.parameters
                row.append((int(law.code), float(p0), float(p1),
                            self.mixture.reduced_mass(s, r), 0.5 * (1.0 + law.min_alpha)))
            out.append(tuple(row))
        return tuple(out)

    @cached_property
    def _kernel_argument(self) -> float | tuple[int, float]:
        family, parameter = self.mixture.collision_kernel.numeric
        return float(parameter) if family == FAMILY_POWER_LAW else (family, float(parameter))

    def split(self, x: NDArray[np.float64]) -> list[NDArray[np.float64]]:
        """The full coefficients :math:`u_s` of the stacked even unknowns ``x``."""
        off = self.offsets
        return [f.expand(x[off[s]:off[s + 1]]) for s, f in enumerate(self.folds)]

    def stack(self, us: Sequence[NDArray[np.float64]]) -> NDArray[np.float64]:
        """The stacked even unknowns of full (even) coefficients."""
        return np.concatenate([f.vector(u) / f.counts for f, u in
                               zip(self.folds, us, strict=True)])

    def collision(self, us: Sequence[NDArray[np.float64]], *, jacobian: bool = False
                  ) -> tuple[list[NDArray], list[list[Any]], NDArray]:
        """The even-reduced collision residuals, Jacobian blocks and loss moments.

        Parameters
        ----------
        us : sequence of ndarray
            Even :math:`u_s` on each mesh.
        jacobian : bool
            Also the reduced blocks :math:`\\partial R^s/\\partial u_r`.

        Returns
        -------
        res : list of ndarray
            Reduced residual of each species (full sums: the visited half twice).
        blocks : list of list of ndarray or None
            ``blocks[s][r]``, reduced (None without ``jacobian``).
        loss : ndarray, shape (k, k)
            :math:`\\sum c\\, g^2` of each ordered pair (the full sums).
        """
        k = self.mixture.n_species
        n = self.density
        x = self.mixture.fractions
        res_full = [np.zeros(d.basis.N) for d in self.discs]
        jac_full: list[list[Any]] = [[None] * k for _ in range(k)]
        loss = np.zeros((k, k))
        ref_x, ref_w = self.discs[0].basis.quadrature
        ref_x = np.ascontiguousarray(ref_x[0])
        laws = self.law_arguments
        for o in range(k):
            verts_o, dofs_o = self.discs[o].mesh_arrays
            for i in range(k):
                xq, wq, eq = self.discs[o].points if o == i else self.cross_points[o, i]
                verts_i, dofs_i = self.discs[i].mesh_arrays
                a, b = self.rules[o, i]
                law = laws[o][i]
                alpha = self.mixture.laws[o][i].constant
                if alpha is not None and o == i and self.order >= 2 and alpha < 1.0:
                    # the one-species bracket at density n x_o, by its P2/P3 kernel
                    r_s, j_s, lo = self_collision(
                        verts_o, dofs_o, np.ascontiguousarray(us[o]), xq, wq, eq, ref_x,
                        ref_w, float(alpha), n * x[o], self._kernel_argument, jacobian)
                    res_full[o] += r_s
                    loss[o, o] = 2.0 * lo
                    if jacobian:
                        jac_full[o][o] = j_s if jac_full[o][o] is None \
                            else jac_full[o][o] + j_s
                    continue
                r_o, r_i, jxo, joi, jxi, jii, lo = cross_collision(
                    verts_o, dofs_o, np.ascontiguousarray(us[o]), xq, wq, eq, verts_i, dofs_i,
                    np.ascontiguousarray(us[i]), self.order, ref_x, ref_w, float(a), float(b),
                    self._kernel_argument, n * x[i], 0.5 * n * x[i], 0.5 * n * x[o],
                    jacobian, True, *(law or _CONSTANT_RULE),
                    0.5 if law else float(self.rules[i, o, 1]))
                res_full[o] += r_o
                res_full[i] += r_i
                loss[o, i] = 2.0 * lo
                if jacobian:
                    for (p, q), block in (((o, o), jxo.T), ((o, i), joi), ((i, o), jxi.T),
                                          ((i, i), jii)):
                        jac_full[p][q] = block if jac_full[p][q] is None \
                            else jac_full[p][q] + block
        # the visited half (x > 0) of even sums: S^T (r + r[mirror]) = 2 S^T r exactly
        res = [2.0 * f.vector(r) for f, r in zip(self.folds, res_full, strict=True)]
        if not jacobian:
            return res, [[None] * k for _ in range(k)], loss
        blocks = [[2.0 * _fold_block(jac_full[p][q], self.folds[p], self.folds[q])
                   for q in range(k)] for p in range(k)]
        return res, blocks, loss

    def distributions(self, us: Sequence[NDArray[np.float64]], **kwargs: Any
                      ) -> tuple[VelocityDistribution, ...]:
        """One :class:`VelocityDistribution` per species (quadrature points and weights)."""
        return tuple(d.distribution(u, **kwargs) for d, u in zip(self.discs, us, strict=True))


def merged_rule(outer: NDArray, inner: NDArray, ref_x: NDArray, ref_w: NDArray
                ) -> tuple[NDArray, NDArray, NDArray]:
    """The outer quadrature of a pair sum on two meshes: the reference rule on every
    piece of the ``outer`` elements cut at the ``inner`` vertices.

    For a fixed outer point :math:`x` the inner integral runs over :math:`y` with the
    kernel's kink at :math:`y = x`; as :math:`x` crosses an inner vertex, that kink crosses
    the kink of :math:`P_i(y) = e^{u_h}` there, and the inner integral, a function of
    :math:`x`, has a jump in a higher derivative inside an outer element.  A rule on the
    whole element then errs by :math:`O(h^4)` (P3) with a constant set by where the two
    meshes' vertices fall: measured, identical species (hard rods, alpha 0.5, free
    cooling) on meshes of spacings 0.25 and 0.3, a2 errors 4.2e-9 / 1.4e-9 (order 4 under
    refinement) against 1.2e-10 on equal meshes (order 8); on the cut pieces 1.6e-10 /
    4.2e-10 (order 7-8).  With ``inner`` equal to ``outer`` it is the element rule.

    Parameters
    ----------
    outer, inner : ndarray
        Increasing vertices: the outer species' mesh and the cuts (inner vertices).
    ref_x, ref_w : ndarray
        Reference rule on [0, 1].

    Returns
    -------
    x, w : ndarray
        Points and weights.
    e : ndarray of int
        The outer element of each point.
    """
    size = np.diff(outer)
    e_in = np.clip(np.searchsorted(outer, inner, side="right") - 1, 0, size.size - 1)
    offset = inner - outer[e_in]
    # inner vertices strictly inside an outer element (not within round-off of its ends)
    inside = (offset > 1e-12 * size[e_in]) & (size[e_in] - offset > 1e-12 * size[e_in])
    cuts = np.union1d(outer, inner[inside])
    left, width = cuts[:-1], np.diff(cuts)
    elements = np.searchsorted(outer, left + 0.5 * width, side="right") - 1
    x = (left[:, None] + width[:, None] * ref_x[None, :]).ravel()
    w = (width[:, None] * ref_w[None, :]).ravel()
    return x, w, np.repeat(elements, ref_x.size).astype(np.int64)


_CONSTANT_RULE = (CONSTANT, 0.0, 0.0, 0.5, 0.5)
"""The law arguments of :func:`cross_collision` for a constant coefficient (unused)."""


def _fold_block(jac: NDArray, rows: EvenFold, cols: EvenFold) -> NDArray:
    """:math:`S_r^T J S_c` of a block between two species."""
    half = jac[:, cols.first]
    half[:, cols.pairs] += jac[:, cols.second]
    out = half[rows.first]
    out[rows.pairs] += half[rows.second]
    return out


# ---------------------------------------------------------------- checks and meshes
def check_mixture_model(mixture: object, what: str, *, cooling: bool,
                        scaled: bool = True) -> Mixture:
    """``mixture`` if the FEM solvers can take it (forced species exactly when not
    ``cooling``; the scaled cooling state: constant restitution per pair and a power-law
    kernel).

    Parameters
    ----------
    mixture : object
        The argument to check.
    what : str
        The caller's name, for the error.
    cooling : bool
        Free cooling (True) or heated.
    scaled : bool
        With ``cooling``: the scaled (homogeneous) cooling state, which needs constant
        coefficients and a homogeneous kernel; False: free cooling in physical time (any
        law, any kernel).

    Returns
    -------
    Mixture
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    scaled = cooling and scaled
    for s, row in enumerate(mixture.laws):
        for r, law in enumerate(row):
            if scaled and law.constant is None:
                raise UnsupportedModelError(
                    f"the FEM cooling state of a mixture needs a constant restitution "
                    f"coefficient for every pair (a velocity-dependent law has no scaling "
                    f"state), got {law!r} for the pair ({s}, {r}); use the heated state, or "
                    "evolve_cooling(mixture, method='fem') for free cooling in physical "
                    "time")
    kernel = mixture.collision_kernel
    if scaled and not isinstance(kernel, PowerLawKernel):
        raise UnsupportedModelError(
            f"the FEM cooling state of a mixture needs a homogeneous kernel |g|^gamma (the "
            f"scaling state exists only then), got {kernel!r}; "
            "evolve_cooling(mixture, method='fem') follows free cooling in physical time")
    if mixture.heated == cooling:
        raise ValueError(f"{what} needs " + (
            "a mixture without forcing (free cooling); this one is forced" if cooling else
            "forced species (Mixture.white_noise or thermostats=...); this one cools"))
    return mixture


def _tail_action(v: NDArray, kernel: Any, density: float, diffusion: float,
                 friction: float) -> NDArray:
    """:math:`S(v)` with :math:`S' = (\\xi v + \\sqrt{\\xi^2v^2 + 4nDB(v)})/(2D)`
    (trapezoid on ``v``, increasing from 0)."""
    rate = (friction * v + np.sqrt((friction * v) ** 2
                                   + 4.0 * density * diffusion * kernel.rate(v))) \
        / (2.0 * diffusion)
    return np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(v))])


def _start_profiles(mixture: Mixture, density: float, variances: NDArray, cooling: bool,
                    one_species: bool = True) -> list[tuple[NDArray, NDArray]]:
    """Per species ``(v, ln f)`` of the start on a fine grid ``v >= 0``.

    The one-species state (FEM; heated: with the species' thermostat, free cooling: the
    scaled state) at the species' own restitution coefficient, stretched to the
    variance ``variances[s]`` and continued linearly in :math:`|v|` beyond its mesh (a
    Gaussian start lies many decades below the tails of hard rods or of the scaled
    state, and Newton's first steps there wander: measured, hard rods m 1:1 alpha 0.7
    at spacing 0.5 did not converge in 40 steps from the Gaussian with the WKB tail).
    """
    out = []
    alpha = mixture.constant_alpha()
    # the one-species state depends on the species' alpha and thermostat, not on its
    # mass: solved once for each distinct pair (identical species, the same_diffusion
    # convention at one alpha: one solve for the mixture)
    solved: dict[tuple[float, ...], Any] = {}
    for s in range(mixture.n_species):
        sigma = math.sqrt(variances[s])
        v = np.linspace(0.0, 60.0 * sigma, 30001)
        if not one_species:  # heated: the Gaussian lifted to the WKB tail
            therm = mixture.thermostats[s]  # type: ignore[index]
            log_f = np.maximum(-0.5 * v**2 / variances[s], -_tail_action(
                v, mixture.collision_kernel, density, therm.diffusion, therm.friction))
            log_f -= math.log(2.0 * np.trapezoid(np.exp(log_f), v))
            out.append((v, log_f))
            continue
        if cooling:
            key: tuple[float, ...] = (float(alpha[s, s]),)
            if key not in solved:
                solved[key] = _one_species_cooling(key[0], mixture.collision_kernel)
        else:
            therm = mixture.thermostats[s]  # type: ignore[index]
            key = (float(alpha[s, s]), float(therm.diffusion), float(therm.friction))
            if key not in solved:
                solved[key] = _one_species_heated(key[0], density, key[1], key[2],
                                                  mixture.collision_kernel)
        one = solved[key]
        keep = one.v > 0
        c = one.v[keep] / math.sqrt(one.moment(2, central=False))
        log_one = np.log(one.values[keep] * math.sqrt(one.moment(2, central=False)))
        slope = (log_one[-1] - log_one[-2]) / (c[-1] - c[-2])
        cv = v / sigma
        log_f = np.interp(cv, c, log_one) - math.log(sigma)
        far = cv > c[-1]
        log_f[far] = log_one[-1] - math.log(sigma) + slope * (cv[far] - c[-1])
        log_f -= math.log(2.0 * np.trapezoid(np.exp(log_f), v))
        out.append((v, log_f))
    return out


@lru_cache(maxsize=START_CACHE)
def _one_species_heated(alpha: float, density: float, diffusion: float, friction: float,
                        kernel: Any) -> VelocityDistribution:
    """The one-species heated state of the start: as :func:`_one_species_cooling`, out to
    :data:`CUTOFF_MARGIN` + 1 thermal velocities beyond the default cut-off
    (:func:`~kinetic_fem.solvers.fem.defaults.model_cutoff`) for
    :math:`1 - \\alpha \\ge` :data:`START_EPS`; else, or if that fails, the default state
    (measured at alpha 0.9: 0.04 s against 0.12 s, <v^2> equal to 6e-9)."""
    from ...model import HeatedProblem
    from ...solve import solve_heated
    from .defaults import model_cutoff, scaled_model

    options = {"density": density, "diffusion": diffusion, "friction": friction,
               "kernel": kernel}
    if 1.0 - alpha >= START_EPS:
        problem = HeatedProblem.from_parameters(alpha, **options)
        try:
            with warnings.catch_warnings():  # a start, coarser than a result should be
                warnings.simplefilter("ignore", ResolutionWarning)
                return solve_heated(alpha, order=START_ORDER, spacing=HEATED_START_SPACING,
                                    cutoff=model_cutoff(scaled_model(problem))
                                    + CUTOFF_MARGIN, tol=START_TOL, **options)
        except ConvergenceError as err:  # pragma: no cover - fallback
            logger.info("one-species start at spacing %g failed (%s); the default mesh",
                        START_SPACING, err)
    return solve_heated(alpha, **options)


@lru_cache(maxsize=START_CACHE)
def _one_species_cooling(alpha: float, kernel: Any) -> VelocityDistribution:
    """The one-species cooling state of the start: P3 at :data:`START_SPACING` out to
    :data:`CUTOFF_MARGIN` + 1 thermal velocities beyond the default cut-off (the start's
    33 decades and the margin of the mixture's cut-off inside the solved interval, no
    extrapolation), for inelasticities down to :data:`START_EPS` (and a kernel other than
    the Maxwell one, whose default mesh carries the tail closure); else, or if that
    solve fails, the default one-species state."""
    from ...model import CoolingProblem
    from ...solve import solve_cooling
    from .cooling_mesh import hcs_cutoff

    problem = CoolingProblem.from_parameters(alpha, kernel=kernel)
    if problem.gas.gamma > 0.0 and problem.gas.epsilon >= START_EPS:
        try:
            return solve_cooling(alpha, kernel=kernel, order=START_ORDER, spacing=START_SPACING,
                                 cutoff=hcs_cutoff(problem) + CUTOFF_MARGIN + 1.0)
        except ConvergenceError as err:  # pragma: no cover - fallback
            logger.info("one-species start at spacing %g failed (%s); the default mesh",
                        START_SPACING, err)
    return solve_cooling(alpha, kernel=kernel)


def mixture_meshes(mixture: Mixture, variances: Sequence[float] | NDArray,
                   cutoffs: Sequence[float],
                   *, spacing: float = DEFAULT_SPACING, cooling: bool = False
                   ) -> tuple[NDArray[np.float64], ...]:
    """Symmetric meshes, graded in each species' thermal velocity.

    The element size grows as :math:`\\max(1, c/3)^\\kappa` with :math:`\\kappa = (3 - p)/3`
    for a tail :math:`\\ln f \\sim -c^p` (the P2 error, :math:`h^3` times the third
    derivative of :math:`\\ln f`, even in the tail): :math:`p = 1 + \\gamma/2` for the heated
    state of a kernel growing as :math:`g^\\gamma`.  The cooling state's tail
    :math:`p = \\gamma` (the one-species rule,
    :func:`~kinetic_fem.solvers.fem.cooling_mesh.hcs_vertices`) is used down to the
    inelasticity :data:`~kinetic_fem.solvers.fem.cooling_mesh.BULK_EPS` of every species.
    The heated state's bulk spacing of each species is ``spacing`` times
    :func:`species_spacing` (finer for the wider species).

    Parameters
    ----------
    mixture : Mixture
        The model (its kernel sets the tail grading).
    variances : sequence of float or ndarray
        :math:`\\sigma_s^2 = \\langle v^2\\rangle_s` estimates.
    cutoffs : sequence of float
        Half-widths :math:`V_s` (physical velocities).
    spacing : float
        Bulk element size in thermal velocities.
    cooling : bool
        The meshes of the cooling state.

    Returns
    -------
    tuple of ndarray
    """
    check_positive("spacing", spacing)
    growth = mixture.collision_kernel.tail_growth[1]
    steep = (cooling and growth > 0.0
             and float(np.min(1.0 - np.diag(mixture.constant_alpha()))) >= BULK_EPS)
    grading = (3.0 - (growth if steep else 1.0 + 0.5 * growth)) / 3.0
    sigmas = np.sqrt(np.asarray(variances, dtype=float))
    out = []
    for sigma, cut in zip(sigmas, cutoffs, strict=True):
        h = spacing if cooling else spacing * species_spacing(sigma, sigmas)
        out.append(sigma * graded_vertices(cut / sigma, h, grading=max(grading, 0.0)))
    return tuple(out)


WIDE_REFINEMENT = 0.8
"""Exponent of :func:`species_spacing`."""


def species_spacing(sigma: float, sigmas: NDArray[np.float64]) -> float:
    """The bulk spacing of a species of the heated state, in units of the mixture's
    ``spacing``: :math:`(\\sigma_{min}/\\sigma)^{0.8}`, finer for the wider species.

    At one spacing in thermal velocities the error of a heated state of unequal
    thermal velocities is set by the wide (light) species: hard rods alpha 0.9, masses
    1:10 (sigma ratio 0.44), spacing 0.25, P3: T_s errors 1.2e-9 against 2e-10 for one
    species; refining the light mesh 0.7 times lowered them to 1.5e-10, refining the
    heavy one changed nothing.  Measured cost at equal accuracy (the largest error of
    T_s, relative, and a2_s, absolute, against spacing 0.08; one species interpolated
    on its spacings 0.5 ... 0.15), alpha 0.9, m 1:10 / 1:3: equal spacings 5.1 / 2.7
    times one species, exponent 0.5: 4.3 / 2.6, 0.8: 3.8 / 2.8, 1.0: 4.6 / 3.1
    (coarsening the narrow species as well, (sigma_max/sigma)^0.3, gave 3.6 / 2.8 but
    lost the heated state of masses 1:2, alpha 0.8 at spacing 0.5).  Equal thermal
    velocities (identical species) keep the one spacing.

    Parameters
    ----------
    sigma : float
        The species' thermal velocity.
    sigmas : ndarray
        Every species' thermal velocity.

    Returns
    -------
    float
    """
    return float((sigmas.min() / sigma) ** WIDE_REFINEMENT)


def _gaussian_zeta(mixture: Mixture, density: float) -> float:
    """The cooling rate of the Gaussian theory (0.25 if it has no solution)."""
    from .. import mixture_gaussian

    try:
        return float(mixture_gaussian.cooling_state(mixture, density=density).zeta or 0.25)
    except (ConvergenceError, ValueError):  # pragma: no cover - fallback
        return 0.25


def gaussian_variances(mixture: Mixture, density: float, cooling: bool) -> NDArray[np.float64]:
    """:math:`\\langle v^2\\rangle_s` of the Gaussian theory (the start and the meshes).

    Parameters
    ----------
    mixture : Mixture
    density : float
    cooling : bool
        The homogeneous cooling state (True) or the heated steady state.

    Returns
    -------
    ndarray, shape (k,)
        Equal temperatures (``1/m_s``) if the Gaussian theory has no solution.
    """
    from .. import mixture_gaussian

    try:
        state = mixture_gaussian.cooling_state(mixture, density=density) if cooling \
            else mixture_gaussian.steady_state(mixture, density=density)
        var = np.asarray(state.moments[:, 2], dtype=float)
        if np.all(np.isfinite(var)) and np.all(var > 0):
            return var
    except (ConvergenceError, ValueError) as err:  # pragma: no cover - fallback
        logger.info("Gaussian estimate failed (%s); equal temperatures", err)
    return 1.0 / np.asarray(mixture.masses, dtype=float)


def constant_model(mixture: Mixture, density: float,
                   variances: NDArray[np.float64] | None = None) -> Mixture:
    """The mixture with each velocity-dependent law replaced by its effective constant
    (the one-species starts of the heated state; ``mixture`` itself if every pair's
    coefficient is constant).

    For the pair :math:`(s, r)`, :math:`1 - \\alpha_{sr}^2` is the average of
    :math:`1 - \\alpha(g)^2` weighted by the energy loss :math:`B(g)g^2` over the
    Gaussian relative velocity of variance :math:`\\sigma_s^2 + \\sigma_r^2` (as the
    one-species :attr:`~kinetic_fem.solvers.fem.defaults.ScaledModel.effective_epsilon`),
    the variances those of the Gaussian theory with the laws (:func:`gaussian_variances`).

    Parameters
    ----------
    mixture : Mixture
        A heated mixture.
    density : float
        Total number density.
    variances : ndarray, shape (k,), optional
        :math:`\\sigma_s^2` (default: :func:`gaussian_variances`).

    Returns
    -------
    Mixture
    """
    laws = mixture.laws
    if all(law.constant is not None for row in laws for law in row):
        return mixture
    if variances is None:
        variances = gaussian_variances(mixture, density, False)
    s_h, w_h = np.polynomial.hermite.hermgauss(120)
    table: list[list[float]] = []
    for a, row in enumerate(laws):
        table.append([])
        for b, law in enumerate(row):
            if law.constant is not None:
                table[-1].append(law.constant)
                continue
            g = math.sqrt(2.0 * (variances[a] + variances[b])) * np.abs(s_h)
            weight = w_h * mixture.collision_kernel.weighted_rate(g, 2.0)
            alpha_g = law(np.minimum(g, law.max_speed))
            mean = float(np.sum(weight * (1.0 - alpha_g**2)) / np.sum(weight))
            table[-1].append(math.sqrt(max(1.0 - mean, 0.0)))
    return replace(mixture, alpha=table)


# ---------------------------------------------------------------- Newton
@dataclass
class _System:
    """The stacked residual and Jacobian of the heated or cooling mixture."""

    mdisc: MixtureDiscretisation
    cooling: bool
    forms: list[TransportArrays] = field(default_factory=list)

    def __post_init__(self) -> None:
        mix = self.mdisc.mixture
        for s, disc in enumerate(self.mdisc.discs):
            if self.cooling:  # the mass gradient only (the drift: _drift)
                self.forms.append(TransportArrays(disc.basis, 0.0))
            else:
                therm = mix.thermostats[s]  # type: ignore[index]
                self.forms.append(TransportArrays(disc.basis, therm.friction / therm.diffusion))

    @property
    def size(self) -> int:
        return int(self.mdisc.offsets[-1]) + int(self.cooling)

    def __call__(self, x: NDArray, jacobian: bool) -> tuple[NDArray, NDArray | None]:
        md = self.mdisc
        mix = md.mixture
        k = mix.n_species
        off = md.offsets
        us = md.split(x[:off[-1]])
        coll, blocks, _ = md.collision(us, jacobian=jacobian)
        r = np.empty(self.size)
        jac = np.zeros((self.size, self.size)) if jacobian else None
        zeta = float(x[-1]) if self.cooling else 0.0
        energy = 0.0
        grad_energy = []
        for s in range(k):
            fold = md.folds[s]
            sl = slice(off[s], off[s + 1])
            heat, hjac, grad_mass = self.forms[s].transport(us[s], jacobian=jacobian)
            if self.cooling:
                # the scaled dynamics' anti-friction: + zeta n int phi' v P
                drift, djac, grad_temp = self._drift(s, us[s], jacobian)
                rs = coll[s] + md.density * zeta * fold.vector(drift)
            else:
                diffusion = mix.thermostats[s].diffusion  # type: ignore[index]
                rs = coll[s] + diffusion * fold.vector(heat)
            row0 = int(off[s]) + md.zero_rows[s]
            r[sl] = rs
            r[row0] = grad_mass.sum() - 1.0
            if self.cooling:
                weight = mix.fractions[s] * mix.masses[s]
                energy += weight * grad_temp.sum()
                grad_energy.append(weight * grad_temp)
            if jacobian:
                assert jac is not None
                for q in range(k):
                    jac[sl, off[q]:off[q + 1]] = blocks[s][q]
                if self.cooling:
                    assert djac is not None
                    jac[sl, sl] += md.density * zeta * fold.matrix(djac)
                    jac[sl, -1] = md.density * fold.vector(drift)
                else:
                    assert hjac is not None
                    jac[sl, sl] += diffusion * fold.matrix(hjac)
                jac[row0, :] = 0.0
                jac[row0, sl] = fold.vector(grad_mass)
        if self.cooling:
            r[-1] = energy - 1.0
            if jacobian:
                assert jac is not None
                jac[-1, :] = 0.0
                for s in range(k):
                    jac[-1, off[s]:off[s + 1]] = md.folds[s].vector(grad_energy[s])
        return r, jac

    def _drift(self, s: int, u: NDArray, jacobian: bool
               ) -> tuple[NDArray, NDArray | None, NDArray]:
        """:math:`\\int\\varphi_i' vP - [\\varphi_i vP]_{-V}^{V}` (the outflow at the
        cut-offs, as for one species, :mod:`kinetic_fem.solvers.fem.cooling_newton`), its
        dense Jacobian and :math:`\\int \\varphi_i v^2 P`."""
        drift, _, grad_temp, djac = cooling_forms(self.forms[s], u, jacobian)
        x = self.mdisc.discs[s].dof_locations
        edges = np.array([np.argmin(x), np.argmax(x)])
        outflow = np.abs(x[edges]) * np.exp(u[edges])
        drift[edges] -= outflow
        if djac is not None:
            djac[edges, edges] -= outflow
        return drift, djac, grad_temp


def _solve(system: _System, x0: NDArray, *, tol: float, max_iter: int,
           give_up: bool = False) -> tuple[NDArray, RunInfo]:
    start = time.perf_counter()
    n_jac = 0
    # the cooling Newton's line search evaluates the residual at the full step, and the
    # driver then asks for the Jacobian there (the residual again): for a step too large
    # for a chord step the trial is evaluated with its Jacobian, kept for that request
    speculate = False
    kept: tuple[NDArray, NDArray, NDArray | None] | None = None

    # heated: chord steps in P (the points of the last Jacobian and of the last residual)
    # and the Jacobian's row scales for their decrease test, as for one species
    # (kinetic_fem.solvers.fem.newton.newton_steady)
    at: dict[str, NDArray] = {}
    scales = [np.ones(system.size)]

    def fun(x: NDArray, jacobian: bool) -> tuple[NDArray, NDArray | None]:
        nonlocal n_jac, speculate, kept
        at["r"] = x
        if jacobian:
            at["J"] = x
        if jacobian and kept is not None and np.array_equal(kept[0], x):
            r, jac = kept[1], kept[2]
            kept = None
            return r, jac
        ahead = speculate and not jacobian
        speculate = False
        kept = None
        n_jac += int(jacobian or ahead)
        r, jac = system(x, jacobian or ahead)
        if jac is not None and not system.cooling:
            scales[0] = power_of_two_scales(jac)
        if ahead:
            kept = (x.copy(), r, jac)
            return r, None
        return r, jac

    n_u = int(system.mdisc.offsets[-1])

    def update(x: NDArray, d: NDArray) -> NDArray:
        out = x.copy()
        out[:n_u] = x[:n_u] + log_update(d[:n_u])
        if system.cooling:
            out[n_u:] = x[n_u:] + d[n_u:]
        return out

    def factorize(jac: NDArray):
        lu = EquilibratedLU(jac)
        if system.cooling:
            return lu.solve
        base = at["J"]

        def solve(rhs: NDArray) -> NDArray:
            # a chord step: the factorised step on P relative to the Jacobian's point,
            # times P_J / P of this iterate (exact for the equations linear in P: the tail)
            step = lu.solve(rhs)
            here = at["r"]
            if here is base:
                return step
            out = step.copy()
            out[:n_u] *= np.exp(base[:n_u] - here[:n_u])
            return out

        return solve

    monitor = COOLING_MONITOR_LOG_F if system.cooling else HEATED_MONITOR_LOG_F
    sizes: list[float] = []
    last = [x0]

    def step_norm(d: NDArray, x: NDArray) -> float:
        # where f > 1e-40 (and zeta, relative): the far edge of the cooling state carries
        # a near-null mode of the Jacobian whose step stays large at a round-off residual
        # (as for one species, kinetic_fem.solvers.fem.cooling_newton.MONITOR_LOG_F)
        nonlocal speculate
        seen = x[:n_u] > monitor
        size = float(np.max(np.abs(d[:n_u][seen]))) if np.any(seen) else math.inf
        if system.cooling:
            size = max(size, abs(float(d[-1])) / max(abs(float(x[-1])), 1e-300))
        # the next call is the trial of this step (a Newton or a chord step); a step
        # that will be followed by chord steps (newton's chord rules) needs no Jacobian
        contracted = (size < COOLING_CHORD_CONTRACTED and bool(sizes)
                      and size <= CHORD_RATE * CHORD_RATE * sizes[-1])
        speculate = system.cooling and CHORD_LEVEL <= size < math.inf and not contracted
        if sizes and x is last[0]:  # a failed chord step, then Newton's from the same x
            sizes[-1] = size
        else:
            sizes.append(size)
        last[0] = x
        if give_up and _stagnated(sizes):
            raise _Stagnation
        return size

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            out = newton(fun, x0, tol=tol, max_iter=max_iter, criterion="step",
                         update=update, step_norm=step_norm, line_search=system.cooling,
                         stall_level=STALL_LEVEL, factorize=factorize,
                         chord=CHORD_LEVEL if system.cooling else HEATED_CHORD_LEVEL,
                         chord_contracted=COOLING_CHORD_CONTRACTED if system.cooling else 0.0,
                         chord_rate=CHORD_RATE, predict=PREDICT_MARGIN, predict_newton=True,
                         name="FEM mixture Newton",
                         row_scale=None if system.cooling else (lambda x: scales[0]))
    except _Stagnation:
        text = (f"FEM mixture Newton stopped: no step below 1 in {WANDER_STEPS}"
                if min(sizes) > 1.0 else
                f"FEM mixture Newton stagnated: the last {STAGNATION_STEPS} steps below "
                f"{STAGNATION_LEVEL:g} did not contract")
        converged, iterations, x_out = False, len(sizes), last[0]
    else:
        text = "" if out.converged else out.message
        converged, iterations, x_out = out.converged, out.iterations, out.x
        sizes = list(out.history)
    history = f"Newton max|du| history {['%.1e' % h for h in sizes]}; {n_jac} Jacobians"
    text = f"{text}; {history}" if text else history
    info = RunInfo(converged=converged, iterations=iterations,
                   residual=sizes[-1] if sizes else math.inf,
                   wall_time=time.perf_counter() - start, message=text)
    return x_out, info


class _Stagnation(Exception):
    """Raised by the step measure of :func:`_solve` when Newton stagnates."""


def _stagnated(sizes: Sequence[float]) -> bool:
    """The last :data:`STAGNATION_STEPS` steps, all below :data:`STAGNATION_LEVEL`, each
    at least :data:`STAGNATION_RATIO` times the one before (no Newton contraction), or
    no step below 1 in the first :data:`WANDER_STEPS`."""
    if len(sizes) >= WANDER_STEPS and min(sizes) > 1.0:
        return True
    if len(sizes) <= STAGNATION_STEPS:
        return False
    tail = sizes[-STAGNATION_STEPS - 1:]
    return all(STALL_LEVEL <= b < STAGNATION_LEVEL
               and STAGNATION_RATIO * a <= b <= a / STAGNATION_RATIO
               for a, b in zip(tail[:-1], tail[1:], strict=False))


def check_mixture_vertices(vertices: object, k: int) -> tuple[NDArray[np.float64], ...]:
    """One sorted mesh per species from one symmetric mesh or ``k`` of them.

    Parameters
    ----------
    vertices : object
        An array (the same mesh for every species) or a sequence of ``k`` arrays, each
        increasing, symmetric about 0 and including 0.
    k : int
        Number of species.

    Returns
    -------
    tuple of ndarray
    """
    if isinstance(vertices, np.ndarray) and vertices.ndim == 1:
        vertices = [vertices] * k
    if not isinstance(vertices, Sequence | np.ndarray) or len(vertices) != k:
        raise ValueError(f"vertices must be one symmetric mesh (an array) or one per species "
                         f"({k}), got {vertices!r}")
    out = []
    for s, verts in enumerate(vertices):
        verts = np.sort(np.asarray(verts, dtype=float))
        if verts.ndim != 1 or verts.size < 3 or not np.allclose(
                verts, -verts[::-1], rtol=0, atol=1e-12 * np.abs(verts).max()) \
                or not np.any(verts == 0.0):
            raise ValueError(f"vertices[{s}] must be increasing, symmetric about 0 and "
                             f"include v = 0, got {verts!r}")
        out.append(verts)
    return tuple(out)


def _edges(mdisc: MixtureDiscretisation, us: Sequence[NDArray]) -> list[float]:
    """:math:`f_s(V_s)\\sigma_s` at each cut-off."""
    out = []
    for disc, u in zip(mdisc.discs, us, strict=True):
        x = disc.dof_locations
        p = np.exp(u)
        sigma = math.sqrt(float(np.sum(p * x**2) / np.sum(p)))
        out.append(float(np.exp(u[np.argmax(x)])) * sigma)
    return out


def _mixture_state(mixture: Mixture, density: float, mdisc: MixtureDiscretisation,
                   x: NDArray, info: RunInfo, cooling: bool, wall: float) -> MixtureState:
    us = mdisc.split(x[:mdisc.offsets[-1]])
    extra = {"order": mdisc.order, "n_dofs": [int(d.basis.N) for d in mdisc.discs],
             "cutoffs": [float(v[-1]) for v in mdisc.vertices], "cpu_time": wall}
    info = RunInfo(converged=info.converged, iterations=info.iterations,
                   residual=info.residual, wall_time=info.wall_time, message=info.message,
                   extra=extra)
    params = {"density": density, "masses": list(mixture.masses),
              "fractions": list(mixture.fractions)}
    dists = mdisc.distributions(us, method="fem", params=params, info=info)
    zeta = float(x[-1]) if cooling else None
    state = MixtureState(mixture, density, dists, "fem", zeta=zeta, info=info)
    return bisected_recipe(mdisc, x, cooling).attach(state)


def _profiles_of(state: MixtureState) -> tuple[NDArray, list[tuple[NDArray, NDArray]]]:
    """Variances and ``(v, ln f)`` profiles (``v >= 0``, continued linearly in ``|v|`` to
    60 thermal velocities) of a solved state: the start of the next continuation step."""
    variances = np.array([d.moment(2, central=False) for d in state.distributions])
    out = []
    for dist, var in zip(state.distributions, variances, strict=True):
        keep = dist.v > 0
        c, log_f = dist.v[keep], np.log(dist.values[keep])
        slope = (log_f[-1] - log_f[-2]) / (c[-1] - c[-2])
        v = np.linspace(0.0, max(60.0 * math.sqrt(var), float(c[-1])), 30001)
        values = np.interp(v, c, log_f)
        far = v > c[-1]
        values[far] = log_f[-1] + slope * (v[far] - c[-1])
        out.append((v, values))
    return variances, out


def _solve_state(mixture: Mixture, density: float, cooling: bool, *, order: int,
                 spacing: float, cutoff: float | None, vertices: object, tol: float,
                 max_iter: int, start: MixtureState | None = None,
                 one_species: bool = True) -> MixtureState:
    cpu = time.process_time()
    k = mixture.n_species
    zeta0 = None
    if start is None:
        variances = gaussian_variances(mixture, density, cooling)
        if cooling:
            zeta0 = _gaussian_zeta(mixture, density)
        model = mixture if cooling else constant_model(mixture, density, variances)
        profiles = _start_profiles(model, density, variances, cooling, one_species)
    else:
        variances, profiles = _profiles_of(start)
    fixed = vertices is not None or cutoff is not None
    if vertices is not None:
        verts = check_mixture_vertices(vertices, k)
    else:
        if cutoff is not None:
            cuts = [check_positive("cutoff", cutoff) * math.sqrt(v) for v in variances]
        else:
            cuts = []
            # an exponential cooling tail from the P3 starts: the margin in decades (a power
            # law, or the near-elastic starts' tails continued from the humps' steep edge:
            # in velocities)
            steep = (cooling and mixture.collision_kernel.tail_growth[1] > 0.0
                     and float(np.min(1.0 - np.diag(mixture.constant_alpha()))) >= START_EPS)
            decades = DECADES + COOLING_MARGIN_DECADES if steep else DECADES
            margin = 0.0 if steep else CUTOFF_MARGIN
            for (v, log_f), var in zip(profiles, variances, strict=True):
                below = np.flatnonzero(log_f - log_f[0] < -decades * math.log(10.0))
                reach = v[below[0]] if below.size else v[-1]
                cuts.append(float(reach) + margin * math.sqrt(var))
        verts = mixture_meshes(mixture, variances, cuts, spacing=spacing, cooling=cooling)
    # the kernel's kink at g = 0 (|g|^gamma, gamma > 0) against the inner kinks: cut
    kink = cooling and mixture.collision_kernel.tail_growth[1] > 0.0
    reach = tuple(float(SPLIT_REACH * math.sqrt(v)) for v in variances) if kink else None
    mdisc = MixtureDiscretisation(mixture, verts, density, order, split_reach=reach)
    us0 = [np.interp(np.abs(d.dof_locations), v, lf) for d, (v, lf) in
           zip(mdisc.discs, profiles, strict=True)]
    x0 = mdisc.stack(us0)
    if cooling and start is not None:
        x0 = np.concatenate([x0, [start.zeta]])
    elif cooling:
        x0 = np.concatenate([x0, [zeta0]])
    system = _System(mdisc, cooling)
    trimmed = False
    widening = 0
    while True:
        # stop early only where trimmed meshes or another start follow
        x, info = _solve(system, x0, tol=tol, max_iter=max_iter,
                         give_up=not (fixed or trimmed or start is not None))
        us = mdisc.split(x[:mdisc.offsets[-1]])
        if not info.converged:
            trim = None if fixed or trimmed or (cooling and start is not None) \
                else _trimmed_cutoffs(mdisc, us)
            if trim is None:
                raise ConvergenceError(f"the FEM mixture Newton did not converge in "
                                       f"{info.iterations} iterations ({info.message}); refine the "
                                       "mesh (spacing) or increase max_iter")
            logger.info("Newton failed (%s); cut-offs trimmed to %s", info.message, trim)
            trimmed = True
            mdisc, x0 = _remeshed(mdisc, us, trim, spacing, x[mdisc.offsets[-1]:], cooling)
            system = _System(mdisc, cooling)
            continue
        edges = _edges(mdisc, us)
        if max(edges) < TAIL_FLOOR or fixed or widening == MAX_WIDENINGS:
            break
        widening += 1
        logger.info("f_s sigma_s = %s at the cut-offs; widening", edges)
        cuts = _widened(mdisc, us, edges, steep=kink)
        mdisc, x0 = _remeshed(mdisc, us, cuts, spacing, x[mdisc.offsets[-1]:], cooling)
        system = _System(mdisc, cooling)
    if max(edges) >= TAIL_FLOOR:
        warnings.warn(f"f_s sigma_s = {max(edges):.2e} at a cut-off is above {TAIL_FLOOR}: "
                      "the tail is truncated; increase cutoff", ResolutionWarning,
                      stacklevel=3)
    return _mixture_state(mixture, density, mdisc, x, info, cooling,
                          time.process_time() - cpu)


def _variance(disc: FEMDiscretisation, u: NDArray) -> float:
    """:math:`\\sum_i x_i^2 e^{u_i} / \\sum_i e^{u_i}` over the dofs (the mesh scale)."""
    return float(np.sum(np.exp(u) * disc.dof_locations**2) / np.sum(np.exp(u)))


def _remeshed(mdisc: MixtureDiscretisation, us: Sequence[NDArray], cuts: Sequence[float],
              spacing: float, tail: NDArray, cooling: bool
              ) -> tuple[MixtureDiscretisation, NDArray]:
    """New meshes with the cut-offs ``cuts`` (graded on the variances of ``us``) and the
    stacked start on them (``us`` carried over by :func:`_extend`, ``tail`` appended)."""
    variances = np.array([_variance(d, u) for d, u in zip(mdisc.discs, us, strict=True)])
    verts = mixture_meshes(mdisc.mixture, variances, cuts, spacing=spacing, cooling=cooling)
    new = MixtureDiscretisation(mdisc.mixture, verts, mdisc.density, mdisc.order,
                                split_reach=mdisc.split_reach)
    us0 = [_extend(old, u, d) for old, u, d in zip(mdisc.discs, us, new.discs, strict=True)]
    return new, np.concatenate([new.stack(us0), tail])


def _trimmed_cutoffs(mdisc: MixtureDiscretisation, us: Sequence[NDArray]
                     ) -> list[float] | None:
    """Cut-offs where the iterate's :math:`f_s\\sigma_s` first falls below
    :data:`TRIM_LEVEL`, or None if no mesh reaches below it."""
    cuts, changed = [], False
    for disc, u, verts in zip(mdisc.discs, us, mdisc.vertices, strict=True):
        loc = disc.dof_locations
        keep = loc >= 0
        order = np.argsort(loc[keep])
        v, log_f = loc[keep][order], u[keep][order] + 0.5 * math.log(_variance(disc, u))
        below = np.flatnonzero(log_f < math.log(TRIM_LEVEL))
        if below.size and v[below[0]] < float(verts[-1]):
            cuts.append(float(v[below[0]]))
            changed = True
        else:
            cuts.append(float(verts[-1]))
    return cuts if changed else None


def _widened(mdisc: MixtureDiscretisation, us: Sequence[NDArray], edges: Sequence[float],
             steep: bool) -> list[float]:
    """The cut-offs after a widening, for the species whose :math:`f_s\\sigma_s` at the
    cut-off is above :data:`TAIL_FLOOR`: with ``steep`` (the exponential tails of the
    cooling state of a kernel :math:`|g|^\\gamma`, :math:`\\gamma > 0`) where the iterate's
    tail, continued with its slope at the cut-off, falls :data:`WIDEN_DECADES` below it,
    at least :data:`WIDEN_MIN` and at most :data:`WIDEN_MAX` times the old cut-off; else
    (the heated states, the power-law tails of the Maxwell cooling state) a factor
    :data:`WIDEN_MIN`."""
    cuts = []
    for disc, u, edge in zip(mdisc.discs, us, edges, strict=True):
        x = disc.dof_locations
        cut = float(x.max())
        if edge < TAIL_FLOOR:
            cuts.append(cut)
            continue
        keep = x >= 0
        order = np.argsort(x[keep])
        xs, ys = x[keep][order], u[keep][order]
        slope = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
        need = math.log(edge / TAIL_FLOOR) + WIDEN_DECADES * math.log(10.0)
        grow = 1.0 + need / (-slope * cut) if steep and slope < 0.0 else WIDEN_MIN
        cuts.append(cut * min(max(grow, WIDEN_MIN), WIDEN_MAX))
    return cuts


def _extend(old: FEMDiscretisation, u: NDArray, new: FEMDiscretisation) -> NDArray:
    """``u`` on a wider mesh: interpolated inside, continued linearly in |v| outside."""
    x_old = old.dof_locations
    keep = x_old >= 0
    order = np.argsort(x_old[keep])
    xs, us = x_old[keep][order], u[keep][order]
    slope = (us[-1] - us[-2]) / (xs[-1] - xs[-2])
    v = np.abs(new.dof_locations)
    out = np.interp(v, xs, us)
    far = v > xs[-1]
    out[far] = us[-1] + slope * (v[far] - xs[-1])
    return out


@register_solver("fem", problem="mixture-heated")
def solve_mixture_heated(mixture: Mixture, *, density: float = 1.0,
                         order: int = DEFAULT_ORDER, spacing: float = DEFAULT_SPACING,
                         cutoff: float | None = None, vertices: object = None,
                         tol: float = 1e-11, max_iter: int = 40) -> MixtureState:
    """Heated steady state of a mixture by Galerkin FEM and Newton's method.

    Parameters
    ----------
    mixture : Mixture
        Every species forced (white noise or a bath); a restitution law per pair
        (constant or velocity-dependent); a kernel with a compiled rate (power laws, the
        saturating kernel).
    density : float
        Total number density :math:`n > 0`.
    order : int
        Lagrange degree, 1, 2 or 3.
    spacing : float
        Bulk element size in each species' thermal velocity.
    cutoff : float, optional
        Half-width of each mesh in its species' thermal velocities (default: where the
        start falls by 33 decades, widened while :math:`f_s` at the cut-off exceeds 1e-30).
    vertices : array_like or sequence of array_like, optional
        Explicit meshes (physical velocities; one for every species or one each),
        symmetric with a vertex at 0; override ``spacing`` and ``cutoff``.
    tol : float
        Newton tolerance on the update of :math:`\\ln P_s`.
    max_iter : int
        Newton iteration limit.

    Returns
    -------
    MixtureState
        One distribution per species, :math:`T_s`, ratios, :math:`a_{2,s}`;
        ``info.extra`` the mesh sizes and the CPU time.

    Raises
    ------
    ValueError
        If the meshes reach relative speeds beyond a law's range.
    ConvergenceError
        If Newton's method does not converge.

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> mix = kf.Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.6, kernel=0.0)
    >>> state = solve_mixture_heated(mix, spacing=0.5)
    >>> round(float(state.temperatures[0]), 6)      # 4D/(n(1 - alpha^2)) = 6.25
    6.25
    """
    mixture = check_mixture_model(mixture, "the heated steady state", cooling=False)
    density = check_positive("density", density)
    # first from the one-species states for kernels growing at least linearly (hard rods:
    # the gain lifts the tail far above the WKB one), from Gaussians with WKB tails for
    # softer kernels (the Maxwell model's exponential tail does not stretch with sigma);
    # then the other
    first = mixture.collision_kernel.tail_growth[1] >= 1.0
    try:
        return _solve_state(mixture, density, False, order=order, spacing=spacing,
                            cutoff=cutoff, vertices=vertices, tol=tol, max_iter=max_iter,
                            one_species=first)
    except ConvergenceError as err:
        logger.info("heated mixture from the first start failed (%s); the other", err)
    return _solve_state(mixture, density, False, order=order, spacing=spacing, cutoff=cutoff,
                        vertices=vertices, tol=tol, max_iter=max_iter, one_species=not first)


@register_solver("fem", problem="mixture-cooling")
def solve_mixture_cooling(mixture: Mixture, *, density: float = 1.0,
                          order: int = DEFAULT_ORDER, spacing: float = DEFAULT_SPACING,
                          cutoff: float | None = None, vertices: object = None,
                          tol: float = 1e-11, max_iter: int = 40) -> MixtureState:
    """Homogeneous cooling state of a mixture (scaled, :math:`T = 1`) by FEM and Newton.

    Parameters
    ----------
    mixture : Mixture
        No forcing; constant restitution per pair; a power-law kernel.
    density, order, spacing, cutoff, vertices, tol, max_iter
        As in :func:`solve_mixture_heated`.

    Returns
    -------
    MixtureState
        Scaled to the mixture temperature :math:`T = 1`; ``zeta`` the common cooling
        rate (:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`).

    Raises
    ------
    UnsupportedModelError
        For a restitution law or a kernel that is not a power law.
    ConvergenceError
        If Newton's method does not converge.
    """
    mixture = check_mixture_model(mixture, "the homogeneous cooling state", cooling=True)
    density = check_positive("density", density)
    options = {"order": order, "spacing": spacing, "cutoff": cutoff, "vertices": vertices,
               "tol": tol, "max_iter": max_iter}
    try:
        return _solve_state(mixture, density, True, **options)  # type: ignore[arg-type]
    except ConvergenceError as err:
        logger.info("cooling mixture from the one-species start failed (%s); continuation "
                    "from identical species", err)
    return _continued(mixture, density, options)


def _homotopy(mixture: Mixture, t: float) -> Mixture:
    """The mixture at ``t`` on the path from identical species (``t = 0``: unit masses,
    every pair at the mean restitution coefficient) to ``mixture`` (``t = 1``)."""
    alpha = mixture.constant_alpha()
    masses = tuple(float(m) ** t for m in mixture.masses)
    table = (1.0 - t) * float(alpha.mean()) + t * alpha
    return Mixture(masses, mixture.fractions, alpha=table.tolist(),
                   kernel=mixture.collision_kernel, thermostats=mixture.thermostats)


def _continued(mixture: Mixture, density: float, options: dict[str, Any]) -> MixtureState:
    """The cooling state by continuation from identical species (:func:`_homotopy`),
    the step halved when Newton fails and grown by half after a success."""
    cpu = time.process_time()
    inner = dict(options, tol=CONTINUATION_TOL)
    state = _solve_state(_homotopy(mixture, 0.0), density, True, **inner)
    t, step, steps = 0.0, 0.25, 0
    while t < 1.0:
        target = min(1.0, t + step)
        final = target == 1.0
        try:
            state = _solve_state(_homotopy(mixture, target), density, True,
                                 **(options if final else inner), start=state)
        except ConvergenceError as err:
            step *= 0.5
            if step < MIN_CONTINUATION_STEP:
                raise ConvergenceError(
                    f"no homogeneous cooling state found for {mixture!r}: the continuation "
                    f"from identical species stalled at t = {t:.4g} of the path to the "
                    "mixture (masses m_s^t, alpha table interpolated); the scaled state may "
                    "not exist (e.g. a runaway temperature ratio at disparate masses) or "
                    f"need a finer mesh ({err})") from err
            continue
        t = target
        steps += 1
        step *= 1.5
    assert state.info is not None
    extra = dict(state.info.extra, continuation_steps=steps,
                 cpu_time=time.process_time() - cpu)
    info = replace(state.info, extra=extra)
    return MixtureState(state.mixture, density, state.distributions, "fem", zeta=state.zeta,
                        info=info, error_recipe=state.error_recipe)


# ---------------------------------------------------------------- error estimate
def bisected_recipe(mdisc: MixtureDiscretisation, x: NDArray, cooling: bool
                    ) -> MixtureErrorRecipe:
    """The error estimate of a mixture state: one Newton step on the bisected meshes.

    As for one species (:mod:`kinetic_fem.solvers.fem.error`): every species' :math:`u_s`
    is interpolated exactly onto its mesh with every element bisected, one undamped
    Newton step of the coupled system (with :math:`\\zeta` in free cooling) is taken
    there, and the state is compared with the result, times
    :func:`~kinetic_fem.error.richardson_factor` (:mod:`kinetic_fem.mixture_error`).
    Computed when ``state.error`` is first read: one Jacobian on twice the dofs.  The
    Maxwell mixture's cooling state adds its cut-off error (:func:`_plus_cutoff`).

    Parameters
    ----------
    mdisc : MixtureDiscretisation
        The state's discretisation.
    x : ndarray
        Its stacked even unknowns (and :math:`\\zeta` last in free cooling).
    cooling : bool
        A cooling state.

    Returns
    -------
    MixtureErrorRecipe
    """
    from .error import bisected, interpolated_log

    def compute() -> MixtureError:
        mix = mdisc.mixture
        fine = MixtureDiscretisation(mix, tuple(bisected(d).vertices for d in mdisc.discs),
                                     mdisc.density, mdisc.order, mdisc.intorder,
                                     mdisc.split_reach)
        us = mdisc.split(x[:mdisc.offsets[-1]])
        x_fine = fine.stack([interpolated_log(d, u, f) for d, u, f in
                             zip(mdisc.discs, us, fine.discs, strict=True)])
        if cooling:
            x_fine = np.concatenate([x_fine, x[-1:]])
        res, jac = _System(fine, cooling)(x_fine, True)
        assert jac is not None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            step = -EquilibratedLU(jac).solve(res)
        n_u = int(fine.offsets[-1])
        better = fine.distributions(fine.split(x_fine[:n_u] + log_update(step[:n_u])))
        zeta = (float(x[-1]), float(x[-1] + step[-1])) if cooling else None
        est = compare_species(mdisc.distributions(us), better, mix.masses, mix.fractions,
                              method=BISECTED_MIXTURE,
                              factor=richardson_factor(mdisc.order), zeta=zeta)
        if cooling and mix.collision_kernel.tail_growth[1] == 0.0:
            return _plus_cutoff(est, mdisc, x)
        return est

    return MixtureErrorRecipe(compute, BISECTED_MIXTURE, mdisc.mixture.n_species)


BISECTED_MIXTURE = "one Newton step on the bisected meshes"
CUTOFF_POWER = 3.0
"""The order :math:`p` of the cut-off error :math:`V^{-p}` of the Maxwell mixture's
cooling state where the observed one is not available (3: the mass of a :math:`v^{-4}`
tail beyond :math:`V`; measured 3.5, m 1:3 with the alpha table)."""


def _plus_cutoff(est: MixtureError, mdisc: MixtureDiscretisation, x: NDArray
                 ) -> MixtureError:
    """``est`` plus the cut-off error of a Maxwell mixture's cooling state.

    Its power-law tails carry mass and energy beyond the cut-offs, an error no mesh
    changes and the bisection does not see (200 times its estimate at the default
    cut-offs, m 1:3 with the alpha table).  The state is solved again (Newton from it) on
    each mesh cut at its last vertex :math:`V'_s \\le V_s/2` and at :math:`V_s/4`; the
    change to the first, times :math:`1/((V/V')^p - 1)` with the order :math:`p` observed
    from the two changes of :math:`\\zeta` (clipped to [1, 6]; :data:`CUTOFF_POWER` if
    they do not decrease), is added to every estimate.  Cost: two Newton solves on the
    shorter meshes (with the bisected step 0.3 - 0.4 times the solve, P2).

    Parameters
    ----------
    est : MixtureError
        The bisected meshes' estimate.
    mdisc : MixtureDiscretisation
        The state's discretisation.
    x : ndarray
        Its stacked even unknowns and :math:`\\zeta` last.
    """
    from .error import interpolated_log

    mix = mdisc.mixture
    us = mdisc.split(x[:mdisc.offsets[-1]])
    states = []
    for share in (0.5, 0.25):
        cuts = [float(d.vertices[d.vertices <= share * d.vertices[-1]].max())
                for d in mdisc.discs]
        short = MixtureDiscretisation(
            mix, tuple(d.vertices[np.abs(d.vertices) <= c] for d, c in
                       zip(mdisc.discs, cuts, strict=True)), mdisc.density, mdisc.order,
            mdisc.intorder, mdisc.split_reach)
        x0 = np.concatenate([short.stack([interpolated_log(d, u, e) for d, u, e in
                                          zip(mdisc.discs, us, short.discs, strict=True)]),
                             x[-1:]])
        x_short, info = _solve(_System(short, True), x0, tol=1e-11, max_iter=40)
        if not info.converged:
            return replace(est, note=f"{est.note}; without the cut-off's share (the state "
                                     f"on the meshes cut at {share} did not converge: "
                                     f"{info.message})")
        ratio = min(d.vertices[-1] / c for d, c in zip(mdisc.discs, cuts, strict=True))
        states.append((short, x_short, ratio))
    # the observed order from the changes of zeta (V/4 -> V/2 against V/2 -> V)
    (short, x_short, ratio), (_, x_quarter, ratio4) = states
    d_half = abs(float(x_short[-1]) / float(x[-1]) - 1.0)
    d_quarter = abs(float(x_quarter[-1]) / float(x_short[-1]) - 1.0)
    power = CUTOFF_POWER
    if d_half > 0 and d_quarter > d_half:
        power = min(max(math.log(d_quarter / d_half) / math.log(ratio4 / ratio), 1.0), 6.0)
    cut = compare_species(mdisc.distributions(us),
                          short.distributions(short.split(x_short[:short.offsets[-1]])),
                          mix.masses, mix.fractions, method="the cut-offs halved",
                          factor=1.0 / (ratio**power - 1.0),
                          zeta=(float(x[-1]), float(x_short[-1])))
    species = tuple(replace(
        p, temperature=p.temperature + q.temperature, a2=p.a2 + q.a2,
        zeta=None if p.zeta is None or q.zeta is None else p.zeta + q.zeta,
        f_relative=p.f_relative + np.nan_to_num(q.f_relative, nan=np.inf),
        method=f"{p.method} plus the cut-offs halved")
        for p, q in zip(est.species, cut.species, strict=True))
    return MixtureError(species, est.ratios + cut.ratios, est.temperature + cut.temperature,
                        None if est.zeta is None or cut.zeta is None else est.zeta + cut.zeta,
                        method=f"{BISECTED_MIXTURE} plus the cut-offs halved")

