"""Tests of kinetic_fem.solvers.fem.cooling_chain (several states, one continuation)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem import cooling_chain as fem_cooling_chain


def test_states_at_requested_inelasticities():
    """alpha = 0.93 at 0.14 hump widths: zeta/eps 1.0021305966 (test_fem_cooling)."""
    states = fem_cooling_chain.hump_states([0.07], resolution=0.14)
    assert list(states) == [0.07]
    assert states[0.07].info.converged
    assert states[0.07].zeta / 0.07 == pytest.approx(1.0021305966, rel=1e-9)


def test_unreachable_states_are_left_out(monkeypatch):
    def state(converged):
        return SimpleNamespace(info=SimpleNamespace(converged=converged, message="stalled"),
                               zeta=1.0)

    calls = []

    def step(prev, eps_prev, eps, **kwargs):  # converges down to 1e-3 only
        calls.append(eps)
        return state(eps >= 1e-3)

    monkeypatch.setattr(fem_cooling, "hump_start", lambda order, intorder: state(True))
    monkeypatch.setattr(fem_cooling, "continued_state", step)
    states = fem_cooling_chain.hump_states([1e-2, 1e-3, 1e-5], resolution=0.1)
    assert sorted(states) == [1e-3, 1e-2]
    assert min(calls) < 1e-3  # it tried, halving the step, before giving up
    with pytest.raises(ValueError, match="inelasticities"):
        fem_cooling_chain.hump_states([0.2])
