"""The parallel pair kernel (numba prange) is bit-identical to the serial one
(:mod:`kinetic_fem.operators.fem_pair_parallel`): residual, Jacobian, pair and loss
moments, P2 and P3, every kernel, on any number of element blocks and chunks."""

from __future__ import annotations

import numba
import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import SaturatingKernel
from kinetic_fem.model.kernel_base import FAMILY_POWER_LAW
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation
from kinetic_fem.operators.fem_pair_breaks import kernel_graded
from kinetic_fem.operators.fem_pair_fast import collision_constant
from kinetic_fem.operators.fem_pair_parallel import (
    PARALLEL_ENV,
    collision,
    collision_constant_parallel,
    parallel_enabled,
)
from kinetic_fem.solvers.fem import heated as fem

THREADS = sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)})


def _kernel(disc):
    """The kernel as the compiled pair rule takes it (a power law: its exponent)."""
    family, parameter = disc.kernel.numeric
    return float(parameter) if family == FAMILY_POWER_LAW else (family, float(parameter))


def _args(disc, u, jacobian, energy_power):
    verts, dofs = disc.mesh_arrays
    xq, wq, eq = disc.points
    rx, rw = disc.basis.quadrature
    return (verts, dofs, disc.order, u, xq, wq, eq, np.ascontiguousarray(rx[0]), rw,
            disc.alpha, 1.0, jacobian, energy_power, False, _kernel(disc), 0,
            disc.alpha, 0.0, 1.0, 0.8)


def _same(a, b):
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert a[2] == b[2] and a[3] == b[3]


MESHES = {"uniform": np.linspace(-8.0, 8.0, 29),
          "graded": 8.0 * np.sinh(np.linspace(-2.0, 2.0, 25)) / np.sinh(2.0)}


@pytest.mark.parametrize("order", [2, 3])
# the saturating kernel (a kernel passed as (family, parameter)) compiles its own
# specialisation of the opt-in parallel kernel: 80 s in CI, so slow
@pytest.mark.parametrize("gamma", [0.0, 0.5, 1.0, 2.0,
                                   pytest.param(SaturatingKernel(1.0), marks=pytest.mark.slow)])
@pytest.mark.parametrize("alpha, mesh", [(0.6, "uniform"), (0.0, "graded"),
                                         (0.95, "graded")])
def test_two_passes_are_bit_identical(order, gamma, alpha, mesh):
    """Residual, Jacobian and both moments equal bit for bit, full and even sums, with 1,
    2 and 3 element blocks and with chunks of one outer point (gamma = 0.5: graded
    pieces; the saturating kernel: a kernel passed as (family, parameter); a graded
    mesh: blocks of unequal length)."""
    disc = FEMDiscretisation(alpha, MESHES[mesh], order, 2 * order + 1, gamma=gamma)
    x = disc.dof_locations
    u = -0.4 * x**2 + 0.05 * np.cos(x) - 1.0
    graded = bool(kernel_graded(_kernel(disc)))
    assert graded == (gamma == 0.5)
    for mirror in (None, disc.mirror):
        for jacobian in (False, True):
            for power in (-1, 3):
                args = _args(disc, u, jacobian, power)
                common = (args[0], args[1], *args[3:12])  # verts ... with_jacobian
                serial = collision_constant(*common, power, args[14], graded, mirror)
                if power >= 0:
                    assert serial[2] > 0.0 and serial[3] > 0.0
                for blocks in (1, 2, 3):
                    for chunk in (1 << 18, 1):
                        par = collision_constant_parallel(*common, power, args[14], graded,
                                                          blocks, mirror, chunk)
                        _same(par, serial)


def test_collision_runs_the_parallel_kernel_bit_identically():
    """The entry point on numba's threads (2 where available, else the serial kernel on
    one thread) equals the serial kernel bit for bit."""
    disc = FEMDiscretisation(0.6, np.linspace(-8.0, 8.0, 41), 3, 7)
    u = disc.gaussian(1.5)
    before = numba.get_num_threads()
    try:
        for jacobian in (False, True):
            for power in (-1, 3):
                args = _args(disc, u, jacobian, power)
                serial = collision(*args, disc.mirror, parallel=False)
                for threads in THREADS:
                    numba.set_num_threads(threads)
                    _same(collision(*args, disc.mirror, parallel=True), serial)
    finally:
        numba.set_num_threads(before)


def test_the_setting_is_off_by_default(monkeypatch):
    """:data:`PARALLEL_ENV` switches the parallel kernel on; unset, it is off."""
    monkeypatch.delenv(PARALLEL_ENV, raising=False)
    assert not parallel_enabled()
    monkeypatch.setenv(PARALLEL_ENV, "1")
    assert parallel_enabled()
    monkeypatch.setenv(PARALLEL_ENV, "0")
    assert not parallel_enabled()


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


def test_cooling_state_is_bit_identical_with_the_parallel_kernel(monkeypatch):
    """A cooling state (its Newton asks for the pair moments too) is the same bit for
    bit."""
    monkeypatch.setenv(PARALLEL_ENV, "0")
    serial = kf.solve_cooling(0.8)
    monkeypatch.setenv(PARALLEL_ENV, "1")
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(THREADS[-1])
        par = kf.solve_cooling(0.8)
    finally:
        numba.set_num_threads(before)
    np.testing.assert_array_equal(par.values, serial.values)
    assert par.a2 == serial.a2
