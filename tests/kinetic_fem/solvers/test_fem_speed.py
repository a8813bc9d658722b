"""Issue 16: mesh sequencing, the chord-predicted stop, the P3 default of the heated FEM."""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.solvers.fem import heated as fem
from kinetic_fem.solvers.fem.defaults import default_spacing


def test_nested_coarse_keeps_every_third_vertex_and_the_end_band():
    half = np.linspace(0.0, 10.0, 51)
    v = np.concatenate([-half[:0:-1], half])
    c = fem.nested_coarse(v, 3, band=4)
    assert np.isin(c, v).all()
    np.testing.assert_allclose(c, -c[::-1])
    pos = c[c >= 0]
    np.testing.assert_allclose(np.diff(pos)[-4:], 0.2)  # the fine band at the end
    np.testing.assert_allclose(np.diff(pos)[:10], 0.6)


@pytest.mark.parametrize("alpha", [0.3, 0.95])
def test_mesh_sequencing_reaches_the_direct_state(monkeypatch, alpha):
    """Sequenced (coarse mesh first) and direct Newton end at the same state: measured
    max |du| 3e-13 (alpha = 0.3) and 1e-12 (0.95, with the widening done on the coarse
    mesh); tolerance 1e-10, the Newton tolerance 1e-11 plus the chord-predicted stop."""
    seq = fem.steady_state(alpha, order=2, spacing=0.08)
    monkeypatch.setattr(fem, "SEQUENCE_MAX_SPACING", 0.0)
    direct = fem.steady_state(alpha, order=2, spacing=0.08)
    assert seq.u.size == direct.u.size
    assert np.abs(seq.u - direct.u).max() < 1e-10


def test_chord_predicted_stop_saves_the_confirming_residual():
    """The shared driver's ``predict``: the last chord step is taken without the residual
    that would confirm it, and the result is as close to the root as without it."""
    from kinetic_fem.solvers.newton import newton

    calls = []

    def fun(x, jac):
        calls.append(jac)
        return x**3 + x - 3.0, np.diag(3.0 * x**2 + 1.0)

    kw = dict(tol=1e-12, criterion="step", line_search=False, chord=1e-2,
              factorize=lambda j: (lambda b: np.linalg.solve(j, b)))
    plain = newton(fun, [1.2], **kw)
    n_plain = len(calls)
    calls.clear()
    fast = newton(fun, [1.2], predict=0.01, **kw)
    assert plain.converged and fast.converged and "chord-predicted" in fast.message
    assert len(calls) < n_plain
    assert abs(fast.x[0] - plain.x[0]) < 1e-12


@pytest.mark.parametrize("alpha", [0.0, 0.6, 0.9])
def test_p3_default_is_at_least_as_accurate_as_p2(alpha):
    """The P3 default against P3 at 0.8 times the P2 spacing: T and a2 errors below the
    P2 default's (measured 10-1000 times below: benchmarks/archive/results/fem_speed.md)."""
    p3 = fem.steady_state(alpha)
    assert p3.disc.order == 3
    p2 = fem.steady_state(alpha, order=2)
    assert p3.u.size < 0.8 * p2.u.size
    cut = p2.disc.vertices[-1] / np.sqrt(p2.disc.distribution(p2.u).temperature)
    ref = fem.steady_state(alpha, order=3, spacing=0.8 * default_spacing(alpha), cutoff=cut)
    dr = ref.disc.distribution(ref.u)
    errs = {}
    for name, st in (("p2", p2), ("p3", p3)):
        d = st.disc.distribution(st.u)
        errs[name] = (abs(d.temperature / dr.temperature - 1), abs(d.a2 / dr.a2 - 1))
    assert errs["p3"][0] < errs["p2"][0] and errs["p3"][1] < errs["p2"][1]
    assert errs["p3"][0] < 1e-8 and errs["p3"][1] < 1e-6
