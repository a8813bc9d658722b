"""Checkpoints and outputs lose nothing (issue 28): the path given is the path written,
a file that is not a checkpoint of the run is never overwritten, and an edited, damaged
or foreign checkpoint is refused before any work."""

import numpy as np
import pytest

from kinetic_fem import VelocityDistribution
from kinetic_fem.exceptions import FileFormatError
from particles import dsmc, md
from particles.sampling import load_checkpoint

DSMC_KW = dict(seed=3, collisions_per_particle=6, n_batches=2, relax=1.0)
MD_KW = dict(seed=1, collisions_per_particle=6.0, n_batches=2)


def _gauss():
    v = np.linspace(-6, 6, 61)
    return VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")


def test_checkpoint_path_is_used_as_given(tmp_path):
    a, b = tmp_path / "ck_alpha0.6", tmp_path / "ck_alpha0.7"
    dsmc.simulate_heated(0.6, 200, checkpoint=a, **DSMC_KW)
    dsmc.simulate_heated(0.7, 200, checkpoint=b, **DSMC_KW)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ck_alpha0.6.npz", "ck_alpha0.7.npz"]
    md.simulate_heated(0.9, 30, checkpoint=tmp_path / "m.run.npz", **MD_KW)
    assert (tmp_path / "m.run.npz").exists()


def test_checkpoint_never_overwrites_another_file(tmp_path):
    saved = _gauss().save(tmp_path / "alpha0.6.dsmc")  # alpha0.6.dsmc.npz
    before = saved.read_bytes()
    with pytest.raises(FileFormatError, match="left untouched"):
        dsmc.simulate_heated(0.6, 200, checkpoint=saved, **DSMC_KW)
    assert saved.read_bytes() == before
    ck = tmp_path / "run.npz"
    dsmc.simulate_heated(0.6, 200, checkpoint=ck, **DSMC_KW)
    with pytest.raises(FileExistsError, match="not overwritten"):
        dsmc.simulate_heated(0.7, 200, checkpoint=ck, **DSMC_KW)
    dsmc.simulate_heated(0.6, 200, checkpoint=ck, **DSMC_KW)  # the same run: replaced


def test_checkpoint_directory_is_checked_before_the_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="checkpoint=.*does not exist"):
        dsmc.simulate_heated(0.6, 200, checkpoint=tmp_path / "no" / "ck", **DSMC_KW)


def _edit(path, **changes):
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    for k, f in changes.items():
        arrays[k] = f(arrays[k])
    np.savez(path, **arrays)


@pytest.mark.parametrize("edit", [
    {"v": lambda v: v[:100]},
    {"counts": lambda c: -c},
    {"v": lambda v: np.full_like(v, np.nan)},
])
def test_edited_dsmc_checkpoint_is_refused(tmp_path, edit):
    ck = tmp_path / "run.npz"
    dsmc.simulate_heated(0.6, 200, checkpoint=ck, max_wall_time=1e-9, **DSMC_KW)
    _edit(ck, **edit)
    with pytest.raises(FileFormatError, match="checksum"):
        dsmc.simulate_heated(0.6, 200, checkpoint=ck, resume=True, **DSMC_KW)
    _edit(ck, __sha256__=lambda s: s, __meta__=lambda m: np.array(  # an old-format file
        str(m).replace(', "__format__": "particles.checkpoint/1", "__engine__": "dsmc"', "")))
    with np.load(ck) as data:
        assert "__format__" not in str(data["__meta__"])
    with pytest.raises(FileFormatError, match="shape|non-finite|negative"):
        dsmc.simulate_heated(0.6, 200, checkpoint=ck, resume=True, **DSMC_KW)


def test_edited_md_checkpoint_is_refused(tmp_path):
    ck = tmp_path / "md.npz"
    with pytest.raises(RuntimeError, match="before any sample"):
        md.simulate_heated(0.9, 30, checkpoint=ck, max_wall_time=1e-9, **MD_KW)
    _edit(ck, md_v=lambda v: v * np.nan)
    with pytest.raises(FileFormatError, match="checksum"):
        md.simulate_heated(0.9, 30, checkpoint=ck, resume=True, **MD_KW)


def test_checkpoint_of_the_other_engine_is_refused(tmp_path):
    d, m = tmp_path / "d.npz", tmp_path / "m.npz"
    dsmc.simulate_heated(0.6, 200, checkpoint=d, max_wall_time=1e-9, **DSMC_KW)
    with pytest.raises(RuntimeError, match="before any sample"):
        md.simulate_heated(0.9, 30, checkpoint=m, max_wall_time=1e-9, **MD_KW)
    with pytest.raises(FileFormatError, match="written by DSMC"):
        md.simulate_heated(0.9, 30, checkpoint=d, resume=True, **MD_KW)
    with pytest.raises(FileFormatError, match="written by MD"):
        dsmc.simulate_heated(0.6, 200, checkpoint=m, resume=True, **DSMC_KW)
    with pytest.raises(FileFormatError, match="written by MD"):
        load_checkpoint(m, engine="dsmc")


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04junk", bytes(range(256)) * 4])
def test_damaged_checkpoint_is_one_clear_error(tmp_path, content):
    ck = tmp_path / "ck.npz"
    ck.write_bytes(content)
    with pytest.raises(FileFormatError, match="ck.npz.*DSMC checkpoint"):
        dsmc.simulate_heated(0.6, 200, checkpoint=ck, resume=True, **DSMC_KW)
    assert ck.read_bytes() == content
