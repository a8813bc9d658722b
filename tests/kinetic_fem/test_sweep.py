"""Tests of kinetic_fem.sweep: grid points, seeds, persistence, executors, Dataset."""

import logging
import os
import signal
import subprocess
import sys
import textwrap
import time
from concurrent.futures import ProcessPoolExecutor
from types import SimpleNamespace

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem import VelocityDistribution
from kinetic_fem.sweep import grid_points, point_filename, point_key, point_seed, sweep

CALLS: list[dict] = []


def sampled_gauss(alpha, *, seed, n=4000, width=1.0):
    """A toy stochastic 'method': Gaussian samples of variance width/alpha from ``seed``."""
    CALLS.append({"alpha": alpha, "seed": seed})
    rng = np.random.default_rng(seed)
    x = rng.normal(scale=np.sqrt(width / alpha), size=n)
    return VelocityDistribution.from_samples(x, n_batches=8, bins=np.linspace(-8, 8, 81),
                                             method="toy")


def fails_at_half(alpha, *, seed):
    if alpha == 0.5:
        raise RuntimeError("no convergence at 0.5")
    return sampled_gauss(alpha, seed=seed)


def fake_run(alpha):
    """Duck-typed particle run: its own temperature, a2 and collision count are used."""
    dist = kf.solve_heated(alpha, method="spectral")
    return SimpleNamespace(distribution=dist, a2=0.25, a2_error=0.01, temperature=3.0,
                           n_collisions=12345)


def without_wall_time(ds):
    return ds.drop_vars("wall_time").assign_attrs(store=None)


def test_grid_points_outer_product_and_validation():
    coords, points = grid_points({"alpha": [0.3, 0.6, 0.9], "kernel": [0, 1],
                                  "method": "fem"})
    assert len(points) == 6 and points[0] == {"alpha": 0.3, "kernel": 0, "method": "fem"}
    assert list(coords["method"]) == ["fem"]
    for bad, err in [({}, TypeError), ({"alpha": []}, ValueError),
                     ({"alpha": [0.5, 0.5]}, ValueError), ({"a b": [1]}, ValueError),
                     ({"alpha": [object()]}, TypeError)]:
        with pytest.raises(err):
            grid_points(bad)
    assert point_key({"b": np.float64(0.1), "a": np.int64(2)}) == '{"a": 2, "b": 0.1}'
    assert point_seed({"alpha": 0.3}) != point_seed({"alpha": 0.30000000000000004})


def test_deterministic_sweep_equals_direct_solves():
    ds = sweep(kf.solve_heated, {"alpha": [0.4, 0.8], "density": [1.0, 2.0]},
               method="spectral", executor="serial")
    assert ds.a2.dims == ("alpha", "density") and ds.f.dims == ("alpha", "density", "c")
    assert ds.sonine.dims == ("alpha", "density", "p")
    d = kf.solve_heated(0.8, density=2.0, method="spectral")
    point = ds.sel(alpha=0.8, density=2.0)
    # rel 1e-12: run-to-run round-off of the solver (the sweep itself copies values; bit
    # identity across executors is tested with seeded DSMC below)
    assert float(point.T) == pytest.approx(d.temperature, rel=1e-12)
    assert float(point.a2) == pytest.approx(d.a2, rel=1e-12)
    assert float(point.sonine.sel(p=3)) == pytest.approx(d.sonine_coefficient(3), rel=1e-12)
    np.testing.assert_allclose(point.f, d.f(ds.c.values), rtol=1e-12, atol=0)
    assert bool(ds.converged.all()) and "seed" not in ds
    # deterministic methods: the a posteriori estimate dist.error (issue 29)
    assert float(point.a2_error) == pytest.approx(d.error.a2, rel=1e-9)
    assert bool((ds.a2_error > 0).all()) and bool((ds.T_error > 0).all())
    assert ds.attrs["function"] == "kinetic_fem.solve.solve_heated"
    assert ds.attrs["method"] == "spectral" and ds.attrs["fixed_method"] == "spectral"


def test_cooling_sweep_has_zeta():
    ds = sweep(kf.solve_cooling, {"alpha": [0.6, 0.9]}, method="spectral", order=4,
               executor="serial")
    # rel 1e-13: the Sonine Newton solve's own run-to-run round-off (its first call in a
    # process can differ from later ones in the last bit)
    assert float(ds.zeta.sel(alpha=0.6)) == pytest.approx(kf.solve_cooling(
        0.6, method="spectral", order=4).info.extra["zeta"], rel=1e-13)


def test_particle_runs_are_duck_typed():
    ds = sweep(fake_run, {"alpha": [0.6]}, executor="serial")
    assert float(ds.a2[0]) == 0.25 and float(ds.T[0]) == 3.0
    assert float(ds.n_collisions[0]) == 12345 and np.isnan(ds.T_error[0])
    with pytest.raises(TypeError, match="must return a VelocityDistribution"):
        sweep(lambda alpha: 1.0, {"alpha": [0.5]}, executor="serial")


def test_seeds_come_from_the_point_and_the_root():
    ds = sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, executor="serial")
    assert int(ds.seed.sel(alpha=0.5)) == point_seed({"alpha": 0.5})
    assert float(ds.a2_error[0]) > 0 and np.isfinite(ds.T_error).all()
    # the variance of 4000 normal samples has relative standard error sqrt(2/4000) = 2.2 %
    assert float(ds.T.sel(alpha=0.5)) == pytest.approx(2.0, rel=0.11)  # 5 standard errors
    rooted = sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, executor="serial", seed=7)
    assert int(rooted.seed.sel(alpha=0.5)) == point_seed({"alpha": 0.5}, root=7)
    assert float(rooted.T[0]) != float(ds.T[0])
    given = sweep(sampled_gauss, {"alpha": [0.5], "seed": [1, 2]}, executor="serial")
    assert "seed" in given.dims and given.T.sel(seed=1).item() == sampled_gauss(
        0.5, seed=1).temperature


def test_replica_dimension_labels_independent_seeds():
    ds = sweep(sampled_gauss, {"alpha": [0.5, 1.0], "replica": range(3)}, executor="serial")
    assert ds.T.dims == ("alpha", "replica")
    assert int(ds.seed.sel(alpha=0.5, replica=2)) == point_seed({"alpha": 0.5, "replica": 2})
    assert len(set(ds.seed.values.ravel())) == 6 and len(set(ds.T.values.ravel())) == 6
    with pytest.raises(ValueError, match="labels independent runs"):
        sweep(kf.solve_heated, {"alpha": [0.5], "replica": [0, 1]}, method="spectral",
              executor="serial")


def test_bad_arguments_are_named():
    with pytest.raises(TypeError, match=r"no argument\(s\) \['widht'\]; valid names"):
        sweep(sampled_gauss, {"alpha": [0.5]}, executor="serial", widht=2.0)
    with pytest.raises(ValueError, match="both in the grid and as fixed"):
        sweep(sampled_gauss, {"alpha": [0.5]}, executor="serial", alpha=0.5)
    with pytest.raises(TypeError, match="executor must be"):
        sweep(sampled_gauss, {"alpha": [0.5]}, executor="threads")
    with pytest.raises(TypeError, match="module-level function"):
        sweep(lambda alpha: sampled_gauss(alpha, seed=1), {"alpha": [0.5]})


def test_store_resumes_and_returns_complete_store_at_once(tmp_path):
    store = tmp_path / "s"
    grid = {"alpha": [0.25, 0.5, 1.0]}
    CALLS.clear()
    first = sweep(sampled_gauss, grid, store=store, executor="serial")
    assert len(CALLS) == 3 and len(list(store.glob("point-*.nc"))) == 3
    CALLS.clear()
    again = sweep(sampled_gauss, grid, store=store, executor="serial")
    assert CALLS == [] and again.identical(first)
    next(iter(sorted(store.glob("point-*.nc")))).unlink()
    resumed = sweep(sampled_gauss, grid, store=store, executor="serial")
    assert len(CALLS) == 1 and without_wall_time(resumed).identical(without_wall_time(first))
    wider = sweep(sampled_gauss, {"alpha": [0.25, 0.5, 1.0, 2.0]}, store=store,
                  executor="serial")
    assert len(CALLS) == 2 and float(wider.T.sel(alpha=0.5)) == float(first.T.sel(alpha=0.5))
    with pytest.raises(ValueError, match="holds another sweep"):
        sweep(sampled_gauss, grid, store=store, executor="serial", width=2.0)


@pytest.mark.parametrize("damage", ["truncate", "flip"])
def test_damaged_point_file_is_recomputed(tmp_path, caplog, damage):
    store = tmp_path / "s"
    first = sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, store=store, executor="serial")
    path = store / point_filename(point_key({"alpha": 1.0}))
    raw = path.read_bytes()
    if damage == "truncate":
        path.write_bytes(raw[: len(raw) // 2])
    else:  # the last bit of the last float flipped: the file parses, the checksum catches it
        path.write_bytes(raw[:-1] + bytes([raw[-1] ^ 1]))
    CALLS.clear()
    with caplog.at_level(logging.WARNING, logger="kinetic_fem.sweep.store"):
        again = sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, store=store, executor="serial")
    assert "damaged" in caplog.text and CALLS == [{"alpha": 1.0, "seed": point_seed(
        {"alpha": 1.0})}]
    assert without_wall_time(again).identical(without_wall_time(first))


def test_progress_bar_goes_to_stderr(capsys):
    sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, executor="serial", progress=True)
    err = capsys.readouterr().err
    assert "sweep: 100%" in err and "2/2" in err


def test_progress_default_is_quiet_when_not_interactive(capsys):
    """progress=None (the default): no bar when stderr is not a terminal (pytest captures it)."""
    sweep(sampled_gauss, {"alpha": [0.5, 1.0]}, executor="serial")
    assert "sweep" not in capsys.readouterr().err


def test_failure_keeps_finished_points(tmp_path):
    store = tmp_path / "s"
    with pytest.raises(RuntimeError, match="no convergence") as info:
        sweep(fails_at_half, {"alpha": [0.25, 0.5, 1.0]}, store=store, executor="serial")
    if hasattr(info.value, "__notes__"):
        assert "in sweep point {'alpha': 0.5}" in info.value.__notes__
    assert len(list(store.glob("point-*.nc"))) == 1


def _dsmc_sweep(executor):
    from particles import dsmc

    return sweep(dsmc.simulate_heated, {"alpha": [0.5, 0.8], "n_particles": [200, 300]},
                 executor=executor, collisions_per_particle=8, n_batches=4, relax=2.0)


def test_results_identical_for_every_executor():
    """DSMC runs seeded from the point: serial, 2 processes and dask agree bit for bit."""
    distributed = pytest.importorskip("distributed")
    serial = without_wall_time(_dsmc_sweep("serial"))
    assert np.isfinite(serial.a2_error).all() and (serial.n_collisions > 0).all()
    with ProcessPoolExecutor(2) as pool:
        assert without_wall_time(_dsmc_sweep(pool)).identical(serial)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        assert without_wall_time(_dsmc_sweep(client)).identical(serial)


def test_default_process_pool():
    from particles import dsmc

    grid, fixed = {"alpha": [0.5, 0.7]}, {"n_particles": 200, "collisions_per_particle": 8,
                                          "n_batches": 4, "relax": 2.0}
    ds = sweep(dsmc.simulate_heated, grid, **fixed)
    assert without_wall_time(ds).identical(without_wall_time(
        sweep(dsmc.simulate_heated, grid, executor="serial", **fixed)))


_SCRIPT = """
import sys, time
sys.path.insert(0, {here!r})
import sweeptoy
from kinetic_fem.sweep import sweep
sweep(sweeptoy.slow_gauss, {{"alpha": {alphas!r}}}, store={store!r}, executor="serial",
      log={log!r}, delay={delay!r})
"""

_TOY = '''
import time
import numpy as np
from kinetic_fem import VelocityDistribution

def slow_gauss(alpha, *, seed, log, delay):
    with open(log, "a") as fh:
        fh.write(f"{alpha}\\n")
    time.sleep(delay)
    x = np.random.default_rng(seed).normal(scale=alpha, size=2000)
    return VelocityDistribution.from_samples(x, n_batches=4, bins=np.linspace(-5, 5, 41))
'''


def test_killed_sweep_resumes_with_missing_points_only(tmp_path):
    """SIGKILL a sweep process after some points; the rerun computes only the rest."""
    (tmp_path / "sweeptoy.py").write_text(_TOY)
    store, log = tmp_path / "store", tmp_path / "calls.log"
    alphas = [0.5 + 0.1 * k for k in range(10)]
    script = _SCRIPT.format(here=str(tmp_path), alphas=alphas, store=str(store),
                            log=str(log), delay=0.3)
    proc = subprocess.Popen([sys.executable, "-c", textwrap.dedent(script)])
    try:
        deadline = time.monotonic() + 60
        while len(list(store.glob("point-*.nc"))) < 3:
            assert proc.poll() is None, "the sweep ended before it could be killed"
            assert time.monotonic() < deadline
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait()
    done = len(list(store.glob("point-*.nc")))
    assert 3 <= done < len(alphas)
    assert len(log.read_text().split()) in (done, done + 1)  # at most one point lost
    sys.path.insert(0, str(tmp_path))
    try:
        import sweeptoy

        log.unlink()
        ds = sweep(sweeptoy.slow_gauss, {"alpha": alphas}, store=store, executor="serial",
                   log=str(log), delay=0.3)
        assert len(log.read_text().split()) == len(alphas) - done
        fresh = sweep(sweeptoy.slow_gauss, {"alpha": alphas}, executor="serial",
                      log=str(tmp_path / "fresh.log"), delay=0.0)
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop("sweeptoy", None)
    assert np.array_equal(ds.a2.values, fresh.a2.values)
    assert np.array_equal(ds.f.values, fresh.f.values, equal_nan=True)
