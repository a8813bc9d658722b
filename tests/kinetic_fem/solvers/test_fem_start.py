"""The gain-delayed (tangent) tail of the heated FEM start for soft kernels (issue 16)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
import kinetic_fem.solvers.fem.defaults as defaults
import kinetic_fem.solvers.fem.heated as fem
from kinetic_fem.model import ConstantRestitution, PowerLawKernel, SaturatingKernel
from kinetic_fem.solvers.fem.defaults import ScaledModel
from kinetic_fem.solvers.fem.start import start_exponent


def _grid(kernel, temperature: float, top: float = 60.0):
    v = np.linspace(0.0, top, 6001)
    return v, v**2 / (2.0 * temperature), np.asarray(kernel.wkb_action(v), dtype=float)


@pytest.mark.parametrize("kernel, friction", [(PowerLawKernel(1.0), 0.0),
                                              (PowerLawKernel(2.0), 0.0),
                                              (SaturatingKernel(1.0), 0.5)])
def test_other_models_keep_the_bare_tail(kernel, friction):
    model = ScaledModel(ConstantRestitution(0.5), kernel, friction, 1.0, 3.0)
    _, gauss, action = _grid(kernel, 3.0)
    np.testing.assert_array_equal(start_exponent(gauss, action, model),
                                  np.minimum(gauss, action))


@pytest.mark.parametrize("kernel", [PowerLawKernel(0.0), PowerLawKernel(0.5),
                                    SaturatingKernel(1.0)])
def test_soft_kernels_continue_the_gaussian(kernel):
    temperature = 5.0
    model = ScaledModel(ConstantRestitution(0.5), kernel, 0.0, 1.0, temperature)
    v, gauss, action = _grid(kernel, temperature)
    out = start_exponent(gauss, action.copy(), model)
    # the Gaussian up to the tangent point, S continued beyond: never above either
    t = int(np.flatnonzero(np.diff(gauss) > np.diff(action))[0])  # G grows faster
    np.testing.assert_array_equal(out[:t], gauss[:t])
    np.testing.assert_allclose(out[t:], gauss[t] + action[t:] - action[t], rtol=1e-15)
    assert np.all(out <= gauss) and np.all(out <= action + 1e-12)
    # continuous slope: the Gaussian's v/T meets S' = sqrt(B) at the tangent point
    slope = np.sqrt(float(kernel.rate(v[t])))
    assert v[t] / temperature == pytest.approx(slope, abs=2 * (v[1] - v[0]) / temperature)


def _jacobians(alpha: float, kernel) -> list[int]:
    counts: list[int] = []
    original = fem.newton_steady

    def counted(disc, u0, **kw):
        u, info = original(disc, u0, **kw)
        counts.append(int(info.message.split(";")[-1].split()[0]))
        return u, info

    fem.newton_steady = counted
    try:
        fem.steady_state(kf.HeatedProblem.from_parameters(alpha, kernel=kernel))
    finally:
        fem.newton_steady = original
    return counts


def test_the_tangent_start_saves_a_coarse_jacobian(monkeypatch):
    """Saturating kernel at alpha = 0.9: coarse Jacobians 3 -> 2 (measured), the same
    state."""
    kernel = SaturatingKernel(1.0)
    problem = kf.HeatedProblem.from_parameters(0.9, kernel=kernel)
    new = fem.steady_state(problem)
    assert _jacobians(0.9, kernel) == [2, 1]
    monkeypatch.setattr(defaults, "start_exponent", lambda g, a, m: np.minimum(g, a))
    assert _jacobians(0.9, kernel) == [3, 1]
    old = fem.steady_state(problem)
    d_new, d_old = new.disc.distribution(new.u), old.disc.distribution(old.u)
    assert d_new.temperature == pytest.approx(d_old.temperature, rel=1e-13)
    assert d_new.a2 == pytest.approx(d_old.a2, abs=1e-13)
