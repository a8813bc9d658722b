"""Tests of kinetic_fem.plot: sweep figures without pyplot, saved with Agg."""

import subprocess
import sys

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.plot import new_axes, plot_a2, plot_f, plot_sweep, save_figure
from kinetic_fem.sonine import a2_first_order


@pytest.fixture(scope="module")
def ds():
    return kf.sweep(kf.solve_heated, {"alpha": [0.3, 0.6, 0.9], "density": [1.0, 2.0]},
                    method="spectral", executor="serial")


def test_plot_a2_one_line_per_other_dim_and_theory(ds):
    ax = plot_a2(ds, theory=a2_first_order)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sorted(labels) == ["a2_first_order", "spectral density=1.0", "spectral density=2.0"]
    x, y = ax.get_lines()[0].get_data()
    np.testing.assert_array_equal(y, ds.a2.sel(density=1.0).values)
    with pytest.raises(ValueError, match="not a grid dimension"):
        plot_a2(ds, x="kernel")


def test_plot_a2_error_bars_for_sampled_points(ds):
    noisy = ds.sel(density=1.0).assign(a2_error=ds.a2.sel(density=1.0) * 0 + 0.01)
    ax = plot_a2(noisy, label="dsmc")
    (container,) = ax.containers
    assert container.has_yerr
    segs = container.lines[2][0].get_segments()
    assert [s[1, 1] - s[0, 1] for s in segs] == pytest.approx([0.02] * 3)


def test_plot_f_family_and_saved_file(ds, tmp_path):
    ax = plot_f(ds)
    assert len(ax.get_lines()) == 6 + 1 and ax.get_yscale() == "log"
    path = save_figure(ax.figure, tmp_path / "f.png")
    assert path.stat().st_size > 1000
    fig = plot_sweep(ds, tmp_path / "sweep.png", theory=a2_first_order)
    assert len(fig.axes) == 2 and (tmp_path / "sweep.png").exists()
    axes = new_axes(3)
    assert len(axes) == 3 and axes[0].figure is axes[2].figure


def test_import_and_drawing_select_no_backend():
    code = ("import sys, kinetic_fem as kf, kinetic_fem.plot as p\n"
            "ds = kf.sweep(kf.solve_heated, {'alpha': [0.5, 0.9]}, method='spectral',"
            " executor='serial')\n"
            "p.plot_sweep(ds)\n"
            "print('matplotlib.pyplot' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


# ------------------------------------------------------------------ one result, one line
def _gaussian(scale: float = 1.0, method: str = "exact") -> kf.VelocityDistribution:
    v = np.linspace(-12, 12, 481) * scale
    return kf.VelocityDistribution.from_values(v, np.exp(-v**2 / (2 * scale**2)), method=method,
                                               params={"alpha": 0.5})


def _sampled() -> kf.VelocityDistribution:
    rng = np.random.default_rng(3)
    return kf.VelocityDistribution.from_samples(rng.standard_normal(20000), n_batches=10,
                                                bins=41, method="dsmc")


def test_plot_f_takes_a_distribution_a_list_an_evolution_and_datasets():
    from kinetic_fem.evolution import Evolution

    d = _gaussian()
    ax = plot_f(d)
    c, f = ax.get_lines()[0].get_data()
    np.testing.assert_array_equal(f, d.f_values[d.f_values > 0])
    assert ax.get_yscale() == "log" and ax.get_legend().get_texts()[0].get_text() == \
        "exact alpha=0.5"
    assert len(plot_f([d, _gaussian(2.0)]).get_lines()) == 2 + 1  # and the Gaussian
    assert len(plot_f(d.to_xarray()).get_lines()) == 2
    ev = Evolution([0.0, 1.0], np.stack([d.v, d.v]), np.stack([d.values, d.values]),
                   np.full((2, d.v.size), d.v[1] - d.v[0]), method="test")
    assert len(plot_f(ev).get_lines()) == 3
    assert len(plot_f(ev.to_xarray()).get_lines()) == 3
    with pytest.raises(TypeError, match="VelocityDistribution"):
        plot_f(np.zeros(3))


def test_dist_plot_draws_the_error_band_of_sampled_results_only():
    d = _sampled()
    ax = d.plot()
    assert len(ax.collections) == 1  # the band of one standard error
    band = ax.collections[0].get_paths()[0].vertices[:, 1]
    top = (d.f_values + d.f_errors)[d.f_values > 0]
    assert band.min() >= 0 and band.max() == pytest.approx(top.max())
    assert len(_gaussian().plot().collections) == 0  # no estimate computed: no band
    assert len(d.plot(errors=False).collections) == 0


def test_deterministic_sweep_plots_draw_its_estimates(ds):
    """A deterministic sweep's a2_error (dist.error.a2, issue 29) gives error bars, its
    f_error bands; a deterministic result draws its estimate's band when asked."""
    line = ds.sel(density=1.0)
    ax = plot_a2(line)
    (container,) = ax.containers
    assert container.has_yerr
    segs = container.lines[2][0].get_segments()
    assert [s[1, 1] - s[0, 1] for s in segs] == pytest.approx(2 * line.a2_error.values)
    assert np.all(line.a2_error.values > 0)
    assert len(plot_f(line).collections) == 3  # one band per point
    d = kf.solve_heated(0.6, method="spectral")
    assert len(d.plot(errors=True).collections) == 1
