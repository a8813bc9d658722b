"""The CLI checks outputs before computing, exports what it computed (issue 28)."""

import time
from pathlib import Path

import numpy as np
import pytest

from kinetic_fem.cli import main


@pytest.mark.parametrize("argv", [
    ["solve-heated", "0.6", "--out"], ["sweep", "--alpha", "0.5", "--out"],
    ["dsmc", "0.6", "-N", "200", "--out"],
])
def test_unwritable_out_is_refused_before_computing(tmp_path, capsys, argv):
    suffix = ".nc" if argv[0] == "sweep" else ".vtu"
    start = time.process_time()
    with pytest.raises(SystemExit) as exit_:
        main([*argv, str(tmp_path / "missing" / f"x{suffix}"), "--quiet"])
    assert exit_.value.code == 2 and time.process_time() - start < 2.0
    assert "does not exist" in capsys.readouterr().err


def test_checkpoint_flag_keeps_the_name(tmp_path):
    ck = tmp_path / "ck.a0.6"
    assert main(["dsmc", "0.6", "-N", "200", "--collisions", "4", "--seed", "1", "-o",
                 "n_batches=2", "--checkpoint", str(ck), "--quiet"]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["ck.a0.6.npz"]


def test_particle_sweep_exports_netcdf(tmp_path):
    xr = pytest.importorskip("xarray")
    out = tmp_path / "d.nc"
    assert main(["sweep", "--method", "dsmc", "--alpha", "0.5", "--particles", "200", "-o",
                 "collisions_per_particle=4", "-o", "n_batches=2", "--workers", "1",
                 "--out", str(out), "--quiet"]) == 0
    with xr.open_dataset(out, engine="scipy") as ds:
        assert int(ds.n_particles.values[0]) == 200 and bool(ds.converged.values.all())


def test_unrepresentable_scale_exits_non_zero(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["solve-heated", "0.6", "--density", "1e300", "--quiet"])
    assert exit_.value.code == 2 and "outside [1e-24" in capsys.readouterr().err


def test_a_failing_export_keeps_the_result(tmp_path):
    from kinetic_fem.cli.parser import save
    from kinetic_fem.distribution import VelocityDistribution

    v = np.linspace(-6, 6, 61)
    dist = VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")
    with pytest.raises(OSError, match="the result is saved in") as err:
        save(dist, tmp_path / "gone" / "x.npz")
    kept = Path(str(err.value).split("saved in ")[1].strip("'"))
    assert np.array_equal(VelocityDistribution.load(kept).values, dist.values)
    kept.unlink()
