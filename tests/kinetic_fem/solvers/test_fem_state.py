"""The heated FEM state's run figures: the C1 sides computed on first read (issue 16)."""

from __future__ import annotations

import dataclasses
import json
import pickle

import pytest

import kinetic_fem as kf
from kinetic_fem.solvers.fem import heated as fem
from kinetic_fem.solvers.fem.state import LazyExtra


@pytest.mark.parametrize(("alpha", "gamma"), [(0.6, 1.0), (0.8, 0.5)])
def test_c1_figures_are_the_eager_ones_bit_for_bit(alpha, gamma):
    problem = kf.HeatedProblem.from_parameters(alpha, kernel=gamma)
    state = fem.steady_state(problem)
    injection, loss = state.energy_terms()  # the former eager evaluation
    extra = fem.state_distribution(problem, state, state.disc.order).info.extra
    assert isinstance(extra, LazyExtra) and extra._lazy is not None  # not yet computed
    assert extra["c1_injection"] == injection and extra["c1_loss"] == loss
    assert list(extra) == ["n_dofs", "order", "c1_injection", "c1_loss"]


def test_lazy_extra_reads_as_a_plain_dict():
    calls = []

    def lazy():
        calls.append(1)
        return {"b": 2.0}

    extra = LazyExtra({"a": 1}, lazy=lazy)
    assert extra == {"a": 1, "b": 2.0} and len(calls) == 1
    assert "b" in extra and extra.get("b") == 2.0 and len(extra) == 2 and len(calls) == 1
    assert dict(extra) == {"a": 1, "b": 2.0} and extra.copy() == {"a": 1, "b": 2.0}
    for read in (lambda e: e["b"], lambda e: dict(e.items()), lambda e: list(e.values()),
                 lambda e: sorted(e), lambda e: pickle.loads(pickle.dumps(e)),
                 lambda e: json.loads(json.dumps(e)), lambda e: {**e}, repr):
        fresh = LazyExtra({"a": 1}, lazy=lambda: {"b": 2.0})
        out = read(fresh)
        assert dict.__contains__(fresh, "b"), read
        if isinstance(out, dict):
            assert out == {"a": 1, "b": 2.0}
    unpickled = pickle.loads(pickle.dumps(LazyExtra({"a": 1}, lazy=lambda: {"b": 2.0})))
    assert type(unpickled) is dict


def test_distribution_with_lazy_extra_stores_and_pickles():
    dist = kf.solve_heated(0.7, kernel=0.0)
    info = pickle.loads(pickle.dumps(dist.info))
    assert type(info.extra) is dict and info.extra["c1_loss"] == dist.info.extra["c1_loss"]
    meta = dataclasses.asdict(kf.solve_heated(0.7, kernel=0.0).info)
    assert json.loads(json.dumps(meta["extra"]))["c1_loss"] == pytest.approx(
        dist.info.extra["c1_loss"], rel=1e-14)
