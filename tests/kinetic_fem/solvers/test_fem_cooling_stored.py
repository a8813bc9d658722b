"""Tests of the stored cooling states: data files, generator, independence (issue 26).

The seeds are regenerated (fast) in test_fem_cooling_seeds.py."""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem import cooling_generate as gen
from kinetic_fem.solvers.fem import cooling_stored as stored
from kinetic_fem.solvers.fem import regimes as fr


def test_data_files_ship_and_read():
    """Both tables are read from the installed package (importlib.resources): 2,448
    numbers of gamma = 2 anchors, 717 of hard-rod seeds (+ their three eps)."""
    points, anchors = stored.gamma2_anchors()
    assert points == 65 and len(anchors) == 36
    assert sum(3 + len(a[3]) for a in anchors) == 2448
    assert all(len(a[3]) == points for a in anchors)
    seeds = stored.hard_rod_seeds()
    assert sum(1 + len(c) + len(f) for _, c, f in seeds.values()) == 717
    with pytest.raises(ValueError, match="name must be one of"):
        stored.read_data("anchors.py")


@pytest.mark.parametrize("name", stored.DATA_FILES)
def test_data_files_are_what_the_generator_writes(name):
    """The files are in the generator's format (to_json of their content is the file)."""
    from importlib import resources

    text = resources.files("kinetic_fem.solvers.fem").joinpath("data").joinpath(name).read_text()
    assert gen.to_json(stored.read_data(name)) == text


_DEEP = 30.0 * np.log(10.0)  # compare where f > 1e-30 of its peak


def _estimate(state) -> tuple[float, float]:
    """The true-error bound of a state from its two-level estimate: the estimate is the
    distance to the state on the bisected mesh, whose own error is 2^-p times smaller
    (p = order + 1, the rate of ln f in the maximum norm), so the error is the estimate
    times 2^p / (2^p - 1).  Returns (zeta relative, max over elements where f > 1e-30)."""
    eta, dzeta = state.error_estimate()
    verts = state.disc.vertices
    log_f = state.log_f(0.5 * (verts[1:] + verts[:-1]))
    factor = 2.0 ** (state.disc.order + 1) / (2.0 ** (state.disc.order + 1) - 1.0)
    return factor * dzeta, factor * float(eta[log_f > log_f.max() - _DEEP].max())


def _agreement(gamma: float, alpha: float) -> tuple[float, float, float, float]:
    problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
    with_table = fr.solve_state(problem, fr.CoolingOptions())
    without = fr.solve_state(problem, fr.CoolingOptions(stored=False))
    c = np.linspace(0.0, 0.9 * min(with_table.disc.vertices[-1], without.disc.vertices[-1]),
                    2000)
    la, lb = with_table.log_f(c), without.log_f(c)
    keep = la > la.max() - _DEEP
    (za, ea), (zb, eb) = _estimate(with_table), _estimate(without)
    return (abs(with_table.zeta - without.zeta) / with_table.zeta, za + zb,
            float(np.abs(la - lb)[keep].max()), ea + eb)


@pytest.mark.parametrize("gamma, alpha", [
    (2.0, 0.3), (1.0, 0.97), pytest.param(2.0, 0.9, marks=pytest.mark.slow),
    pytest.param(2.0, 0.999, marks=pytest.mark.slow)])
def test_answer_does_not_depend_on_the_table(gamma, alpha):
    """From the stored start and from the generic start/continuation (stored=False) the
    states agree within the sum of their error bounds (:func:`_estimate`).  Measured
    (zeta relative, max |ln f| where f > 1e-30, against the bounds): gamma 2 at 0.3 and
    0.9 and hard rods at 0.97 the same discrete state (zeta to 1e-15, bounds 1e-9 to
    1e-13); gamma 2 at 0.999 (the anchors' own mesh) zeta 3.9e-8 against 4.4e-8 (the
    chain's state is the less accurate: estimate 3.7e-8 against 1.0e-9), ln f 0.073
    against 0.091."""
    dzeta, dzeta_bound, dlogf, dlogf_bound = _agreement(gamma, alpha)
    assert dzeta <= dzeta_bound
    assert dlogf <= dlogf_bound


@pytest.mark.slow
def test_gamma2_table_regenerates():
    """Every gamma = 2 anchor recomputed by the generator: zeta/eps and c_end to 1e-12,
    eps ln f to its 8 stored digits (36 continuations, several CPU minutes)."""
    data = stored.read_data("gamma2_anchors.json")
    eps_values = [a["eps"] for a in data["anchors"]]
    # the generator's grid (np.geomspace: its last bit varies between numpy versions)
    np.testing.assert_allclose(eps_values, np.geomspace(1.0, 5e-4, 36), rtol=1e-15)
    fresh = gen.gamma2_table(eps_values, data["points"])
    for old, new in zip(data["anchors"], fresh["anchors"], strict=True):
        assert new["zeta_ratio"] == pytest.approx(old["zeta_ratio"], rel=1e-12)
        assert new["c_end"] == pytest.approx(old["c_end"], rel=1e-12)
        np.testing.assert_allclose(new["eps_log_f"], old["eps_log_f"], rtol=1e-7, atol=1e-9)
