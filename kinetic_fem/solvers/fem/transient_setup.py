"""Options, counters, meshes and initial data of the FEM transients.

The pieces of :mod:`kinetic_fem.solvers.fem.transient` that do not step in time: the
validated numerical options (:class:`TransientOptions`), the run counters
(:class:`TransientStats`), the ratio of error constants of the step-size control
(:func:`lte_ratio`), the symmetric mesh, graded where a Gaussian is steep
(:func:`build_mesh`), the discretisation of a model (:func:`make_discretisation`), the
floored initial data (:func:`floor_log`) and the accepted levels (:class:`Level`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...model import CollisionKernel, RestitutionLaw
from ...operators.mesher import ScaleGrading, march
from .heated import FEMDiscretisation

__all__ = ["MAX_RATIO", "MIN_EXPONENT", "retry_step", "CAP_GROWTH", "NOISE_FLOOR",
           "INITIAL_FLOOR", "LOG_SMALLEST", "LOG_TAIL", "MAX_DROP", "MESH_GROWTH",
           "TransientOptions", "TransientStats", "lte_ratio", "build_mesh",
           "make_discretisation", "floor_log", "Level", "lagrange_weights",
           "check_normalised", "distribution_log_density", "progress_bar",
           "default_newton_tol", "SCHEMES", "BDF3_MAX_RATIO", "bdf_weights"]

CAP_GROWTH = 1.2
"""After a Newton failure at a step h, steps stay below 0.7 h, and after a rejected
step below the retried one: a cap that grows by this factor per accepted step."""

MAX_RATIO = 2.0
"""Largest ratio of a step to the one before: variable-step BDF2 is zero-stable below
:math:`1 + \\sqrt 2` (the step after one shortened to reach an output time had ratios
up to 47 and was rejected)."""

BDF3_MAX_RATIO = 1.5
"""Largest ratio of a step to the one before for variable-step BDF3 and BDF4, and their
largest growth per step (BDF2: ``MAX_RATIO``); a smaller growth than BDF2's, as the
zero-stability bounds of variable-step BDF fall with the order."""

SCHEMES = {"bdf2": 2, "bdf3": 3, "bdf4": 4}
"""Time schemes of the FEM transients and their highest order (``TransientOptions.scheme``):
all start with backward Euler and raise the order by one per accepted step."""

MIN_EXPONENT = 0.3
"""Smallest exponent of the error norm in the step assumed after a second rejection of
the same step (:func:`retry_step`)."""

NOISE_FLOOR = 10.0
"""The local error tolerance of a step is at least this many Newton tolerances (the
error per unit step of a very short step would otherwise be below the Newton noise)."""

INITIAL_FLOOR = 1e-45
"""Initial data are floored at this fraction of their maximum (see :func:`floor_log`).

A Gaussian's far tail lies hundreds of decades below the collisional tail that builds
up within one collision time; Newton's method on ln P cannot bridge that gap in one
step."""


LOG_TAIL = math.log(1e-30)
"""Far tail: ln P this far below the peak is continued linearly (see
:meth:`kinetic_fem.solvers.fem.transient.Integrator.tail_closure`)."""

MAX_DROP = 2.0
"""Largest fall of a Gaussian's ln P across one element of a graded mesh
(:func:`build_mesh`)."""

MESH_GROWTH = 1.1
"""Growth of the element size beyond the refined zone of a graded mesh."""

LOG_SMALLEST = math.log(1e-300)
"""Initial tails stay above this (ln P), far from underflow of exp."""


@dataclass(frozen=True)
class TransientOptions:
    """Numerical options of a transient (all validated by the entry points).

    Attributes
    ----------
    rtol : float
        Tolerance on the local error per collision time (per unit of scaled time when
        cooling): relative on T, absolute on a2; the global errors are about ``rtol``.
    min_step : float
        Smallest step: below about (node spacing)^2 / (2 D) the implicit Galerkin step
        of a state with steep ln P has no positive solution, so steps this short are
        accepted whatever their error estimate (counted in ``forced``); 0 (the heated
        gas: the graded mesh and the tail closure keep short steps solvable).
    order : int
        Lagrange degree of the elements (1 or 2).
    spacing : float
        Element size in thermal velocities of the coldest state.
    cutoff : float, optional
        Half-width of the velocity interval in thermal velocities of the hottest state.
    first_step : float, optional
        First step (and step after a discontinuity); default ``rtol`` collision times.
    max_step : float
        Largest step (time units of the problem; inf: no limit).
    max_steps : int
        Accepted plus rejected steps before giving up.
    newton_tol : float
        Newton tolerance on the update of ln P.
    max_newton : int
        Newton iterations per step before the step counts as failed.
    moment_norm : bool
        The step Newton measures its updates by the moments they change (and every ln P
        to ``TAIL_TOL``, :meth:`~kinetic_fem.solvers.fem.transient.BDF2.newton_weights`);
        False: by the largest update of ln P against ``newton_tol`` (the free-cooling
        driver: with the moment norm a viscoelastic cooling run at spacing 0.5, rtol 1e-5
        found no acceptable step at s = 2.26).
    scheme : str
        ``"bdf2"`` (the default), ``"bdf3"`` or ``"bdf4"`` (variable-step BDF3/BDF4
        once four/five levels are known: 2-3 times fewer steps at equal or smaller global
        error, but on coarse meshes, spacing 0.6, their long steps ended in cascades of
        Newton failures; :data:`SCHEMES`).
    """

    rtol: float = 1e-4
    min_step: float = 0.0
    order: int = 2
    spacing: float = 0.25
    cutoff: float | None = None
    first_step: float | None = None
    max_step: float = math.inf
    max_steps: int = 20000
    newton_tol: float = 1e-11
    max_newton: int = 12
    moment_norm: bool = True
    scheme: str = "bdf2"


@dataclass
class TransientStats:
    """Counters of a run.

    Parameters
    ----------
    accepted, rejected, newton_failures, newton_iterations, restarts, forced : int
        Counts of steps and Newton iterations.
    residuals, jacobians, factorisations : int
        Residual evaluations of the step Newton, Jacobian evaluations (kept across
        steps) and LU factorisations of the step matrix.
    slow_newton : int
        Simplified Newton iterations stopped for slow contraction or divergence.
    backtracks : int
        Levels dropped and taken again by BDF2 after a BDF3/BDF4 step had no
        continuation (``transient.BACKTRACK_FAILURES``).
    """

    accepted: int = 0
    rejected: int = 0
    newton_failures: int = 0
    newton_iterations: int = 0
    restarts: int = 0
    forced: int = 0
    residuals: int = 0
    jacobians: int = 0
    factorisations: int = 0
    slow_newton: int = 0
    backtracks: int = 0

    def as_dict(self) -> dict[str, int]:
        return dict(vars(self))


def default_newton_tol(rtol: float, scheme: str = "bdf2") -> float:
    """Default tolerance of the step Newton on the update of ln P: ``1e-4 rtol`` with
    BDF2, ``1e-3 rtol`` with the higher orders, at least 1e-11.

    With BDF3 and ``1e-4 rtol`` the simplified Newton of the longer steps stalled near
    round-off on a coarse mesh (hard rods from T = 0.8, spacing 0.6, rtol 1e-3: 9 Newton
    failures cascading to steps of 1e-5; ``1e-3 rtol``: none, 31 steps), and the global
    errors did not change (hard rods to t = 5, rtol 1e-3 ... 1e-5: the same to two
    digits; Maxwell model in a bath: within rtol, ``benchmarks/bench_transient_speed.py``).

    Far below the local error the step control admits (``rtol`` per collision time),
    so the Newton error does not reach the error estimate; tighter costs iterations,
    and below 1e-11 (the earlier fixed tolerance) the simplified Newton meets round-off
    (``rtol`` 5e-10 stalled).  ``1e-3 rtol`` was too loose: the error floor of short
    steps (``NOISE_FLOOR`` Newton tolerances) then left <v^4> of the Maxwell transient
    at 1.2e-6 instead of 4.3e-7 (rtol 1e-5, spacing 0.25, cut-off 8).

    Parameters
    ----------
    rtol : float
        The transient's tolerance.
    scheme : str
        The time scheme (:data:`SCHEMES`).

    Returns
    -------
    float
    """
    return max((1e-4 if scheme == "bdf2" else 1e-3) * rtol, 1e-11)


def lte_ratio(steps: tuple[float, ...], order: int) -> float:
    """Ratio ``E_c / (E_c - E_p)`` of corrector and predictor error constants.

    The local error of the corrector is ``lte_ratio * (y_corrector - y_predictor)``.
    ``steps = (h_k, h_{k-1}, h_{k-2})`` (BDF2 with a quadratic predictor) or
    ``(h_k,)`` (backward Euler with an explicit Euler predictor), ``(h_k, h_{k-1})``
    (backward Euler with the linear extrapolation through the last two levels), or
    ``(h_k, ..., h_{k-3})`` (BDF3 with a cubic predictor).  Computed by applying
    both formulas to :math:`t^{q+1}/(q+1)!`.

    Parameters
    ----------
    steps : tuple of float
        The last step sizes, newest first.
    order : int
        1 (backward Euler), 2 (BDF2) or 3 (BDF3).

    Returns
    -------
    float

    Examples
    --------
    >>> round(lte_ratio((1.0, 1.0, 1.0), 2), 12), lte_ratio((0.1,), 1)
    (0.181818181818, 0.5)
    >>> round(lte_ratio((1.0, 1.0, 1.0, 1.0), 3), 12), round(lte_ratio((1.0, 1.0), 1), 12)
    (0.12, 0.333333333333)
    """
    if order == 1 and len(steps) == 1:
        return 0.5
    if order != 2:
        return _lte_ratio_generic(steps, order)
    h, h1, h2 = steps
    w = h / h1
    c_new = (1.0 + 2.0 * w) / (1.0 + w)
    # y = t^3/6 with t_{k+1} = 0: residual of c_new y - (1+w) y_k + w^2/(1+w) y_{k-1} - h y'
    resid = -(1.0 + w) * (-h) ** 3 / 6.0 + w * w / (1.0 + w) * (-(h + h1)) ** 3 / 6.0
    e_corr = -resid / c_new
    e_pred = -h * (h + h1) * (h + h1 + h2) / 6.0
    return e_corr / (e_corr - e_pred)


def bdf_weights(nodes: list[float]) -> list[float]:
    """Derivative at ``nodes[0]`` of the Lagrange interpolant through ``nodes``.

    The variable-step BDF formula of order ``len(nodes) - 1`` for the new time
    ``nodes[0]`` is :math:`\\sum_j a_j m(t_j) = R(t_0)` with these weights :math:`a_j`.

    Parameters
    ----------
    nodes : list of float
        The new time first, then the past times (distinct).

    Returns
    -------
    list of float

    Examples
    --------
    >>> [round(a, 12) for a in bdf_weights([2.0, 1.0, 0.0])]   # BDF2, h = 1
    [1.5, -2.0, 0.5]
    """
    s = nodes[0]
    out = []
    for j, sj in enumerate(nodes):
        if j == 0:
            out.append(sum(1.0 / (s - sk) for sk in nodes[1:]))
            continue
        w = 1.0 / (sj - s)
        for k, sk in enumerate(nodes):
            if k not in (0, j):
                w *= (s - sk) / (sj - sk)
        out.append(w)
    return out


def _lte_ratio_generic(steps: tuple[float, ...], order: int) -> float:
    """:func:`lte_ratio` of variable-step BDF of ``order`` with the predictor through
    ``order + 1`` past levels, by both formulas applied to :math:`t^{q+1}/(q+1)!`."""
    times = [0.0]
    for h in steps:
        times.append(times[-1] - h)
    y = [t ** (order + 1) / math.factorial(order + 1) for t in times]
    a = bdf_weights(times[:order + 1])
    # y(0) = y'(0) = 0: the corrector's value solves a_0 y_0 + sum a_j y_j = 0
    e_corr = -sum(aj * yj for aj, yj in zip(a[1:], y[1:order + 1], strict=True)) / a[0]
    e_pred = sum(wj * yj for wj, yj in
                 zip(lagrange_weights(times[1:order + 2], 0.0), y[1:order + 2], strict=True))
    return e_corr / (e_corr - e_pred)


def retry_step(h: float, err: float, order: int,
               rejected: tuple[float, float] | None = None) -> float:
    """The step to try after a rejection of ``h`` with error norm ``err > 1``.

    First rejection: the asymptotic factor :math:`0.9\\,err^{-1/p}` (``p = order``: the
    error per unit step is :math:`O(h^p)`) within [0.2, 0.9].  A further rejection of
    the same step uses the exponent observed between the two tries instead, at least
    ``MIN_EXPONENT`` (factor within [0.05, 0.9]): after a quench the estimate can fall
    far slower than :math:`h^p` as the step is cut (measured, Kovacs quench: 1.85, 2.86,
    2.88, 2.19, 1.56, 1.22, 1.04, 0.94 while the step fell 17x), so that the asymptotic
    factor took eight tries.

    Parameters
    ----------
    h, err : float
        The rejected step and its error norm.
    order : int
        Order of the step (1 backward Euler, 2 BDF2).
    rejected : tuple of float, optional
        ``(h, err)`` of the try of the same step before ``h``.

    Returns
    -------
    float

    Examples
    --------
    >>> round(retry_step(1.0, 4.0, 2), 4), round(retry_step(0.5, 3.0, 2, (1.0, 4.0)), 4)
    (0.45, 0.0319)
    """
    if rejected is not None and rejected[0] > h and rejected[1] > 0.0:
        exponent = math.log(err / rejected[1]) / math.log(h / rejected[0])
        exponent = min(max(exponent, MIN_EXPONENT), order)
        return h * max(0.05, min(0.9, 0.9 * err ** (-1.0 / exponent)))
    return h * max(0.2, min(0.9, 0.9 * err ** (-1.0 / order)))


def build_mesh(v_max: float, h: float, thermal: float | None = None
               ) -> NDArray[np.float64]:
    """Symmetric vertices on ``[-v_max, v_max]`` with about ``h`` spacing.

    With ``thermal`` (the thermal velocity :math:`\\sqrt{T}` of the coldest state),
    elements are refined where a Gaussian at that temperature falls by more than
    ``MAX_DROP`` in ln P per element, out to where it falls below ``LOG_TAIL`` of its
    peak: the P2 Galerkin masses of steeper elements are not positivity preserving and
    the implicit steps of such a state lose their positive solution (measured: the
    tolerance benchmark from T = 0.5 at spacing 0.5, ln P falling 8 per element at
    v = 4 thermal velocities).  Beyond, the elements grow back by ``MESH_GROWTH``.

    Parameters
    ----------
    v_max : float
        Half-width of the mesh.
    h : float
        Element size.
    thermal : float, optional
        Thermal velocity of the coldest state (None: uniform).

    Returns
    -------
    ndarray
        Vertices symmetric about 0.
    """
    if thermal is None:
        return ScaleGrading(h, 0.0).stretched(v_max)
    temp = thermal * thermal
    v_tail = math.sqrt(-2.0 * LOG_TAIL) * thermal
    last = [h]

    def element(x: float) -> float:
        if x < v_tail:   # the Gaussian's drop (x e + e^2/2)/T over [x, x + e] is MAX_DROP
            last[0] = min(h, math.sqrt(x * x + 2.0 * MAX_DROP * temp) - x)
        else:
            last[0] = min(h, last[0] * MESH_GROWTH)
        return last[0]

    marched = march(element, v_max)
    edges, size = marched[marched.size // 2:], last[0]
    pos = np.array(edges)
    pos *= v_max / pos[-1] if pos[-1] - v_max < 0.5 * size else 1.0
    if pos[-1] > v_max * (1.0 + 1e-12):   # a short last element: merge it
        pos = np.append(pos[:-2], v_max)
    return np.concatenate([-pos[:0:-1], pos])


def make_discretisation(law: RestitutionLaw, gamma: float | CollisionKernel,
                        vertices: NDArray, order: int) -> FEMDiscretisation:
    """The FEM discretisation of the collision operator with ``law`` and ``|g|^gamma``.

    Velocities are physical (``speed_scale = 1``); the collision term is that of unit
    density (the integrator multiplies it by ``n``).

    Parameters
    ----------
    law : RestitutionLaw
        The restitution law.
    gamma : float or CollisionKernel
        The kernel (a float: the exponent of a power law).
    vertices : ndarray
        Mesh vertices.
    order : int
        Lagrange degree.

    Returns
    -------
    FEMDiscretisation
    """
    alpha = law.constant if law.constant is not None else getattr(law, "alpha", 1.0)
    if law.constant is not None and gamma == 1.0:
        return FEMDiscretisation(alpha, vertices, order, 2 * order + 1)
    return FEMDiscretisation(alpha, vertices, order, 2 * order + 1, gamma=gamma,
                             law=None if law.constant is not None else law)


def floor_log(x: NDArray[np.float64], u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Even ``u = ln P`` at ``x``, continued below ``ln(INITIAL_FLOOR * max P)`` linearly.

    Beyond the speed where ``u`` first falls below the floor, ``u`` continues with the
    slope it has there (an exponential tail, exact in P1/P2): a kink or a plateau of
    ln P within an element leaves the first implicit steps without a positive solution.

    Parameters
    ----------
    x : ndarray
        Nodes.
    u : ndarray
        :math:`\\ln P` at ``x``.

    Returns
    -------
    ndarray
    """
    out = np.array(u, dtype=float)
    level = out.max() + math.log(INITIAL_FLOOR)
    speed = np.abs(x)
    order = np.argsort(speed, kind="stable")
    s_sorted, u_sorted = speed[order], out[order]
    below = np.flatnonzero(u_sorted < level)
    if below.size == 0:
        return out
    j = max(int(below[0]), 1)
    i = j - 1
    while i > 0 and s_sorted[i] == s_sorted[j]:
        i -= 1
    slope = min((u_sorted[j] - u_sorted[i]) / (s_sorted[j] - s_sorted[i]), -1e-3)
    # no value below ln(1e-300) at the edge: P must stay a normal double
    span = s_sorted[-1] - s_sorted[j]
    if span > 0:
        slope = max(slope, (LOG_SMALLEST - u_sorted[j]) / span)
    beyond = speed > s_sorted[j]
    out[beyond] = u_sorted[j] + slope * (speed[beyond] - s_sorted[j])
    return out


@dataclass
class Level:
    """One accepted level: time ``s``, ``u``, masses, ``zeta``, aux ``y``, observables.

    Parameters
    ----------
    s : float
        Time of the level.
    u : ndarray
        Coefficients of :math:`\\ln P_h`.
    m : ndarray
        Masses :math:`\\int\\varphi_i P_h`.
    zeta : float
        Drift coefficient (cooling; 0 heated).
    y : ndarray
        Auxiliary variables (:math:`\\ln T` and the physical time, cooling).
    obs : ndarray
        Observables (T, a2, ...).
    udot : ndarray, optional
        Time derivative of ``u``.
    """

    s: float
    u: NDArray[np.float64]
    m: NDArray[np.float64]
    zeta: float
    y: NDArray[np.float64]
    obs: NDArray[np.float64]
    udot: NDArray[np.float64] | None = None


def lagrange_weights(nodes: list[float], s: float) -> list[float]:
    """Weights of the Lagrange interpolant through ``nodes`` evaluated at ``s``.

    Parameters
    ----------
    nodes : list of float
        Interpolation nodes (times).
    s : float
        Evaluation point.

    Returns
    -------
    list of float
        Weights of the Lagrange interpolant at ``s``.
    """
    out = []
    for j, sj in enumerate(nodes):
        w = 1.0
        for k, sk in enumerate(nodes):
            if k != j:
                w *= (s - sk) / (sj - sk)
        out.append(w)
    return out


def check_normalised(dist: VelocityDistribution) -> None:
    """Raise ``ValueError`` unless ``dist`` has unit mass (to 1e-6).

    Parameters
    ----------
    dist : VelocityDistribution
        An initial state.

    Raises
    ------
    ValueError
        If its mass differs from 1 by more than 1e-6.
    """
    mass = float(dist.raw_moments[0])
    if not abs(mass - 1.0) <= 1e-6:
        raise ValueError(f"the initial distribution is not normalised: its mass is {mass:.8g}; "
                         "pass a normalised VelocityDistribution (from_values normalises "
                         "by default)")


def distribution_log_density(dist: VelocityDistribution, v: NDArray[np.float64], *,
                        scale: float = 1.0) -> NDArray:
    """``ln(scale P(scale v))`` of an even version of ``dist``, floored, Gaussian beyond.

    Parameters
    ----------
    dist : VelocityDistribution
        The initial distribution.
    v : ndarray
        Velocities where :math:`\\ln P` is wanted.
    scale : float
        Velocity scale factor (see the summary).

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        If ``dist`` is not normalised (mass differs from 1 by more than 1e-6).
    """
    check_normalised(dist)
    temp = dist.temperature
    inner = 0.999 * min(abs(dist.v[0]), abs(dist.v[-1]))
    av = np.abs(v) * scale
    a_in = np.minimum(av, inner)
    p = 0.5 * (dist.pdf(a_in) + dist.pdf(-a_in)) * scale
    tiny = np.finfo(float).tiny
    log_p = np.log(np.maximum(p, tiny)) - 0.5 * (av**2 - a_in**2) / temp
    return floor_log(v, log_p)


def progress_bar(progress: bool, t_end: float, desc: str):
    """A tqdm bar over the time ``[0, t_end]`` (disabled unless ``progress``) and its
    update ``t -> None``.

    Parameters
    ----------
    progress : bool
        Show the bar.
    t_end : float
        Last output time.
    desc : str
        Label of the bar.

    Returns
    -------
    bar, update
    """
    from tqdm.auto import tqdm

    bar = tqdm(total=float(t_end), desc=desc, disable=not progress, unit="t",
               bar_format="{l_bar}{bar}| t={n:.4g}/{total:.4g} [{elapsed}]")

    def update(t: float) -> None:
        bar.update(min(float(t), float(t_end)) - bar.n)

    return bar, update
