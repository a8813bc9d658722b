"""The parallel pair kernel (numba prange over outer points) is bit-identical to the
serial one (:mod:`kinetic_fem.operators.fem_pair_parallel`)."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from kinetic_fem.operators.fem_discretisation import FEMDiscretisation
from kinetic_fem.operators.fem_pair_parallel import PARALLEL_ENV, collision, parallel_enabled
from kinetic_fem.solvers import fem

THREADS = sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)})


def _args(disc, u, jacobian, energy_power):
    verts, dofs = disc.mesh_arrays
    xq, wq, eq = disc.points
    rx, rw = disc.basis.quadrature
    return (verts, dofs, disc.order, u, xq, wq, eq, np.ascontiguousarray(rx[0]), rw,
            disc.alpha, 1.0, jacobian, energy_power, False, float(disc.gamma), 0, disc.alpha,
            0.0, 1.0, 0.8)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("gamma", [1.0, 0.5])
@pytest.mark.parametrize("even", [False, True])
@pytest.mark.parametrize("jacobian", [False, True])
def test_parallel_kernel_is_bit_identical(order, gamma, even, jacobian):
    """Residual and Jacobian equal bit for bit at 1 and 2 threads (gamma = 0.5: graded
    pieces)."""
    disc = FEMDiscretisation(0.6, np.linspace(-8.0, 8.0, 41), order, 2 * order + 1,
                             gamma=gamma)
    x = disc.dof_locations
    u = -0.4 * x**2 + 0.05 * np.cos(x) - 1.0
    mirror = disc.mirror if even else None
    args = _args(disc, u, jacobian, -1)
    serial = collision(*args, mirror, parallel=False)
    before = numba.get_num_threads()
    try:
        for threads in THREADS:
            numba.set_num_threads(threads)
            par = collision(*args, mirror, parallel=True)
            np.testing.assert_array_equal(par[0], serial[0])
            np.testing.assert_array_equal(par[1], serial[1])
    finally:
        numba.set_num_threads(before)


def test_moments_and_the_setting_select_the_serial_kernel(monkeypatch):
    """Pair moments are summed in the serial order: a call asking for them runs the
    serial kernel (moments non-zero); the environment setting is off by default."""
    monkeypatch.delenv(PARALLEL_ENV, raising=False)
    assert not parallel_enabled()
    monkeypatch.setenv(PARALLEL_ENV, "1")
    assert parallel_enabled()
    disc = FEMDiscretisation(0.6, np.linspace(-8.0, 8.0, 21), 3, 7)
    u = disc.gaussian(1.5)
    res, _, moment, loss = collision(*_args(disc, u, False, 3), disc.mirror)
    assert moment > 0.0 and loss > 0.0
    np.testing.assert_array_equal(res, collision(*_args(disc, u, False, -1), disc.mirror)[0])


def test_steady_state_is_bit_identical_with_the_parallel_kernel(monkeypatch):
    """A whole Newton solve (P3, alpha = 0.5) gives the same coefficients bit for bit."""
    monkeypatch.setenv(PARALLEL_ENV, "0")
    serial = fem.steady_state(0.5, order=3, spacing=0.3)
    monkeypatch.setenv(PARALLEL_ENV, "1")
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(THREADS[-1])
        par = fem.steady_state(0.5, order=3, spacing=0.3)
    finally:
        numba.set_num_threads(before)
    np.testing.assert_array_equal(par.u, serial.u)
