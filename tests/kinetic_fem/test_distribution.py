"""Tests of kinetic_fem.distribution: the result type and its observables.

Known distributions (moments in closed form):

* Gaussian of temperature T: all Sonine coefficients a_p = 0 and effective
  exponent n(c) = 2 (ln P is exactly quadratic).
* Laplace P = exp(-|v|)/2: <v^2k> = (2k)!, so T = 2 and a2 = 24/(3*4) - 1 = 1.
* Uniform on [-a, a]: <v^k> = a^k/(k+1) (even k), a2 = (1/5)/(3/9) - 1 = -2/5.
* Two Gaussians of width s at +-1: T = 1 + s^2, <v^4> = 1 + 6 s^2 + 3 s^4.
* exp(-|v|^k): n(c) = k at every c > 0.
"""

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from kinetic_fem.distribution import MAX_MOMENT, RunInfo, VelocityDistribution


def gaussian(temperature=1.0, mean=0.0, n_v=1201, cutoff=12.0, **kwargs):
    s = math.sqrt(temperature)
    v = np.linspace(mean - cutoff * s, mean + cutoff * s, n_v)
    return VelocityDistribution.from_values(v, np.exp(-((v - mean) ** 2) / (2 * temperature)),
                                            **kwargs)


def info_equal(a: RunInfo, b: RunInfo) -> bool:
    """RunInfo equality with NaN == NaN."""
    same = [a.converged == b.converged, a.iterations == b.iterations,
            a.message == b.message, dict(a.extra) == dict(b.extra)]
    for x, y in ((a.residual, b.residual), (a.wall_time, b.wall_time)):
        same.append(x == y or (math.isnan(x) and math.isnan(y)))
    return all(same)


def assert_identical(a: VelocityDistribution, b: VelocityDistribution) -> None:
    """Arrays equal bitwise (dtype and shape too), metadata equal."""
    for name in ("v", "values", "raw_moments", "errors", "batch_moments"):
        x, y = getattr(a, name), getattr(b, name)
        if x is None or y is None:
            assert x is None and y is None, name
            continue
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), name
    assert a.method == b.method
    assert dict(a.params) == dict(b.params)
    assert info_equal(a.info, b.info)
    assert set(a.series) == set(b.series)
    for key in a.series:
        assert a.series[key].tobytes() == b.series[key].tobytes(), key


temperatures = st.floats(1e-3, 1e3)


@given(temperatures, st.floats(-5, 5))
def test_gaussian_has_no_sonine_corrections(temperature, mean):
    """a_p = 0 for p = 2..6, a_0 = 1, a_1 = 0, at any temperature and mean.

    Central moments come from raw moments about v = 0, so a_p carries the round-off of
    moments of order 2p of a distribution whose mean lies |mean| thermal speeds away:
    about eps (1 + |mean|)^(2p) (seen: 1.5e-8 for p = 6, |mean| = 5, where that scale is
    4.8e-7; 5e-15 at mean = 0)."""
    d = gaussian(temperature, mean * math.sqrt(temperature))
    assert d.temperature == pytest.approx(temperature, rel=1e-12)
    assert d.mean == pytest.approx(mean * math.sqrt(temperature),
                                   abs=1e-10 * math.sqrt(temperature))
    assert d.sonine_coefficient(0) == pytest.approx(1.0, abs=1e-12)
    for p in range(1, 7):
        roundoff = 1e-13 + 4 * np.finfo(float).eps * (1.0 + abs(mean)) ** (2 * p)
        assert abs(d.sonine_coefficient(p)) < roundoff, p
    assert abs(d.a2) < 1e-10


@given(temperatures)
def test_gaussian_effective_exponent_is_two(temperature):
    d = gaussian(temperature)
    c = np.linspace(0.2, 8.0, 40)
    np.testing.assert_allclose(d.effective_exponent(c), 2.0, atol=1e-6)
    # outside the data: NaN, never an extrapolation
    assert np.isnan(d.effective_exponent([20.0])).all()


@given(temperatures)
def test_gaussian_f_is_the_unit_gaussian(temperature):
    d = gaussian(temperature)
    c = np.linspace(-6, 6, 25)
    np.testing.assert_allclose(d.f(c), np.exp(-c**2 / 2) / math.sqrt(2 * math.pi), rtol=1e-7)
    np.testing.assert_allclose(d.f_values, np.exp(-d.c**2 / 2) / math.sqrt(2 * math.pi),
                               rtol=1e-10)


@given(st.floats(1.0, 4.0))
def test_effective_exponent_of_stretched_exponential(k):
    """P = exp(-|v|^k) has n(v) = k: computed stably from the spline of ln P."""
    v = np.linspace(-10, 10, 4001)
    d = VelocityDistribution.from_values(v, np.exp(-np.abs(v) ** k))
    x = np.linspace(0.5, 4.0, 15)
    n = d.effective_exponent(x / math.sqrt(d.temperature))
    np.testing.assert_allclose(n, k, atol=1e-6)


def test_effective_exponent_in_a_tail_of_200_decades():
    """No cancellation: n = 3/2 where P ~ 1e-200 (differences of P would give 0/0)."""
    v = np.linspace(-400, 400, 8001)
    d = VelocityDistribution.from_values(v, np.exp(-np.abs(v) ** 1.5))
    x = np.array([30.0, 35.0])  # ln P = -164, -207
    assert d.pdf(x).min() < 1e-70
    np.testing.assert_allclose(d.effective_exponent(x / math.sqrt(d.temperature)), 1.5,
                               atol=1e-8)


def test_laplace_moments():
    """<v^2k> = (2k)! up to k = 6 by quadrature; a2 = 1."""
    v = np.linspace(-80, 80, 16001)  # v = 0 is a Simpson panel boundary (the kink)
    d = VelocityDistribution.from_values(v, 0.5 * np.exp(-np.abs(v)))
    for k in range(0, MAX_MOMENT + 1, 2):
        assert d.moment(k) == pytest.approx(math.factorial(k), rel=1e-6), k
    assert d.temperature == pytest.approx(2.0, rel=1e-9)
    assert d.a2 == pytest.approx(1.0, rel=1e-6)


def test_uniform_moments():
    a = 1.7
    v = np.linspace(-a, a, 2001)
    d = VelocityDistribution.from_values(v, np.ones_like(v))
    for k in range(0, MAX_MOMENT + 1, 2):
        assert d.moment(k) == pytest.approx(a**k / (k + 1), rel=1e-10), k
    assert d.a2 == pytest.approx(-0.4, rel=1e-10)


@given(st.floats(0.02, 0.3))
def test_two_narrow_gaussians(s):
    v = np.linspace(-1 - 10 * s, 1 + 10 * s, 4001)
    p = np.exp(-(v - 1) ** 2 / (2 * s * s)) + np.exp(-(v + 1) ** 2 / (2 * s * s))
    d = VelocityDistribution.from_values(v, p)
    assert d.temperature == pytest.approx(1 + s * s, rel=1e-10)
    assert d.moment(4) == pytest.approx(1 + 6 * s**2 + 3 * s**4, rel=1e-10)
    assert d.a2 == pytest.approx((1 + 6 * s**2 + 3 * s**4) / (3 * (1 + s * s) ** 2) - 1,
                                 abs=1e-10)


@given(st.integers(0, 2**32 - 1), st.integers(1, 20))
def test_sample_moments_come_from_the_samples(seed, n_batches):
    """Moments of from_samples are those of the samples, not of the histogram."""
    x = np.random.default_rng(seed).exponential(size=2000) - 1.0
    d = VelocityDistribution.from_samples(x, n_batches=n_batches, bins=7)
    expected = np.array([np.mean(x**k) for k in range(MAX_MOMENT + 1)])
    np.testing.assert_allclose(d.raw_moments, expected, rtol=1e-9)
    assert d.temperature == pytest.approx(np.var(x), rel=1e-9)
    assert d.mean == pytest.approx(np.mean(x), abs=1e-12)
    assert (d.batch_moments is None) == (n_batches == 1)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_sampled_uniform_a2_within_error(seed):
    """Uniform samples: a2 = -2/5 within 4 standard errors; errors shrink as 1/sqrt(N)."""
    x = np.random.default_rng(seed).uniform(-1, 1, size=200_000)
    d = VelocityDistribution.from_samples(x, n_batches=20, bins=50)
    assert 0 < d.a2_error < 5e-3
    assert abs(d.a2 + 0.4) < 4 * d.a2_error
    # histogram: density 1/2 with errors from the batch spread
    assert d.errors is not None and d.errors.shape == d.values.shape
    assert np.all(np.abs(d.values - 0.5) < 5 * d.errors + 1e-12)
    # the error of the temperature from the same batches
    t_err = d.observable_error(lambda b: b.temperature)
    assert abs(d.temperature - 1 / 3) < 4 * t_err


def test_from_batches_pools_counts():
    edges = np.array([-1.0, 0.0, 1.0])
    counts = np.array([[1.0, 3.0], [2.0, 2.0]])
    x = [np.array([-0.5, 0.5, 0.5, 0.5]), np.array([-0.5, -0.5, 0.5, 0.5])]
    sums = np.array([[np.sum(b**k) for k in range(MAX_MOMENT + 1)] for b in x])
    d = VelocityDistribution.from_batches(edges, counts, sums, method="test")
    np.testing.assert_allclose(d.values, [3 / 8, 5 / 8])
    np.testing.assert_allclose(d.v, [-0.5, 0.5])
    dens = counts / 4.0
    np.testing.assert_allclose(d.errors, dens.std(axis=0, ddof=1) / math.sqrt(2))
    assert d.mean == pytest.approx(0.125)  # pooled: (1.0 + 0.0) / 8 samples


def test_from_batches_errors():
    edges = np.linspace(-1, 1, 5)
    good = np.zeros((2, MAX_MOMENT + 1))
    good[:, 0] = 1
    with pytest.raises(ValueError, match="one column per bin"):
        VelocityDistribution.from_batches(edges, np.ones((2, 3)), good)
    with pytest.raises(ValueError, match=r"power_sums must have shape \(n_batches, 13\)"):
        VelocityDistribution.from_batches(edges, np.ones((2, 4)), good[:, :5])
    with pytest.raises(ValueError, match="at least one sample"):
        VelocityDistribution.from_batches(edges, np.ones((2, 4)), np.zeros((2, 13)))
    bad = good.copy()
    bad[0, 3] = np.nan
    with pytest.raises(ValueError, match="power_sums contains 1 non-finite"):
        VelocityDistribution.from_batches(edges, np.ones((2, 4)), bad)
    with pytest.raises(ValueError, match="bin_edges contains"):
        VelocityDistribution.from_batches([0.0, np.inf], np.ones((2, 1)), good)


@given(st.floats(1e-2, 1e2), st.sampled_from(["gauss", "laplace", "samples"]))
def test_rescaling_invariance(scale, kind):
    """v -> s v, P -> P/s leaves f(c), a_p and n(c) unchanged; T scales as s^2."""
    if kind == "gauss":
        d = gaussian(0.7)
    elif kind == "laplace":
        v = np.linspace(-30, 30, 3001)
        d = VelocityDistribution.from_values(v, np.exp(-np.abs(v)))
    else:
        x = np.random.default_rng(5).normal(size=5000)
        d = VelocityDistribution.from_samples(x, n_batches=5, bins=30)
    r = d.rescaled(scale)
    assert r.temperature == pytest.approx(scale**2 * d.temperature, rel=1e-12)
    for p in range(2, 7):
        assert r.sonine_coefficient(p) == pytest.approx(d.sonine_coefficient(p), rel=1e-8,
                                                        abs=1e-10)
    np.testing.assert_allclose(r.c, d.c, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r.f_values, d.f_values, rtol=1e-12)
    c = np.linspace(-2.5, 2.5, 11)
    np.testing.assert_allclose(r.f(c), d.f(c), rtol=1e-9, atol=1e-300)
    if kind == "samples":
        assert r.a2_error == pytest.approx(d.a2_error, rel=1e-8)
        np.testing.assert_allclose(r.f_errors, d.f_errors, rtol=1e-12)


@given(st.floats(0.1, 10.0))
def test_rescaled_equals_solution_on_scaled_mesh(scale):
    """rescaled() agrees with building the distribution on the scaled mesh."""
    v = np.linspace(-12, 12, 1201)
    p = np.exp(-v**2 / 2) * (1 + 0.1 * v**2)
    a = VelocityDistribution.from_values(v, p).rescaled(scale)
    b = VelocityDistribution.from_values(scale * v, p / scale)
    # odd moments vanish up to round-off of the largest one
    np.testing.assert_allclose(a.raw_moments, b.raw_moments, rtol=1e-10,
                               atol=1e-14 * np.abs(b.raw_moments).max())
    assert a.compare(b).f_rel_max < 1e-10


def test_save_load_round_trip(tmp_path):
    x = np.random.default_rng(3).normal(size=4000)
    info = RunInfo(converged=False, iterations=17, residual=1.25e-9, wall_time=float("nan"),
                   message="stopped", extra={"n_v": 401, "seeds": [1, 2]})
    d = VelocityDistribution.from_samples(x, n_batches=4, bins=20, method="dsmc",
                                          params={"alpha": 0.9, "problem": "heated"},
                                          info=info)
    d = replace(d, series={"t": np.linspace(0, 1, 5), "a2": np.full(5, -0.1)})
    path = d.save(tmp_path / "run")
    assert path.suffix == ".npz"
    assert_identical(VelocityDistribution.load(path), d)
    g = gaussian(2.0, method="fem")
    assert_identical(VelocityDistribution.load(g.save(tmp_path / "g.npz")), g)


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=3,
                max_size=30),
       st.dictionaries(st.sampled_from(["alpha", "density", "n_v"]),
                       st.floats(allow_nan=False, allow_infinity=False), max_size=3))
def test_save_load_round_trip_property(tmp_path_factory, values, params):
    """Any finite values (also negative: the type does not judge them) round-trip exactly."""
    v = np.arange(len(values), dtype=float)
    arr = np.abs(np.array(values)) + 1e-300
    d = VelocityDistribution(v=v, values=arr, raw_moments=np.arange(MAX_MOMENT + 1.0),
                             params=params, method="m")
    path = d.save(tmp_path_factory.mktemp("rt") / "d.npz")
    assert_identical(VelocityDistribution.load(path), d)


def test_compare():
    g1 = gaussian(1.0)
    g2 = gaussian(4.0, n_v=801)
    cmp = g1.compare(g2)
    assert cmp.temperature_rel == pytest.approx(0.75, rel=1e-10)
    assert cmp.a2_abs < 1e-10
    assert cmp.f_rel_max < 1e-6  # same shape: f(c) agree
    v = np.linspace(-40, 40, 8001)
    lap = VelocityDistribution.from_values(v, np.exp(-np.sqrt(2) * np.abs(v)))  # T = 1
    cmp = g1.compare(lap, c_max=3.0)
    assert cmp.a2_abs == pytest.approx(1.0, rel=1e-5)
    assert cmp.temperature_rel < 1e-6
    assert cmp.c_max == 3.0
    # f_rel_max at c = 0: Gaussian 1/sqrt(2 pi) against Laplace 1/sqrt(2)
    assert cmp.f_rel_max >= abs(1 / math.sqrt(2 * math.pi) * math.sqrt(2) - 1)


def test_pdf_interpolates_in_log_and_is_zero_outside():
    d = gaussian(1.0, n_v=241)
    v = np.array([-13.0, -3.33, 0.123, 7.77, 13.0])
    p = d.pdf(v)
    assert p[0] == 0 and p[-1] == 0
    np.testing.assert_allclose(p[1:-1], np.exp(-v[1:-1] ** 2 / 2) / math.sqrt(2 * math.pi),
                               rtol=1e-9)


@pytest.mark.parametrize("v, values, match", [
    ([0.0, 1.0], [1.0, 1.0], "at least 3 strictly increasing"),
    ([0.0, 2.0, 1.0], [1.0, 1.0, 1.0], "at least 3 strictly increasing"),
    ([0.0, 1.0, 2.0], [1.0, 1.0], "differ in shape"),
    ([0.0, 1.0, np.nan], [1.0, 1.0, 1.0], "v contains 1 non-finite"),
    ([0.0, 1.0, 2.0], [1.0, np.inf, 1.0], "values contains 1 non-finite"),
    ([0.0, 1.0, 2.0], [0.0, 0.0, 0.0], "non-positive mass"),
    ([[0.0, 1.0, 2.0]], [[1.0, 1.0, 1.0]], "1-d array"),
])
def test_from_values_bad_input(v, values, match):
    with pytest.raises(ValueError, match=match):
        VelocityDistribution.from_values(v, values)


def test_bad_orders_and_samples():
    d = gaussian()
    with pytest.raises(ValueError, match=r"moment order must be in 0..12, got 13"):
        d.moment(13)
    with pytest.raises(ValueError, match=r"Sonine order must be in 0..6, got 7"):
        d.sonine_coefficient(7)
    with pytest.raises(ValueError, match="need at least n_batches=10 samples, got 5"):
        VelocityDistribution.from_samples(np.zeros(5))
    with pytest.raises(ValueError, match="samples contains"):
        VelocityDistribution.from_samples([0.0, np.nan] * 10)
    assert math.isnan(d.a2_error)  # deterministic: no error bars
    assert d.errors is None and d.f_errors is None


def test_explicit_weights_give_exact_moments_for_the_discretisation():
    """With the solver's own weights, moments are those of its quadrature."""
    v = np.linspace(-1, 1, 5)
    w = np.array([0.25, 0.5, 0.5, 0.5, 0.25])  # trapezoid
    d = VelocityDistribution.from_values(v, np.ones(5), weights=w)
    assert d.raw_moments[0] == 1.0
    assert d.temperature == pytest.approx(np.sum(w * v**2) / np.sum(w), rel=1e-14)
