"""Property tests over the public API, tried as a hostile user would (issue 28).

Any generated input gives either a valid result (finite, converged) or a clear error of
the package -- ``ValueError``/``TypeError`` (with ``FileFormatError``,
``UnsupportedModelError``), ``ConvergenceError``/``RuntimeError`` or ``MemoryError``/
``OSError`` raised by the package's own code -- never a hang, a silent NaN or an
exception from inside numba, numpy, scipy or meshio.  The default run takes a few
examples each; ``-m slow`` runs many.
"""

import os
import traceback
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import kinetic_fem as kf
from kinetic_fem import io
from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.exceptions import FileFormatError
from kinetic_fem.mixture_file import mixture_from_table
from particles import dsmc, dsmc_mixture, md, md_mixture
from particles.sampling import load_checkpoint

OURS = (f"{os.sep}kinetic_fem{os.sep}", f"{os.sep}particles{os.sep}")
CLEAR = (ValueError, TypeError, RuntimeError, MemoryError, OSError)
FAST = settings(max_examples=8, deadline=20_000,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])
MANY = settings(max_examples=300, deadline=20_000,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])


def assert_clear(err: BaseException) -> None:
    """A documented exception type, raised by the package itself, with a message."""
    assert isinstance(err, CLEAR), f"{type(err).__name__}: {err}"
    frames = traceback.extract_tb(err.__traceback__)
    assert frames and any(s in frames[-1].filename for s in OURS), \
        f"{type(err).__name__} from {frames[-1].filename}: {err}"
    assert str(err)


def outcome(call):
    """The result of ``call()``, or None after checking the exception is clear."""
    try:
        return call()
    except BaseException as err:  # noqa: BLE001 - checked below
        if isinstance(err, KeyboardInterrupt):
            raise
        assert_clear(err)
        return None


def assert_physical(dist: VelocityDistribution) -> None:
    if dist.info.converged:
        assert np.isfinite(dist.temperature) and dist.temperature > 0
        assert not np.isnan(dist.a2) and np.all(np.isfinite(dist.values))


scale = st.one_of(st.floats(1e-300, 1e300), st.sampled_from([1.0, 1e-30, 1e30]))
alpha = st.one_of(st.floats(0.0, 1.0), st.sampled_from([0.0, 0.5, 0.999999, 1 - 1e-12, 1.0]),
                  st.just(float("nan")), st.booleans(), st.text(max_size=3))


def _heated(a, density, diffusion, friction):
    dist = outcome(lambda: kf.solve_heated(a, density=density, diffusion=diffusion,
                                           friction=friction, method="spectral"))
    if dist is not None:
        assert_physical(dist)


def _cooling(a, kernel):
    dist = outcome(lambda: kf.solve_cooling(a, kernel=kernel, method="spectral"))
    if dist is not None:
        assert_physical(dist)


heated_args = (alpha, scale, scale, st.one_of(st.just(0.0), scale))
cooling_args = (alpha, st.one_of(st.floats(-1.0, 3.0), st.sampled_from([1e-12, 0.0, 2.0])))


@FAST
@given(*heated_args)
def test_solve_heated_spectral(a, density, diffusion, friction):
    _heated(a, density, diffusion, friction)


@FAST
@given(*cooling_args)
def test_solve_cooling_spectral(a, kernel):
    _cooling(a, kernel)


def _dsmc(a, n, cpp, every, seed):
    run = outcome(lambda: dsmc.simulate_heated(a, n, seed=seed, collisions_per_particle=cpp,
                                               sample_every=every, n_batches=2, bins=20))
    if run is not None:
        assert_physical(run.distribution)


def _md(a, n, cpp, boxes, seed):
    run = outcome(lambda: md.simulate_cooling(a, n, seed=seed, collisions_per_particle=cpp,
                                              n_samples=2, n_batches=2, box_counts=boxes))
    if run is not None:
        assert_physical(run.distribution)


small_n = st.one_of(st.integers(-2, 60), st.sampled_from([2**40, 2.5, True]))
cpp = st.one_of(st.floats(1e-300, 8.0), st.sampled_from([1e300, 0.0, -1.0, float("inf")]))
seeds = st.one_of(st.none(), st.integers(-5, 2**70), st.booleans())
dsmc_args = (st.one_of(st.floats(0.0, 0.99), st.sampled_from([0.999999, 1.0])), small_n,
             cpp, st.one_of(st.floats(1e-300, 4.0), st.just(float("nan"))), seeds)
md_args = (st.floats(0.5, 0.99), st.one_of(st.integers(-2, 40), st.just(True)), cpp,
           st.lists(st.integers(-2, 10**10), max_size=3), seeds)


def _mixture_particles(entry, mass, n, cpp, seed, forced, method):
    """A binary mixture from a mixture-file table whose alpha is ``entry`` (a number, a
    law string, junk), run by the mixture DSMC or MD."""
    def call():
        table = {"masses": [1.0, mass], "fractions": [0.5, 0.5], "alpha": entry,
                 "forcing": "same_diffusion" if forced else "cooling"}
        mix, density = mixture_from_table(table)
        if method == "md":
            return md_mixture.simulate_mixture(mix, n, seed=seed, collisions_per_particle=cpp,
                                               n_samples=3, n_batches=2, threshold=1e-3)
        return dsmc_mixture.simulate_mixture(
            mix, n, density=density, seed=seed, collisions_per_particle=cpp, relax=0.5,
            options=dsmc_mixture.MixtureDSMCOptions(n_batches=2, bins=10))

    run = outcome(call)
    if run is not None:
        assert np.all(np.isfinite(run.temperatures)) and np.all(run.temperatures > 0)


law_entry = st.one_of(
    st.floats(0.0, 0.99), st.builds("viscoelastic:{}".format, st.floats(0.01, 0.5)),
    st.builds("threshold:{}:{}".format, st.floats(0.0, 0.99), st.floats(0.01, 5.0)),
    st.lists(st.lists(st.sampled_from([0.7, "viscoelastic:0.1", "threshold:0.6:0.5"]),
                      min_size=2, max_size=2), min_size=2, max_size=2),
    alpha, st.builds("viscoelastic:{}".format, st.floats(-1.0, 5.0)),
    st.builds("threshold:{}:{}".format, st.floats(-0.5, 1.5), st.floats(-1.0, 10.0)),
    st.lists(st.lists(st.sampled_from([0.7, "threshold:0.6", "x", float("nan")]),
                      min_size=1, max_size=3), max_size=3))
valid_n = st.integers(2, 30).map(lambda k: 2 * k)
long_enough = st.floats(3.0, 12.0)
mixture_args = (law_entry,
                st.one_of(st.sampled_from([0.5, 1.0, 3.0]), st.sampled_from([0.5, 1.0, 3.0]),
                          st.sampled_from([0.0, -1.0, float("nan")])),
                st.one_of(valid_n, valid_n, st.integers(-2, 60), st.just(True)),
                st.one_of(long_enough, long_enough, st.floats(0.0, 3.0)),
                st.one_of(st.integers(0, 100), seeds), st.sampled_from([True, True, False]),
                st.sampled_from(["dsmc", "md"]))


@FAST
@given(*mixture_args)
def test_mixture_particles_with_laws_tiny(entry, mass, n, cpp, seed, forced, method):
    _mixture_particles(entry, mass, n, cpp, seed, forced, method)


def _mixture_fem(entry, mass, spacing):
    """The FEM heated state of a binary mixture from a mixture-file table whose alpha is
    ``entry`` (a number, a law string, a table of them, junk)."""
    def call():
        table = {"masses": [1.0, mass], "fractions": [0.5, 0.5], "alpha": entry}
        mix, density = mixture_from_table(table)
        return kf.solve_heated(mix, density=density, spacing=spacing)

    state = outcome(call)
    if state is not None:
        assert np.all(np.isfinite(state.temperatures)) and np.all(state.temperatures > 0)
        assert np.all(np.isfinite(state.a2))


# (spacings of at least 0.2: finer meshes are valid and only slow, 110 s at 0.01)
mixture_fem_args = (law_entry, st.sampled_from([0.5, 1.0, 3.0, 0.0, float("nan")]),
                    st.one_of(st.sampled_from([0.5, 0.25]), st.floats(0.2, 2.0),
                              st.sampled_from([0.0, -1.0, float("nan"), float("inf")])))


@FAST
@given(*mixture_fem_args)
def test_mixture_fem_with_laws_tiny(entry, mass, spacing):
    _mixture_fem(entry, mass, spacing)


@FAST
@given(*dsmc_args)
def test_dsmc_heated_tiny(a, n, cpp, every, seed):
    _dsmc(a, n, cpp, every, seed)


@FAST
@given(*md_args)
def test_md_cooling_tiny(a, n, cpp, boxes, seed):
    _md(a, n, cpp, boxes, seed)


# ----------------------------------------------------------------------------- files
def _gauss():
    v = np.linspace(-6, 6, 61)
    return VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")


def _corrupt(data: bytes, cut: int, flips: list[tuple[int, int]]) -> bytes:
    b = bytearray(data[:cut] if cut < len(data) else data)
    for pos, val in flips:
        if b:
            b[pos % len(b)] = val
    return bytes(b)


corruptions = (st.integers(0, 20_000), st.lists(st.tuples(st.integers(0, 10**6),
                                                          st.integers(0, 255)), max_size=4))


def _loaders(tmp: Path, corrupt):
    npz = _gauss().save(tmp / "d.npz")
    vtu = io.write_distribution(_gauss(), tmp / "d.vtu")
    for path, load in ((npz, VelocityDistribution.load), (vtu, io.read_distribution),
                       (npz, load_checkpoint), (io.sidecar_path(vtu), None)):
        path.write_bytes(corrupt(path.read_bytes()))
        if load is None:  # the sidecar: read through the mesh file
            path, load = vtu, io.read_distribution
        try:
            got = load(path)
        except FileFormatError as err:
            assert str(path) in str(err)
            continue
        except BaseException as err:  # noqa: BLE001
            pytest.fail(f"{load.__qualname__} of a damaged file: {type(err).__name__}: {err}")
        if isinstance(got, VelocityDistribution):
            assert np.all(np.isfinite(got.values))


@FAST
@given(*corruptions)
def test_damaged_files_give_one_error(tmp_path_factory, cut, flips):
    _loaders(tmp_path_factory.mktemp("f"), lambda b: _corrupt(b, cut, flips))


@FAST
@given(st.binary(max_size=2000))
def test_random_bytes_give_one_error(tmp_path_factory, data):
    _loaders(tmp_path_factory.mktemp("r"), lambda b: data)


# ----------------------------------------------------------------------------- many
@pytest.mark.slow
@MANY
@given(*heated_args)
def test_solve_heated_spectral_many(a, density, diffusion, friction):
    _heated(a, density, diffusion, friction)


@pytest.mark.slow
@MANY
@given(*dsmc_args)
def test_dsmc_heated_many(a, n, cpp, every, seed):
    _dsmc(a, n, cpp, every, seed)


@pytest.mark.slow
@MANY
@given(*mixture_args)
def test_mixture_particles_with_laws_many(entry, mass, n, cpp, seed, forced, method):
    _mixture_particles(entry, mass, n, cpp, seed, forced, method)


@pytest.mark.slow
@MANY
@given(*mixture_fem_args)
def test_mixture_fem_with_laws_many(entry, mass, spacing):
    _mixture_fem(entry, mass, spacing)


@pytest.mark.slow
@MANY
@given(*md_args)
def test_md_cooling_many(a, n, cpp, boxes, seed):
    _md(a, n, cpp, boxes, seed)


@pytest.mark.slow
@MANY
@given(*corruptions)
def test_damaged_files_many(tmp_path_factory, cut, flips):
    _loaders(tmp_path_factory.mktemp("f"), lambda b: _corrupt(b, cut, flips))
