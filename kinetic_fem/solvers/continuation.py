"""One continuation driver over a model parameter (issue 26).

A continuation reaches the solution at a parameter value :math:`p_*` (the inelasticity
:math:`\\varepsilon = 1 - \\alpha`, the restitution coefficient, the kernel exponent
:math:`\\gamma`, a restitution law's parameter: the driver does not know which) from a
solution at :math:`p_0`, through the solutions at the values of a *path*
:math:`p_0 \\to p_1 \\to \\dots \\to p_*`.  Each step is one call of the caller's
``solve(prev, p_prev, p)``, which returns a state with ``info.converged`` (a
:class:`~kinetic_fem.run_info.RunInfo`); the driver decides what comes next:

- a converged step moves on to the next value of the path;
- a failed step is retried through the midpoint of the step (the geometric mean on a
  ``"log"`` scale, the arithmetic mean on a ``"linear"`` one) while the step is larger
  than :attr:`StepRule.min_ratio` (the *retry rule*), else the continuation stops and
  reports the failed step;
- with :attr:`StepRule.target_iterations` set, the driver also chooses the values
  between those of the path: after a converged step of :math:`k` Newton iterations the
  next step is the last one scaled by :math:`\\min(g, \\max(1/g, k_*/k))` on the path's
  scale (:math:`k_*` the target, :math:`g` :attr:`StepRule.growth`), capped at the next
  value of the path.  Newton's iteration count measures its contraction from the
  predicted start (a start inside the quadratic basin converges in a few steps; a
  contraction near 1 takes many), so the step grows where the solutions move slowly and
  shrinks where they move fast, never below ``min_ratio``.  The iteration count has a
  floor (Newton from the nearest start still takes a few steps to its tolerance): a
  target at or below it only shrinks the step.  Without it the path is walked as given
  (the planned chains of the FEM cooling state, whose intermediate states also set the
  next meshes: results bit-identical to the loops this driver replaced; on the alpha
  chain of gamma = 2 and 1.5 the planned ratio 1.6 took fewer Newton steps than the
  controlled step, ``benchmarks/results/continuation_step.md``).

Used by the FEM cooling state (the continuation in alpha of hard kernels
:func:`~.fem.cooling_alpha.alpha_chain`, the near-elastic chain
:func:`~.fem.cooling_quasi.quasi_elastic_chain`, the hump chain
:func:`~.fem.cooling_links.chain_state`, the band's links
:func:`~.fem.cooling_band.band_state`, several states in one walk
:func:`~.fem.cooling_chain.hump_states`, the strong-inelasticity start
:class:`~.fem.regimes.StrongInelastic`) and by the curves of states
(:func:`~.fem.curve.heated_curve`, :func:`~.fem.cooling_curve.cooling_curve`, whose
paths are the values asked for and whose steps do not split).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Generic, Literal, Protocol, TypeVar

from ..run_info import RunInfo

__all__ = ["StepRule", "NO_RETRY", "ContinuationResult", "continuation",
           "geometric_path", "ratio_path"]

logger = logging.getLogger(__name__)


class _Converging(Protocol):
    """A state with a convergence report (``info.converged``, ``info.iterations``)."""

    @property
    def info(self) -> RunInfo:  # noqa: D102
        ...


S = TypeVar("S", bound=_Converging)
P = TypeVar("P")


@dataclass(frozen=True)
class StepRule:
    """How a continuation controls its step.

    Parameters
    ----------
    min_ratio : float
        Retry rule: a failed step from :math:`p` to :math:`q` is split at its midpoint
        while it is larger than this (``"log"``: :math:`\\max(p/q, q/p)`; ``"linear"``:
        :math:`|q - p|`); ``math.inf``: a failed step is never split (the continuation
        stops there).
    scale : {"log", "linear"}
        The scale of midpoints and of the adaptive step (``"log"`` for a parameter that
        goes to 0, such as :math:`\\varepsilon`).
    target_iterations : int, optional
        Newton iterations per step aimed at by the adaptive step (module docstring);
        None: the path is walked as given, split only by the retry rule.
    growth : float
        Largest factor (> 1) by which the adaptive step grows, or shrinks, per step.
    first_step : float, optional
        The first adaptive step on the path's scale (a ratio > 1 on ``"log"``, a
        positive difference on ``"linear"``); default: up to the first value of the path.

    Raises
    ------
    ValueError
        For a non-positive ``min_ratio`` (or <= 1 on the log scale), an unknown ``scale``,
        ``target_iterations`` < 1 or ``growth`` <= 1.
    """

    min_ratio: float = 1.1
    scale: Literal["log", "linear"] = "log"
    target_iterations: int | None = None
    growth: float = 2.0
    first_step: float | None = None

    def __post_init__(self) -> None:
        if self.scale not in ("log", "linear"):
            raise ValueError(f"scale must be 'log' or 'linear', got {self.scale!r}")
        low = 1.0 if self.scale == "log" else 0.0
        if not self.min_ratio > low:
            raise ValueError(f"min_ratio must be > {low:g} on the {self.scale} scale, got "
                             f"{self.min_ratio!r}")
        if self.target_iterations is not None and self.target_iterations < 1:
            raise ValueError(f"target_iterations must be >= 1 or None, got "
                             f"{self.target_iterations!r}")
        if not self.growth > 1.0:
            raise ValueError(f"growth must be > 1, got {self.growth!r}")

    def size(self, p: float, q: float) -> float:
        """The size of the step from ``p`` to ``q`` on this scale.

        Parameters
        ----------
        p, q : float
            The two values (both positive on the log scale).

        Returns
        -------
        float
            :math:`\\max(p/q, q/p)` or :math:`|q - p|`.
        """
        if self.scale == "log":
            return max(p / q, q / p)
        return abs(q - p)

    def midpoint(self, p: float, q: float) -> float:
        """The midpoint of the step from ``p`` to ``q`` (where a failed step is split).

        Parameters
        ----------
        p, q : float
            The two values.

        Returns
        -------
        float
        """
        return math.sqrt(p * q) if self.scale == "log" else 0.5 * (p + q)

    def splits(self, p: float, q: float) -> bool:
        """Whether a failed step from ``p`` to ``q`` is retried through its midpoint.

        Parameters
        ----------
        p, q : float
            The two values.

        Returns
        -------
        bool
        """
        return self.size(p, q) > self.min_ratio

    def advanced(self, p: float, q: float, step: float) -> float:
        """The value one adaptive ``step`` from ``p`` toward ``q``, not beyond ``q``.

        Parameters
        ----------
        p, q : float
            The last value reached and the next value of the path.
        step : float
            The step on this scale (a ratio > 1, or a positive difference).

        Returns
        -------
        float
        """
        if self.size(p, q) <= step:
            return q
        if self.scale == "log":
            return p * step if q > p else p / step
        return p + math.copysign(step, q - p)

    def next_step(self, step: float, iterations: int) -> float:
        """The adaptive step after a converged step of ``iterations`` Newton iterations.

        Parameters
        ----------
        step : float
            The step just taken, on this scale.
        iterations : int
            Its Newton iterations.

        Returns
        -------
        float
            At least ``min_ratio``.
        """
        assert self.target_iterations is not None
        factor = min(self.growth, max(1.0 / self.growth,
                                      self.target_iterations / max(iterations, 1)))
        # never below the smallest step the retry rule splits (a failure there would
        # stop the continuation)
        if self.scale == "log":
            return max(float(step ** factor), self.min_ratio)  # the log of the ratio scales
        return max(step * factor, self.min_ratio)


@dataclass(frozen=True)
class ContinuationResult(Generic[S]):
    """The outcome of :func:`continuation`.

    Parameters
    ----------
    state : state
        The last converged state (the start if no step converged).
    value : float
        Its parameter value.
    converged : bool
        The last value of the path was reached.
    failed : state or None
        The state of the step that stopped the continuation (None if it converged).
    failed_value : float or None
        The value that step aimed at.
    steps : int
        Steps solved (converged or not).
    retries : int
        Failed steps that were split.
    """

    state: S
    value: float
    converged: bool
    failed: S | None
    failed_value: float | None
    steps: int
    retries: int

    @property
    def last(self) -> S:
        """The state the old loops returned: the failed step's if one stopped the walk."""
        return self.state if self.failed is None else self.failed


NO_RETRY = StepRule(min_ratio=math.inf, scale="linear")
"""A continuation whose failed step stops it (the path's values only)."""


def continuation(start: S, value: float, path: Sequence[float],
                 solve: Callable[[S, float, float], S], *, rule: StepRule = StepRule(),
                 on_converged: Callable[[S, float], None] | None = None
                 ) -> ContinuationResult[S]:
    """Walk ``path`` from ``start`` at ``value``, one ``solve`` per step (module docstring).

    Parameters
    ----------
    start : state
        The solution at ``value`` (anything with ``info.converged``).
    value : float
        Its parameter value.
    path : sequence of float
        The values to visit in order, the last the target; a value may repeat (a second
        solve at the same value, e.g. on a finer mesh).
    solve : callable
        ``solve(prev, p_prev, p) -> state``: the solution at ``p`` from ``prev`` at
        ``p_prev``; converged or not (``state.info.converged``), it may also raise.
    rule : StepRule
        The retry rule and the adaptive step.
    on_converged : callable, optional
        ``on_converged(state, p)`` after each converged step (e.g. to keep the states at
        the values asked for).

    Returns
    -------
    ContinuationResult
    """
    pending = list(path)[::-1]  # a stack: the next value last
    prev, prev_value = start, value
    steps = retries = 0
    adaptive = rule.target_iterations is not None
    h = rule.first_step
    while pending:
        target = pending[-1]
        p = target
        if adaptive:
            if h is None:
                h = rule.size(prev_value, target) if prev_value != target else None
            if h is not None:
                p = rule.advanced(prev_value, target, h)
        state = solve(prev, prev_value, p)
        steps += 1
        if state.info.converged:
            if p == target:
                pending.pop()
            if adaptive and p != prev_value:
                h = rule.next_step(rule.size(prev_value, p), state.info.iterations)
            prev, prev_value = state, p
            if on_converged is not None:
                on_converged(state, p)
        elif rule.splits(prev_value, p):
            retries += 1
            if adaptive:
                h = rule.size(prev_value, rule.midpoint(prev_value, p))
            else:
                pending.append(rule.midpoint(prev_value, p))
            logger.info("continuation: step %.6g -> %.6g failed; split at its midpoint",
                        prev_value, p)
        else:
            return ContinuationResult(prev, prev_value, False, state, p, steps, retries)
    return ContinuationResult(prev, prev_value, True, None, None, steps, retries)


def geometric_path(start: float, end: float, ratio: float) -> list[float]:
    """Values from ``start`` to ``end`` (either direction) in equal steps on a log scale,
    each a ratio of at most ``ratio``, ending exactly at ``end`` (``start`` left out).

    Parameters
    ----------
    start : float
        The value of the start (positive).
    end : float
        The last value (positive).
    ratio : float
        Largest ratio of successive values (> 1).

    Returns
    -------
    list of float

    Examples
    --------
    >>> [round(e, 6) for e in geometric_path(0.1, 1e-3, 8.0)]
    [0.021544, 0.004642, 0.001]
    >>> [round(e, 6) for e in geometric_path(0.01, 0.04, 2.0)]
    [0.02, 0.04]
    """
    n = max(1, math.ceil(abs(math.log(start / end)) / math.log(ratio) - 1e-9))
    return [start * (end / start) ** (k / n) for k in range(1, n)] + [end]


def ratio_path(start: float, end: float, ratio: float) -> list[float]:
    """Values from ``start`` down to ``end``: ``start / ratio**k`` while above ``end``,
    then ``end`` (``start`` left out).

    Parameters
    ----------
    start : float
        The value of the start (positive, above ``end``).
    end : float
        The last value (positive).
    ratio : float
        The ratio of successive values (> 1).

    Returns
    -------
    list of float

    Examples
    --------
    >>> [round(e, 6) for e in ratio_path(0.1, 1e-3, 2.0)]
    [0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.001563, 0.001]
    """
    n = max(1, math.ceil(math.log(start / end) / math.log(ratio) - 1e-9))
    return [*(start / ratio**k for k in range(1, n)), end]
