"""One clear error for every unreadable file (issue 28): kinetic_fem.files and loaders."""

import json

import numpy as np
import pytest

from kinetic_fem import io
from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.evolution import Evolution
from kinetic_fem.exceptions import FileFormatError
from kinetic_fem.files import npz_path, output_path


def _gauss():
    v = np.linspace(-6, 6, 61)
    return VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")


def test_npz_path_appends_and_never_cuts():
    assert npz_path("a0.6").name == "a0.6.npz" and npz_path("x.npz").name == "x.npz"


def test_output_path_is_checked(tmp_path):
    with pytest.raises(FileNotFoundError, match="out=.*does not exist"):
        output_path(tmp_path / "no" / "x.vtu", name="out")
    with pytest.raises(IsADirectoryError):
        output_path(tmp_path)
    assert output_path(tmp_path / "x.vtu") == tmp_path / "x.vtu"


@pytest.mark.parametrize("cut", [0.5, 0.1])
def test_truncated_vtu_is_a_file_format_error_not_system_exit(tmp_path, cut):
    path = io.write_distribution(_gauss(), tmp_path / "d.vtu")
    data = path.read_bytes()
    path.write_bytes(data[:int(cut * len(data))])
    with pytest.raises(FileFormatError, match="d.vtu"):
        io.read_distribution(path)


def test_nan_moments_in_the_sidecar_are_refused(tmp_path):
    path = io.write_distribution(_gauss(), tmp_path / "d.vtu")
    side = io.sidecar_path(path)
    meta = json.loads(side.read_text())
    meta["raw_moments"] = [float("nan")] * len(meta["raw_moments"])
    side.write_text(json.dumps(meta))
    with pytest.raises(FileFormatError, match="raw_moments"):
        io.read_distribution(path)


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04rest", bytes(range(256))])
def test_damaged_npz_is_one_error(tmp_path, content):
    path = tmp_path / "d.npz"
    path.write_bytes(content)
    for load in (VelocityDistribution.load, Evolution.load):
        with pytest.raises(FileFormatError, match="d.npz") as err:
            load(path)
        assert "allow_pickle" not in str(err.value)


def test_foreign_or_nan_npz_is_refused(tmp_path):
    np.savez(tmp_path / "other.npz", a=np.ones(3))
    with pytest.raises(FileFormatError, match="lacks"):
        VelocityDistribution.load(tmp_path / "other.npz")
    path = _gauss().save(tmp_path / "g")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["values"] = np.full_like(arrays["values"], np.nan)
    np.savez(path, **arrays)
    with pytest.raises(FileFormatError, match="values"):
        VelocityDistribution.load(path)
    arrays["values"] = -np.abs(arrays["raw_moments"][:1]) * np.ones(61)
    np.savez(path, **arrays)
    with pytest.raises(FileFormatError, match="no valid distribution"):
        VelocityDistribution.load(path)
