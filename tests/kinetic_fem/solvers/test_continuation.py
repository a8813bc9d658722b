"""The continuation driver: the retry rule, the adaptive step, the paths."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pytest

from kinetic_fem.run_info import RunInfo
from kinetic_fem.solvers.continuation import (
    NO_RETRY,
    StepRule,
    continuation,
    geometric_path,
    ratio_path,
)


@dataclass(frozen=True)
class _State:
    value: float
    info: RunInfo = field(default_factory=RunInfo)


def _model(largest: float, calls: list[tuple[float, float]]):
    """A solve that converges on steps of ratio <= ``largest``, in a number of Newton
    iterations that grows with the ratio (a contraction that worsens with the step)."""

    def solve(prev: _State, p: float, q: float) -> _State:
        calls.append((p, q))
        ratio = max(p / q, q / p)
        ok = ratio <= largest
        its = 2 + round(10 * math.log(ratio)) if ok else 40
        return _State(q, RunInfo(converged=ok, iterations=its))

    return solve


def test_planned_path_walked_as_given_and_failed_steps_split():
    calls: list[tuple[float, float]] = []
    walk = continuation(_State(0.1), 0.1, geometric_path(0.1, 1e-3, 10.0), _model(4.0, calls),
                        rule=StepRule(min_ratio=1.1))
    assert walk.converged and walk.value == 1e-3 and walk.state.value == 1e-3
    # each step of ratio 10 fails once and is split at the geometric mean (ratio 3.16)
    assert walk.retries == 2
    first = geometric_path(0.1, 1e-3, 10.0)[0]
    assert calls[0] == (0.1, first) and calls[1] == (0.1, math.sqrt(0.1 * first))


def test_retry_rule_stops_and_reports_the_failed_step():
    calls: list[tuple[float, float]] = []
    walk = continuation(_State(0.1), 0.1, [1e-3], _model(1.05, calls),
                        rule=StepRule(min_ratio=1.1))
    assert not walk.converged and walk.value == 0.1
    assert walk.failed is not None and walk.last is walk.failed
    assert 1.0 < 0.1 / walk.failed_value <= 1.1  # split down to the smallest ratio


def test_no_retry_stops_at_the_first_failure():
    calls: list[tuple[float, float]] = []
    walk = continuation(_State(1.0), 1.0, [0.5, 0.1], _model(3.0, calls), rule=NO_RETRY)
    assert not walk.converged and walk.value == 0.5 and walk.failed_value == 0.1
    assert len(calls) == 2


def test_repeated_value_is_solved_twice_and_states_are_kept():
    calls: list[tuple[float, float]] = []
    kept: list[float] = []
    walk = continuation(_State(1.0), 1.0, [0.5, 0.5], _model(3.0, calls),
                        on_converged=lambda s, p: kept.append(p))
    assert walk.converged and calls == [(1.0, 0.5), (0.5, 0.5)] and kept == [0.5, 0.5]


def test_adaptive_step_follows_newton_iterations():
    """Steps of ratio r take 2 + 10 ln r iterations: aiming at 5 iterations the step
    settles near r = e^0.3 = 1.35 and grows back after a shrink; the target is reached."""
    calls: list[tuple[float, float]] = []
    rule = StepRule(min_ratio=1.01, target_iterations=5, first_step=1.05)
    walk = continuation(_State(0.1), 0.1, [1e-4], _model(2.0, calls), rule=rule)
    assert walk.converged and walk.state.value == 1e-4 and walk.retries == 0
    ratios = [p / q for p, q in calls]
    assert ratios[1] > ratios[0]  # 3 iterations < 5: grown
    assert all(r <= 2.0 for r in ratios)
    assert len(calls) < 40  # a fixed step 1.05 would take 142


def test_adaptive_step_shrinks_after_a_failure():
    calls: list[tuple[float, float]] = []
    rule = StepRule(min_ratio=1.01, target_iterations=20, first_step=8.0)
    walk = continuation(_State(1.0), 1.0, [1e-3], _model(2.0, calls), rule=rule)
    assert walk.converged and walk.retries >= 1
    assert calls[0] == (1.0, 1.0 / 8.0) and calls[1][1] == pytest.approx(1.0 / math.sqrt(8.0))


def test_linear_scale_midpoint():
    rule = StepRule(min_ratio=0.01, scale="linear")
    assert rule.midpoint(0.5, 0.7) == pytest.approx(0.6)
    assert rule.splits(0.5, 0.52) and not rule.splits(0.5, 0.505)
    assert rule.advanced(0.5, 0.9, 0.1) == pytest.approx(0.6)


def test_paths():
    assert geometric_path(0.01, 0.04, 2.0) == pytest.approx([0.02, 0.04])
    assert geometric_path(0.1, 0.1, 2.0) == [0.1]
    assert ratio_path(0.1, 1e-3, 2.0)[-1] == 1e-3
    assert ratio_path(0.1, 1e-3, 2.0)[:2] == [0.05, 0.025]


@pytest.mark.parametrize("kwargs, match", [
    ({"min_ratio": 1.0}, "min_ratio"),
    ({"scale": "cubic"}, "scale"),
    ({"target_iterations": 0}, "target_iterations"),
    ({"growth": 1.0}, "growth"),
])
def test_step_rule_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        StepRule(**kwargs)
