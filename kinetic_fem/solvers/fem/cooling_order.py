"""Element degree and spacing of the default FEM cooling state (issue 16).

For hard rods away from the near-elastic humps (:math:`\\varepsilon \\ge 0.1`), P3
elements at :data:`P3_SPACING` times the P2 bulk spacing of
:func:`kinetic_fem.solvers.fem.cooling_mesh.hcs_spacing` (0.1 instead of 0.05) give a
cooling rate and :math:`a_2` about ten thousand times more accurate than the P2 default,
and :math:`f` 2 to 50 times more accurate where :math:`f > 10^{-30}`, with 0.75 times
its dofs.  Measured against P3 at spacing 0.025 (``benchmarks/archive/results/fem_speed.md``,
section "cooling"; relative error of zeta, absolute of a2, max relative of f):

====== ========================= =========================
alpha  P2 default (0.05)         P3 default (0.1)
====== ========================= =========================
0      7.6e-10, 4.2e-9, 3.1e-5   2.2e-14, 9.7e-14, 8.9e-7
0.5    6.0e-10, 3.2e-9, 1.3e-5   2.0e-14, 8.7e-14, 1.7e-6
0.7    1.3e-10, 3.9e-10, 1.4e-5  2.5e-14, 1.2e-13, 5.8e-6
0.8    1.1e-9, 5.1e-9, 2.4e-5    7.6e-14, 3.5e-13, 5.0e-7
0.9    1.9e-9, 9.4e-9, 4.1e-5    1.4e-13, 8.1e-13, 3.4e-6
====== ========================= =========================

At 2.5 times the P2 spacing zeta and a2 were still 1000 times better, but the error of
f near the cut-off (f ~ 1e-30) at alpha = 0.7 was twice the P2 default's (3.0e-5).

The mesh sequencing of :func:`kinetic_fem.solvers.fem.cooling.cooling_state` keeps P2
on its coarse mesh (the coarse state only starts Newton's method on the fine one).
Other kernels keep P2 (their tails and the Maxwell model's recovered :math:`f` were
measured with it), and so do the continuation links on the near-elastic hump meshes;
the state asked for there is P3 at 0.2 hump widths (:mod:`.cooling_hump`), and in
the band :math:`0.035 \\le \\varepsilon < 0.1` P3 on a mesh graded along the tail
(:mod:`.cooling_band`).
"""

from __future__ import annotations

from ...model import CoolingProblem

__all__ = ["P3_SPACING", "COARSE_ORDER", "P3_COARSE_SPACING", "cooling_order", "order_spacing",
           "STRONG_ALPHA", "STRONG_STEP", "COARSE_FACTOR", "COARSE_SPACING", "COARSE_TOL"]

P3_SPACING = 2.0
"""Bulk spacing of the P3 default, in units of the P2 default spacing."""
COARSE_ORDER = 2
"""Degree of the coarse state of the mesh sequencing."""
P3_COARSE_SPACING = 0.3
"""Largest bulk spacing of that coarse state when the fine mesh is P3 (0.2 for P2): its
globalised iteration costs a third (10 to 40 Jacobians on 160-220 instead of 240-330
dofs), and Newton's method on the fine mesh still takes two Jacobians (0.4 fails to
converge at alpha = 0.9)."""

STRONG_ALPHA = 0.5
"""Below this alpha (long exponential tails, far from the Gaussian start) the state is
reached by continuation in alpha from here, in steps of at most STRONG_STEP."""
STRONG_STEP = 0.5
"""Largest step in alpha of that continuation: one step from 0.5 (0.125 before: alpha = 0
and 0.25 1.17 and 1.06 times faster, gamma = 0.5 / 1.5 / 2 at alpha 0 ... 0.3 1.1-1.6
times, the states equal to 1e-15: benchmarks/archive/results/fem_cooling_speed.md)."""
COARSE_FACTOR = 4.0
"""Mesh sequencing: the default mesh's state is started from the state on a mesh this
many times coarser (same cut-off), reached by the globalised (pseudo-transient) Newton
iteration; on the fine mesh Newton's method then converges in three or four steps
(about 2 to 40 times faster than the globalised iteration on the fine mesh, same state:
``benchmarks/results/fem_cooling.md``)."""
COARSE_SPACING = 0.2
"""Largest bulk spacing of the coarse state (no sequencing on meshes this coarse)."""
COARSE_TOL = 1e-7
"""Newton tolerance of the coarse state of the mesh sequencing (it only starts the fine one)."""


def cooling_order(problem: CoolingProblem, order: int | None, *, default_mesh: bool) -> int:
    """The element degree: ``order`` if given, else 3 for hard rods on the default mesh.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (its kernel is read).
    order : int or None
        The degree the caller asked for; None: the default.
    default_mesh : bool
        No ``spacing``, ``cutoff`` or ``vertices`` given and not the near-elastic hump
        mesh (an explicit mesh keeps its P2 meaning).

    Returns
    -------
    int

    Examples
    --------
    >>> cooling_order(CoolingProblem.from_parameters(0.5), None, default_mesh=True)
    3
    >>> cooling_order(CoolingProblem.from_parameters(0.5), None, default_mesh=False)
    2
    """
    if order is not None:
        return order
    return 3 if default_mesh and problem.gas.gamma == 1.0 else 2


def order_spacing(p2_spacing: float, order: int) -> float:
    """The bulk spacing of degree ``order`` from the P2 default ``p2_spacing``.

    Parameters
    ----------
    p2_spacing : float
        The P2 default (:func:`kinetic_fem.solvers.fem.cooling_mesh.hcs_spacing`).
    order : int
        Element degree.

    Returns
    -------
    float
        :data:`P3_SPACING` times ``p2_spacing`` for P3, else ``p2_spacing``.
    """
    return P3_SPACING * p2_spacing if order == 3 else p2_spacing
