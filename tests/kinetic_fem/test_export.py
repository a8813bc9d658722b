"""Tests of kinetic_fem.export: results as xarray Datasets and Jupyter HTML tables."""

import json

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.evolution import Evolution


@pytest.fixture
def sampled():
    rng = np.random.default_rng(5)
    return kf.VelocityDistribution.from_samples(rng.standard_normal(20000), n_batches=10,
                                                bins=41, method="dsmc", params={"alpha": 0.9})


def test_distribution_to_xarray_holds_the_nodes_and_observables(sampled):
    ds = sampled.to_xarray()
    np.testing.assert_array_equal(ds.v.values, sampled.v)
    np.testing.assert_array_equal(ds.f.values, sampled.f_values)
    np.testing.assert_array_equal(ds.f_error.values, sampled.f_errors)
    np.testing.assert_array_equal(ds.c.values, sampled.c)
    assert float(ds.T) == sampled.temperature and float(ds.a2) == sampled.a2
    assert float(ds.a2_error) == sampled.a2_error
    assert float(ds.sonine.sel(p=4)) == sampled.sonine_coefficient(4)
    assert ds.attrs["method"] == "dsmc" and json.loads(ds.attrs["params"]) == {"alpha": 0.9}


def test_deterministic_dataset_has_no_error_variables():
    v = np.linspace(-10, 10, 201)
    ds = kf.VelocityDistribution.from_values(v, np.exp(-v**2 / 2)).to_xarray()
    assert "f_error" not in ds and np.isnan(float(ds.a2_error)) and np.isnan(float(ds.zeta))


def test_evolution_to_xarray_and_html():
    v = np.linspace(-8, 8, 161)
    grid = np.stack([v, 2 * v])
    values = np.stack([np.exp(-v**2 / 2), np.exp(-v**2 / 8) / 2]) / np.sqrt(2 * np.pi)
    ev = Evolution([0.0, 1.0], grid, values, np.stack([np.full(161, 0.1), np.full(161, 0.2)]),
                   method="test", series={"zeta": [0.1, 0.2]})
    ds = ev.to_xarray()
    np.testing.assert_array_equal(ds["T"].values, ev.temperature)
    np.testing.assert_array_equal(ds.v.values, ev.grid)
    np.testing.assert_array_equal(ds.zeta.values, [0.1, 0.2])
    np.testing.assert_allclose(ds.f.values[1], ev[1].f_values)
    assert ds.sonine.shape == (2, 5)
    text = ev._repr_html_()
    assert text.count("<tr>") == 5 + 1 + 2 and "test" in text


def test_distribution_html_escapes_and_shows_the_standard_error(sampled):
    text = sampled._repr_html_()
    assert f"{sampled.a2:.6g} ± " in text and "standard error" in text
    odd = kf.VelocityDistribution.from_values(np.linspace(-5, 5, 51),
                                              np.exp(-np.linspace(-5, 5, 51)**2),
                                              params={"law": "<b>"})
    assert "&lt;b&gt;" in odd._repr_html_() and "<b>" not in odd._repr_html_().split(
        "</caption>")[1]
