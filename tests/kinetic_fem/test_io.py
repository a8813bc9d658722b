"""Tests of kinetic_fem.io: meshio export (VTU, XDMF) and exact read-back."""

import json
import math
from dataclasses import replace

import meshio
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from kinetic_fem import RunInfo, VelocityDistribution
from kinetic_fem.io import (
    read_distribution,
    read_time_series,
    sidecar_path,
    write_distribution,
    write_time_series,
)

FORMATS = [".vtu", ".xdmf"]


def assert_identical(a, b):
    """Same arrays bitwise, same metadata (NaN == NaN in RunInfo)."""
    for name in ("v", "values", "raw_moments", "errors", "batch_moments"):
        x, y = getattr(a, name), getattr(b, name)
        if x is None or y is None:
            assert x is None and y is None, name
        else:
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name
    assert (a.method, dict(a.params)) == (b.method, dict(b.params))
    for field in ("converged", "iterations", "message"):
        assert getattr(a.info, field) == getattr(b.info, field)
    assert dict(a.info.extra) == dict(b.info.extra)
    for field in ("residual", "wall_time"):
        x, y = getattr(a.info, field), getattr(b.info, field)
        assert x == y or (math.isnan(x) and math.isnan(y))
    assert set(a.series) == set(b.series)
    for key in a.series:
        assert a.series[key].tobytes() == b.series[key].tobytes(), key


def sampled():
    x = np.random.default_rng(11).normal(size=6000)
    info = RunInfo(converged=True, iterations=120, residual=float("nan"), wall_time=0.125,
                   message="ok", extra={"seed": 11, "n_particles": 6000})
    d = VelocityDistribution.from_samples(x, n_batches=6, bins=40, method="dsmc",
                                          params={"alpha": 0.9, "problem": "heated"},
                                          info=info)
    return replace(d, series={"t": np.linspace(0, 2, 7), "temperature": np.linspace(1, 2, 7)})


def deterministic():
    v = np.linspace(-10, 10, 401)
    return VelocityDistribution.from_values(v, np.exp(-v**2 / 2) * (1 + 0.01 * v**4),
                                            method="fem", params={"alpha": 0.5},
                                            info=RunInfo(iterations=6, residual=3e-13))


@pytest.mark.parametrize("suffix", FORMATS)
@pytest.mark.parametrize("make", [sampled, deterministic])
def test_round_trip_is_exact(tmp_path, suffix, make):
    d = make()
    path = write_distribution(d, tmp_path / f"dist{suffix}")
    assert path.exists() and sidecar_path(path).exists()
    assert_identical(read_distribution(path), d)


@pytest.mark.parametrize("suffix", FORMATS)
def test_mesh_file_is_a_line_mesh_with_point_data(tmp_path, suffix):
    """What a mesh reader (ParaView) sees: nodes at v, P, c, f(c) and error bars."""
    d = sampled()
    path = write_distribution(d, tmp_path / f"dist{suffix}")
    if suffix == ".vtu":
        mesh = meshio.read(path)
        points, point_data = mesh.points, mesh.point_data
        assert mesh.cells[0].type == "line" and len(mesh.cells[0].data) == d.v.size - 1
    else:
        with meshio.xdmf.TimeSeriesReader(path) as reader:
            points, cells = reader.read_points_cells()
            _, point_data, _ = reader.read_data(0)
        assert cells[0].type == "line"
    np.testing.assert_array_equal(points[:, 0], d.v)
    np.testing.assert_array_equal(points[:, 1:], 0.0)
    np.testing.assert_array_equal(point_data["P"], d.values)
    np.testing.assert_array_equal(point_data["f"], d.f_values)
    np.testing.assert_array_equal(point_data["c"], d.c)
    np.testing.assert_array_equal(point_data["P_error"], d.errors)
    np.testing.assert_array_equal(point_data["f_error"], d.f_errors)


@given(arrays(float, st.integers(3, 40), elements=st.floats(1e-300, 1e300)),
       st.sampled_from(FORMATS),
       st.dictionaries(st.text(min_size=1, max_size=8),
                       st.one_of(st.floats(allow_nan=False, allow_infinity=False),
                                 st.integers(-10**6, 10**6), st.text(max_size=8)),
                       max_size=4))
def test_round_trip_property(tmp_path_factory, values, suffix, params):
    """Any positive values over 600 decades and any JSON-able params round-trip exactly."""
    v = np.cumsum(np.linspace(0.5, 1.5, values.size)) - 3.0
    gauss = [1.0, 0.0, 1.0, 0.0, 3.0, 0.0, 15.0, 0.0, 105.0, 0.0, 945.0, 0.0, 10395.0]
    d = VelocityDistribution(v=v, values=values, raw_moments=np.array(gauss),
                             method="prop", params=params)
    path = write_distribution(d, tmp_path_factory.mktemp("io") / f"p{suffix}")
    assert_identical(read_distribution(path), d)


def test_numpy_params_are_stored_as_plain_values(tmp_path):
    d = replace(deterministic(), params={"n_v": np.int64(401), "alpha": np.float32(0.5)})
    back = read_distribution(write_distribution(d, tmp_path / "d.vtu"))
    assert back.params == {"n_v": 401, "alpha": 0.5}


def test_time_series_round_trip(tmp_path):
    v = np.linspace(-6, 6, 121)
    times = np.array([0.0, 0.5, 1.25])
    dists = [VelocityDistribution.from_values(v, np.exp(-v**2 / (2 * (1 + t))))
             for t in times]
    path = write_time_series(tmp_path / "ts.xdmf", times, dists)
    t_back, v_back, values = read_time_series(path)
    np.testing.assert_array_equal(t_back, times)
    np.testing.assert_array_equal(v_back, v)
    np.testing.assert_array_equal(values, np.array([d.values for d in dists]))


def test_bad_input(tmp_path):
    d = deterministic()
    with pytest.raises(ValueError, match=r"suffix must be one of \['.vtu', '.xdmf'\]"):
        write_distribution(d, tmp_path / "d.csv")
    with pytest.raises(TypeError, match="dist must be a VelocityDistribution, got ndarray"):
        write_distribution(np.zeros(3), tmp_path / "d.vtu")
    path = write_distribution(d, tmp_path / "d.vtu")
    side = sidecar_path(path)
    side.write_text(json.dumps({"schema": "other"}))
    with pytest.raises(ValueError, match="not a kinetic_fem.io sidecar"):
        read_distribution(path)
    side.unlink()
    with pytest.raises(FileNotFoundError, match="sidecar"):
        read_distribution(path)
    with pytest.raises(ValueError, match="one distribution per time"):
        write_time_series(tmp_path / "t.xdmf", [0.0, 1.0], [d])
    with pytest.raises(ValueError, match="strictly increasing"):
        write_time_series(tmp_path / "t.xdmf", [1.0, 1.0], [d, d])
    with pytest.raises(ValueError, match=r"written as \.xdmf"):
        write_time_series(tmp_path / "t.vtu", [0.0], [d])
    other = VelocityDistribution.from_values(d.v * 2, d.values)
    with pytest.raises(ValueError, match="share the velocity mesh"):
        write_time_series(tmp_path / "t.xdmf", [0.0, 1.0], [d, other])
