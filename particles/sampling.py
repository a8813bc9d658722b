"""Histograms with error bars, running moments, checkpoints and replicas.

Shared by DSMC and MD.  Samples are accumulated into independent *batches*: each
batch holds a histogram and the power sums :math:`\\sum_i x_i^k`,
``k = 0 .. MAX_MOMENT``, so that moments come from the samples themselves and the
errors of any observable from the spread between batches
(:meth:`kinetic_fem.VelocityDistribution.from_batches`).

Randomness: every run draws from ``numpy.random.Generator`` objects built from a
``numpy.random.SeedSequence``; independent replicas use ``SeedSequence.spawn``, and
run through any ``concurrent.futures.Executor`` (a local process pool by default,
``dask.distributed.Client.get_executor()`` on a cluster).
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kinetic_fem.distribution import MAX_MOMENT, RunInfo, VelocityDistribution
from kinetic_fem.exceptions import FileFormatError
from kinetic_fem.files import check_loaded_values, json_entry, npz_path, read_npz
from kinetic_fem.model import check_finite_array

from ._jit import jit

__all__ = ["Accumulator", "accumulate_kernel", "save_checkpoint", "load_checkpoint",
           "spawn_seeds", "run_replicas", "integrated_autocorrelation_time", "sonine_draws",
           "initial_velocities_of", "SAMPLER_CHUNK", "CHECKPOINT_FORMAT"]

logger = logging.getLogger(__name__)


@jit
def accumulate_kernel(x, lo, hi, counts, sums):  # pragma: no cover - compiled
    """Add samples ``x`` to one batch: histogram on ``[lo, hi)`` and power sums.

    ``counts`` has shape (n_bins,), ``sums`` shape (K + 1,) (``K = MAX_MOMENT`` in the
    runs); both are updated in place.  Samples outside the range count in the sums only.
    For ``K = 12`` the thirteen sums are kept in local variables during the pass (an
    array accumulator is reloaded and stored for every sample: 13.6 against about 4 ns
    per sample at N = 25000); other ``K`` take a plain loop.
    """
    n_bins = counts.shape[0]
    width = (hi - lo) / n_bins
    if sums.shape[0] == 13:
        _accumulate_12(x, lo, width, counts, sums)
        return
    kmax = sums.shape[0]
    for i in range(x.shape[0]):
        xi = x[i]
        p = 1.0
        for k in range(kmax):
            sums[k] += p
            p *= xi
        b = int(np.floor((xi - lo) / width))
        if 0 <= b < n_bins:
            counts[b] += 1.0


@jit
def _accumulate_12(x, lo, width, counts, sums):  # pragma: no cover - compiled
    """:func:`accumulate_kernel` for power sums ``k = 0 .. 12`` in registers."""
    n_bins = counts.shape[0]
    s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = s10 = s11 = s12 = 0.0
    for i in range(x.shape[0]):
        x1 = x[i]
        x2 = x1 * x1
        x3 = x2 * x1
        x4 = x2 * x2
        x5 = x4 * x1
        x6 = x4 * x2
        s1 += x1
        s2 += x2
        s3 += x3
        s4 += x4
        s5 += x5
        s6 += x6
        s7 += x6 * x1
        s8 += x6 * x2
        s9 += x6 * x3
        s10 += x6 * x4
        s11 += x6 * x5
        s12 += x6 * x6
        b = int(np.floor((x1 - lo) / width))
        if 0 <= b < n_bins:
            counts[b] += 1.0
    sums[0] += x.shape[0]
    sums[1] += s1
    sums[2] += s2
    sums[3] += s3
    sums[4] += s4
    sums[5] += s5
    sums[6] += s6
    sums[7] += s7
    sums[8] += s8
    sums[9] += s9
    sums[10] += s10
    sums[11] += s11
    sums[12] += s12


@dataclass
class Accumulator:
    """Per-batch histograms and power sums of a sampled velocity (or scaled velocity).

    Parameters
    ----------
    lo, hi : float
        Histogram range.
    n_bins : int
        Number of equal bins.
    n_batches : int
        Number of independent batches (>= 2 for error bars).
    """

    lo: float
    hi: float
    n_bins: int
    n_batches: int

    def __post_init__(self) -> None:
        if not (np.isfinite(self.lo) and np.isfinite(self.hi) and self.hi > self.lo):
            raise ValueError(f"histogram range must be finite with hi > lo, got "
                             f"[{self.lo}, {self.hi}]")
        if self.n_bins < 1 or self.n_batches < 1:
            raise ValueError("n_bins and n_batches must be >= 1")
        self.counts = np.zeros((self.n_batches, self.n_bins))
        self.sums = np.zeros((self.n_batches, MAX_MOMENT + 1))

    @property
    def edges(self) -> NDArray[np.float64]:
        """Bin edges, shape (n_bins + 1,)."""
        return np.linspace(self.lo, self.hi, self.n_bins + 1)

    def add(self, batch: int, x: NDArray[np.float64]) -> None:
        """Add samples ``x`` to ``batch``."""
        accumulate_kernel(np.ascontiguousarray(x, dtype=np.float64), self.lo, self.hi,
                          self.counts[batch], self.sums[batch])

    def filled(self) -> NDArray[np.bool_]:
        """Which batches hold samples."""
        return self.sums[:, 0] > 0

    def distribution(self, *, method: str, params: Mapping[str, Any], info: RunInfo,
                     series: Mapping[str, NDArray[np.float64]] | None = None
                     ) -> VelocityDistribution:
        """The accumulated samples as a :class:`VelocityDistribution` (filled batches only)."""
        keep = self.filled()
        if not keep.any():
            raise ValueError("no samples were accumulated; run longer or start sampling earlier")
        return VelocityDistribution.from_batches(
            self.edges, self.counts[keep], self.sums[keep], method=method, params=params,
            info=info, series=series)

    def state(self) -> dict[str, NDArray[np.float64]]:
        """Arrays to checkpoint."""
        return {"acc_counts": self.counts.copy(), "acc_sums": self.sums.copy()}

    def restore(self, state: Mapping[str, NDArray[np.float64]]) -> None:
        """Restore from :meth:`state`."""
        self.counts[...] = state["acc_counts"]
        self.sums[...] = state["acc_sums"]


def integrated_autocorrelation_time(x: NDArray[np.float64], window: float = 5.0) -> float:
    """Integrated autocorrelation time of the series ``x``, in samples.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Equally spaced samples of a stationary series (``n >= 2``).
    window : float
        Sokal's windowing constant ``c``: the sum stops at the first lag ``M`` with
        ``M >= c * tau(M)``.

    Returns
    -------
    float
        :math:`\\tau = 1 + 2\\sum_{k=1}^{M} \\rho(k)` (at least 1; 1 for a constant
        series), so that the variance of the mean of ``n`` samples is
        :math:`\\tau\\,\\sigma^2/n`.

    Notes
    -----
    The autocorrelation :math:`\\rho(k)` comes from a zero-padded FFT.  A. D. Sokal,
    *Monte Carlo methods in statistical mechanics* (1997), section 3.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> round(integrated_autocorrelation_time(rng.normal(size=4000)), 1)
    1.0
    >>> y = np.zeros(20000)
    >>> e = rng.normal(size=20000)
    >>> for k in range(1, y.size):  # AR(1), rho = 0.8: tau = (1 + 0.8)/(1 - 0.8) = 9
    ...     y[k] = 0.8 * y[k - 1] + e[k]
    >>> bool(7.5 < integrated_autocorrelation_time(y) < 10.5)
    True
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"need a 1D series of at least 2 samples, got shape {x.shape}")
    d = x - x.mean()
    var = float(np.dot(d, d))
    if not var > 0.0:
        return 1.0
    f = np.fft.rfft(d, 2 * d.size)
    rho = np.fft.irfft(f * np.conj(f))[:d.size] / var
    tau = 1.0
    for m in range(1, d.size):
        tau += 2.0 * rho[m]
        if m >= window * tau:
            break
    return max(float(tau), 1.0)


CHECKPOINT_FORMAT = "particles.checkpoint/1"
"""Format tag written into every checkpoint (with the engine and a SHA-256 checksum)."""


def _checksum(arrays: Mapping[str, NDArray[Any]], meta_json: str) -> str:
    """SHA-256 over the metadata and every array (name, dtype, shape, bytes)."""
    h = hashlib.sha256(meta_json.encode())
    for k in sorted(arrays):
        a = np.ascontiguousarray(arrays[k])
        h.update(f"{k}|{a.dtype.str}|{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def save_checkpoint(path: str | Path, arrays: Mapping[str, NDArray[Any]],
                    meta: Mapping[str, Any], *, engine: str = "dsmc") -> Path:
    """Write arrays and JSON metadata (e.g. ``rng.bit_generator.state``) atomically.

    The file is written beside ``path`` and renamed, so an interrupted write never
    leaves a corrupt checkpoint.  It carries the format tag :data:`CHECKPOINT_FORMAT`,
    the engine and a SHA-256 checksum of everything in it, checked by
    :func:`load_checkpoint`.

    Parameters
    ----------
    path : str or Path
        Destination file (``.npz`` is appended unless it is the suffix; the path given
        is never cut at its last dot).
    arrays : mapping of str to ndarray
        The arrays to store.
    meta : mapping
        JSON-serialisable metadata.
    engine : str
        The engine writing it (``"dsmc"`` or ``"md"``).

    Returns
    -------
    Path
        The path written.
    """
    path = npz_path(path)
    tmp = path.with_name(path.name[:-len(".npz")] + ".tmp.npz")
    meta_json = json.dumps({**meta, "__format__": CHECKPOINT_FORMAT, "__engine__": engine})
    arrays = {k: np.asarray(a) for k, a in arrays.items()}
    digest = _checksum(arrays, meta_json)
    # (numpy's stub types **kwds of savez as its allow_pickle flag)
    np.savez(tmp, __meta__=np.array(meta_json), __sha256__=np.array(digest),
             **arrays)  # type: ignore[arg-type]
    tmp.replace(path)
    return path


def load_checkpoint(path: str | Path, *, engine: str = "dsmc",
                    like: Mapping[str, NDArray[Any]] | None = None,
                    nonnegative: Sequence[str] = ()
                    ) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Read and verify a checkpoint written by :func:`save_checkpoint`.

    Parameters
    ----------
    path : str or Path
        The checkpoint file.
    engine : str
        The engine that must have written it (``"dsmc"`` or ``"md"``).
    like : mapping of str to ndarray, optional
        Arrays of the run being resumed: each that the file holds must have the same
        shape and be finite.
    nonnegative : sequence of str
        Arrays that must be ``>= 0`` (counts).

    Returns
    -------
    arrays : dict of str to ndarray
    meta : dict
        The JSON metadata (without the format entries).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    kinetic_fem.exceptions.FileFormatError
        If it is not a readable checkpoint, was written by the other engine, fails its
        checksum (edited or damaged) or holds arrays of the wrong shape, non-finite
        values or negative counts.
    """
    what = f"{engine.upper()} checkpoint"
    data = read_npz(path, what=what, required=("__meta__",))
    meta = json_entry(data, "__meta__", path, what)
    arrays = {k: a for k, a in data.items() if k not in ("__meta__", "__sha256__")}
    fmt, written_by = meta.pop("__format__", None), meta.pop("__engine__", None)
    if fmt is None:  # before the format tag: no checksum, recognised by its identity entry
        written_by = "dsmc" if "key" in meta else "md" if "params" in meta else None
        logger.warning("checkpoint %s has no format tag or checksum (an earlier version); "
                       "its arrays are checked for shape and finiteness only", path)
    elif fmt != CHECKPOINT_FORMAT:
        raise FileFormatError(f"{str(path)!r} has checkpoint format {fmt!r}; this version "
                              f"reads {CHECKPOINT_FORMAT!r}")
    elif "__sha256__" not in data or str(data["__sha256__"]) != _checksum(
            arrays, str(data["__meta__"])):
        raise FileFormatError(f"{str(path)!r} fails its checksum: the checkpoint was edited "
                              "or damaged; it cannot be resumed")
    if written_by != engine:
        raise FileFormatError(f"{str(path)!r} is not a {what}"
                              + ("" if written_by is None else
                                 f": it was written by {str(written_by).upper()}"))
    for k, ref in (like or {}).items():
        if k in arrays and arrays[k].shape != np.shape(ref):
            raise FileFormatError(f"{str(path)!r}: {k!r} has shape {arrays[k].shape}, the run "
                                  f"has {np.shape(ref)}; the checkpoint was edited or belongs "
                                  "to another run")
    check_loaded_values(path, **{k: arrays[k] for k in (like or {}) if k in arrays})
    for k in nonnegative:
        if k in arrays and np.any(arrays[k] < 0):
            raise FileFormatError(f"{str(path)!r}: {k!r} holds negative counts; the checkpoint "
                                  "was edited or damaged")
    return arrays, meta


def spawn_seeds(seed: int | np.random.SeedSequence | None, n: int) -> list[np.random.SeedSequence]:
    """``n`` independent seed sequences from one root seed.

    Parameters
    ----------
    seed : int, SeedSequence or None
        Root seed (None: fresh entropy).
    n : int
        Number of child sequences.

    Returns
    -------
    list of SeedSequence
    """
    root = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    return root.spawn(n)


def run_replicas(func: Callable[..., Any], seeds: Sequence[Any], *,
                 executor: Executor | None = None, max_workers: int | None = None,
                 **kwargs: Any) -> list[Any]:
    """Run ``func(seed=s, **kwargs)`` for each seed, in parallel, results in seed order.

    Parameters
    ----------
    func : callable
        A picklable top-level function (e.g. ``particles.dsmc.simulate_heated``).
    seeds : sequence
        One seed (int or SeedSequence) per replica; see :func:`spawn_seeds`.
    executor : concurrent.futures.Executor, optional
        Where to run; default a local ``ProcessPoolExecutor``.  On a cluster pass
        ``dask.distributed.Client(...).get_executor()``.
    """
    if executor is not None:
        futures = [executor.submit(func, seed=s, **kwargs) for s in seeds]
        return [f.result() for f in futures]
    with ProcessPoolExecutor(max_workers=max_workers) as pool:
        futures = [pool.submit(func, seed=s, **kwargs) for s in seeds]
        return [f.result() for f in futures]


SAMPLER_CHUNK = 1 << 16
"""Proposals per chunk of :func:`sonine_draws` (memory: 8 bytes per particle plus a chunk)."""


def sonine_draws(n: int, a2: float, rng: np.random.Generator, *,
                 chunk: int = SAMPLER_CHUNK) -> NDArray[np.float64]:
    """``n`` draws of :math:`\\Phi(c)(1 + a_2 S_2(c^2))_+` on ``|c| < 6`` by rejection.

    Each round proposes ``m = 2 (n - count) + 16`` normals and then ``m`` uniforms from
    ``rng`` (that order); the proposals are processed in chunks of ``chunk`` with a
    second generator started where the round's normals end, so the draws are those of
    drawing the round's arrays whole, while the memory is the output (8 bytes per
    particle) and a chunk (it was 82 bytes per particle with whole arrays).

    Parameters
    ----------
    n : int
        Number of draws.
    a2 : float
        First Sonine coefficient of the target (0: the unit Gaussian).
    rng : numpy.random.Generator
        Random source (advanced).
    chunk : int
        Proposals per chunk (the draws do not depend on it).

    Returns
    -------
    ndarray, shape (n,)
    """
    grid = np.linspace(0.0, 6.0, 601) ** 2
    weight = lambda c2: np.maximum(1 + a2 * (c2**2 / 8 - 3 * c2 / 4 + 3 / 8), 0.0)  # noqa: E731
    top = weight(grid).max()
    out = np.empty(n)
    count = 0
    while count < n:
        m = 2 * (n - count) + 16
        uni = np.random.Generator(type(rng.bit_generator)())
        uni.bit_generator.state = rng.bit_generator.state
        for start in range(0, m, chunk):  # advance uni past the round's normals
            uni.normal(size=min(chunk, m - start))
        for start in range(0, m, chunk):
            k = min(chunk, m - start)
            c = rng.normal(size=k)
            keep = c[(np.abs(c) < 6) & (uni.random(k) * top < weight(c * c))][: n - count]
            out[count:count + keep.size] = keep
            count += keep.size
        rng.bit_generator.state = uni.bit_generator.state  # both streams consumed
        if count >= n:
            break
    return out


def initial_velocities_of(initial: ArrayLike | None, n: int, temperature: float,
                          seed_seq: np.random.SeedSequence, a2: float = 0.0) -> NDArray[np.float64]:
    r"""The user's state, or ``n`` draws from :math:`\Phi(c)(1 + a_2 S_2(c^2))_+`, ``|c| < 6``.

    Rejection from the Gaussian; ``a2 = 0`` gives the Gaussian itself.  The total
    momentum is removed.

    Parameters
    ----------
    initial : array_like, shape (n,), or None
        The user's initial velocities (finite), or None to draw them.
    n : int
        Number of particles.
    temperature : float
        Temperature of the drawn state.
    seed_seq : numpy.random.SeedSequence
        Seed of the draws.
    a2 : float
        First Sonine coefficient of the drawn state.

    Returns
    -------
    ndarray, shape (n,)

    Raises
    ------
    ValueError
        For a non-finite or wrongly shaped ``initial``.
    """
    if initial is None:
        v = sonine_draws(n, a2, np.random.default_rng(seed_seq)) * math.sqrt(temperature)
    else:
        v = check_finite_array("initial_velocities", initial, ndim=1).copy()
        if v.shape != (n,):
            raise ValueError(f"initial_velocities has shape {v.shape}; expected ({n},) "
                             f"for n_particles={n}")
    return v - v.mean()
