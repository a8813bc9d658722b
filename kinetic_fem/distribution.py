"""The velocity distribution: the one result type of every method.

A :class:`VelocityDistribution` holds :math:`P(v)` either on the nodes of a
deterministic solver (with that solver's quadrature weights) or as a histogram of
particle velocities (with error bars from independent batches).  Moments of sampled
distributions come from the samples themselves, never from the histogram.

Observables follow the paper (Barrat et al. 2002) with the kurtosis misprint
corrected:

.. math::

    T = \\langle (v-u)^2 \\rangle, \\quad c = (v - u)/\\sqrt{T},

.. math::

    f(c) = \\sqrt{T} P(u + c\\sqrt{T}), \\quad
    a_2 = \\frac{\\langle (v-u)^4 \\rangle}{3 T^2} - 1,

with :math:`u = \\langle v \\rangle` (zero for the symmetric deterministic
solutions, drifting in finite particle systems).  The Sonine expansion is

.. math::

    f(c) = \\Phi(c)\\Big(1 + \\sum_{p \\ge 2} a_p S_p(c^2)\\Big), \\qquad
    S_p(c^2) = L_p^{(-1/2)}(c^2/2),

and orthogonality with :math:`\\Phi(c) = e^{-c^2/2}/\\sqrt{2\\pi}` gives
:math:`a_p = \\langle S_p \\rangle / \\mathcal N_p` with
:math:`\\mathcal N_p = \\Gamma(p + 1/2)/(\\sqrt{\\pi}\\, p!)`.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from .error import ErrorEstimate, ErrorRecipe
from .exceptions import FileFormatError
from .files import check_loaded_values, json_entry, npz_path, read_npz, reading
from .gas import check_finite_array
from .moments import central_from_raw, sonine_from_central
from .operators.grid import moments as quadrature_moments
from .operators.grid import simpson_weights, trapezoid_weights
from .run_info import RunInfo

__all__ = ["VelocityDistribution", "RunInfo", "Comparison", "MAX_MOMENT", "MAX_SONINE"]

MAX_SONINE = 6
"""Highest Sonine order available (needs moments up to ``2 * MAX_SONINE``)."""
MAX_MOMENT = 2 * MAX_SONINE
"""Raw moments ``<v^k>``, ``k = 0 .. MAX_MOMENT``, are carried by every distribution."""


@dataclass(frozen=True)
class Comparison:
    """Differences between two distributions (see :meth:`VelocityDistribution.compare`).

    Attributes
    ----------
    temperature_rel : float
        Relative difference of the temperatures, :math:`|T_1/T_2 - 1|`.
    a2_abs : float
        Absolute difference of the kurtosis coefficients, :math:`|a_{2,1} - a_{2,2}|`.
    f_rel_max : float
        Largest relative difference :math:`|f_1(c)/f_2(c) - 1|` of the scaled
        distributions over the compared nodes (NaN if none is compared).
    c_max : float
        The nodes compared are those with :math:`|c| \\le` ``c_max`` where both
        distributions exceed the ``floor`` of :meth:`VelocityDistribution.compare`.
    """

    temperature_rel: float
    a2_abs: float
    f_rel_max: float
    c_max: float


@dataclass(frozen=True)
class VelocityDistribution:
    """A velocity distribution :math:`P(v)` with its observables.

    Build one with :meth:`from_values` (deterministic solvers) or
    :meth:`from_samples` / :meth:`from_batches` (particle methods).

    Attributes
    ----------
    v : ndarray, shape (n_v,)
        Increasing velocities: solver nodes or histogram bin centres.
    values : ndarray, shape (n_v,)
        :math:`P(v)` at ``v``, normalised to one.
    errors : ndarray, shape (n_v,) or None
        One standard error of ``values`` (sampled distributions).
    raw_moments : ndarray, shape (MAX_MOMENT + 1,)
        :math:`\\langle v^k \\rangle`, ``k = 0 .. MAX_MOMENT``.
    batch_moments : ndarray, shape (n_batches, MAX_MOMENT + 1) or None
        Raw moments of independent batches; errors of observables come from their spread.
    method : str
        Registry key of the method (``"fem"``, ``"fd"``, ``"dsmc"``, ...).
    params : dict
        Problem parameters (alpha, density, diffusion, ...).
    info : RunInfo
        Convergence and cost of the run.
    series : dict of str to ndarray
        Optional time series (``"t"``, ``"temperature"``, ``"a2"``, ...).
    error_recipe : ErrorRecipe, optional
        How a deterministic solver estimates this result's errors when :attr:`error` is
        first read (:mod:`kinetic_fem.error`).
    """

    v: NDArray[np.float64]
    values: NDArray[np.float64]
    raw_moments: NDArray[np.float64]
    errors: NDArray[np.float64] | None = None
    batch_moments: NDArray[np.float64] | None = None
    method: str = ""
    params: Mapping[str, Any] = field(default_factory=dict)
    info: RunInfo = field(default_factory=RunInfo)
    series: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    error_recipe: ErrorRecipe | None = field(default=None, repr=False, compare=False)

    def __repr__(self) -> str:
        """One line: method, nodes, T, a2 (with its error if sampled), convergence, params.

        The arrays are left out (they are :attr:`v`, :attr:`values`, ...).

        Examples
        --------
        >>> v = np.linspace(-12, 12, 2401)
        >>> VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="exact",
        ...                                  params={"alpha": 1.0})  # doctest: +ELLIPSIS
        VelocityDistribution(method='exact', n_v=2401, v=[-12, 12], temperature=1,
                             a2=..., converged=True, params={'alpha': 1.0})
        """
        a2 = f"{self.a2:.4g}"
        if self.batch_moments is not None:
            a2 += f" +- {self.a2_error:.2g}"
        params = repr(dict(self.params))
        if len(params) > 100:
            params = params[:97] + "..."
        with np.errstate(all="ignore"):
            temperature = f"{self.temperature:.6g}"
        return (f"VelocityDistribution(method={self.method!r}, n_v={self.v.size}, "
                f"v=[{self.v[0]:.4g}, {self.v[-1]:.4g}], temperature={temperature}, "
                f"a2={a2}, converged={self.info.converged}, params={params})")

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_values(
        cls,
        v: ArrayLike,
        values: ArrayLike,
        *,
        weights: ArrayLike | None = None,
        method: str = "",
        params: Mapping[str, Any] | None = None,
        info: RunInfo | None = None,
        series: Mapping[str, ArrayLike] | None = None,
        normalize: bool = True,
    ) -> VelocityDistribution:
        """Distribution from nodal values of a deterministic solver.

        Parameters
        ----------
        v : array_like, shape (n_v,)
            Strictly increasing nodes covering the support (both signs of v).
        values : array_like, shape (n_v,)
            :math:`P(v)` at the nodes.
        weights : array_like, shape (n_v,), optional
            The solver's quadrature weights; default Simpson on uniform nodes,
            trapezoid otherwise.
        normalize : bool
            Divide by :math:`\\sum_j w_j P_j` so that the zeroth moment is one.

        Examples
        --------
        >>> v = np.linspace(-12, 12, 2401)
        >>> d = VelocityDistribution.from_values(v, np.exp(-v**2 / 2))
        >>> round(d.temperature, 10), abs(d.a2) < 1e-10
        (1.0, True)
        """
        v = check_finite_array("v", v, ndim=1)
        vals = check_finite_array("values", values, ndim=1)
        if v.shape != vals.shape:
            raise ValueError(f"v and values differ in shape: {v.shape} vs {vals.shape}")
        if v.size < 3 or np.any(np.diff(v) <= 0):
            raise ValueError("v must hold at least 3 strictly increasing nodes")
        if weights is None:
            h = np.diff(v)
            uniform = np.allclose(h, h[0], rtol=1e-9, atol=0.0)
            w = simpson_weights(v) if uniform else trapezoid_weights(v)
        else:
            w = check_finite_array("weights", weights, ndim=1)
        raw = quadrature_moments(v, vals, w, MAX_MOMENT)
        if not raw[0] > 0:
            raise ValueError(f"distribution has non-positive mass {raw[0]!r}")
        if normalize:
            vals = vals / raw[0]
            raw = raw / raw[0]
        return cls(v=v, values=vals, raw_moments=raw, method=method,
                   params=dict(params or {}), info=info or RunInfo(),
                   series={k: np.asarray(s, dtype=float) for k, s in (series or {}).items()})

    @classmethod
    def from_batches(
        cls,
        bin_edges: ArrayLike,
        counts: ArrayLike,
        power_sums: ArrayLike,
        *,
        method: str = "",
        params: Mapping[str, Any] | None = None,
        info: RunInfo | None = None,
        series: Mapping[str, ArrayLike] | None = None,
    ) -> VelocityDistribution:
        """Distribution from per-batch histograms and power sums of samples.

        Parameters
        ----------
        bin_edges : array_like, shape (n_bins + 1,)
        counts : array_like, shape (n_batches, n_bins)
            Samples per bin in each independent batch.
        power_sums : array_like, shape (n_batches, MAX_MOMENT + 1)
            :math:`\\sum_i v_i^k` over each batch's samples (``k = 0`` is the count,
            including samples outside the bins).

        Notes
        -----
        The histogram density is the pooled count over (total samples x bin width);
        its error is the standard error of the batch densities.  With fewer than
        two batches no errors are given.
        """
        edges = check_finite_array("bin_edges", bin_edges, ndim=1)
        counts = np.atleast_2d(np.asarray(counts, dtype=float))
        sums = np.atleast_2d(check_finite_array("power_sums", power_sums))
        if counts.shape[1] != edges.size - 1:
            raise ValueError("counts must have one column per bin")
        if sums.shape != (counts.shape[0], MAX_MOMENT + 1):
            raise ValueError(f"power_sums must have shape (n_batches, {MAX_MOMENT + 1})")
        n_per_batch = sums[:, 0]
        if np.any(n_per_batch <= 0):
            raise ValueError("every batch needs at least one sample")
        width = np.diff(edges)
        values = counts.sum(axis=0) / (n_per_batch.sum() * width)
        batch_moments = sums / n_per_batch[:, None]
        errors = None
        if counts.shape[0] >= 2:
            dens = counts / (n_per_batch[:, None] * width[None, :])
            errors = dens.std(axis=0, ddof=1) / math.sqrt(counts.shape[0])
        raw = sums.sum(axis=0) / n_per_batch.sum()
        return cls(v=0.5 * (edges[1:] + edges[:-1]), values=values, raw_moments=raw,
                   errors=errors, batch_moments=batch_moments if counts.shape[0] >= 2 else None,
                   method=method, params=dict(params or {}), info=info or RunInfo(),
                   series={k: np.asarray(s, dtype=float) for k, s in (series or {}).items()})

    @classmethod
    def from_samples(
        cls,
        samples: ArrayLike,
        *,
        n_batches: int = 10,
        bins: int | ArrayLike = 200,
        method: str = "",
        params: Mapping[str, Any] | None = None,
        info: RunInfo | None = None,
    ) -> VelocityDistribution:
        """Distribution from velocity samples, split into contiguous batches.

        Parameters
        ----------
        samples : array_like, shape (n,) or (n_batches, m)
            Velocities; a 2-d array gives the batches explicitly.
        n_batches : int
            Number of contiguous batches for a 1-d ``samples``.
        bins : int or array_like
            Number of bins over the sample range, or the bin edges.

        Examples
        --------
        >>> rng = np.random.default_rng(1)
        >>> d = VelocityDistribution.from_samples(rng.normal(size=200_000))
        >>> abs(d.a2) < 5 * d.a2_error
        True
        """
        x = check_finite_array("samples", samples)
        batches: list[NDArray[np.float64]] | NDArray[np.float64]
        batches = x.reshape(1, -1) if x.ndim == 1 else x
        if x.ndim == 1:
            if n_batches < 1 or x.size < n_batches:
                raise ValueError(f"need at least n_batches={n_batches} samples, got {x.size}")
            batches = np.array_split(x, n_batches)
        edges = (np.linspace(x.min(), x.max(), int(bins) + 1)  # type: ignore[arg-type]
                 if np.ndim(bins) == 0
                 else np.asarray(bins, dtype=float))
        counts = np.array([np.histogram(b, edges)[0] for b in batches])
        k = np.arange(MAX_MOMENT + 1)
        sums = np.array([np.sum(np.asarray(b)[:, None] ** k[None, :], axis=0) for b in batches])
        return cls.from_batches(edges, counts, sums, method=method, params=params, info=info)

    # ------------------------------------------------------------------ moments
    @cached_property
    def _central(self) -> NDArray[np.float64]:
        return central_from_raw(self.raw_moments / self.raw_moments[0])

    @property
    def mean(self) -> float:
        """Mean velocity :math:`u = \\langle v \\rangle`."""
        return float(self.raw_moments[1] / self.raw_moments[0])

    @property
    def temperature(self) -> float:
        """Granular temperature :math:`T = \\langle (v - u)^2 \\rangle`."""
        return float(self._central[2])

    def moment(self, k: int, *, central: bool = True) -> float:
        """:math:`\\langle (v-u)^k \\rangle` (or :math:`\\langle v^k\\rangle`), ``k <= 12``."""
        if not 0 <= k <= MAX_MOMENT:
            raise ValueError(f"moment order must be in 0..{MAX_MOMENT}, got {k}")
        return float(self._central[k] if central else self.raw_moments[k] / self.raw_moments[0])

    @property
    def a2(self) -> float:
        """Kurtosis coefficient :math:`a_2 = \\langle (v-u)^4\\rangle / (3T^2) - 1`."""
        return self.sonine_coefficient(2)

    @property
    def a2_error(self) -> float:
        """Standard error of :attr:`a2` from the batch spread (NaN if not sampled)."""
        return self.observable_error(lambda d: d.a2)

    def sonine_coefficient(self, p: int) -> float:
        """Sonine coefficient :math:`a_p`, ``0 <= p <= 6`` (``a_0 = 1``, ``a_1 = 0``)."""
        if not 0 <= p <= MAX_SONINE:
            raise ValueError(f"Sonine order must be in 0..{MAX_SONINE}, got {p}")
        return sonine_from_central(self._central, p)

    def observable_error(self, observable: Any) -> float:
        """Standard error of ``observable(dist)`` from the independent batches.

        The observable is evaluated on each batch's moments; the error is the
        standard deviation over batches divided by ``sqrt(n_batches)``.  Returns NaN
        for deterministic distributions.
        """
        if self.batch_moments is None:
            return float("nan")
        vals = [observable(replace(self, raw_moments=m, batch_moments=None))
                for m in self.batch_moments]
        return float(np.std(vals, ddof=1) / math.sqrt(len(vals)))

    # ------------------------------------------------------------------ shape
    @cached_property
    def _log_spline(self) -> CubicSpline | None:
        positive = self.values > 0
        if positive.sum() < 4:
            return None
        return CubicSpline(self.v[positive], np.log(self.values[positive]))

    def pdf(self, v: ArrayLike) -> NDArray[np.float64]:
        """:math:`P(v)`, interpolated in :math:`\\ln P` (cubic); zero outside the nodes.

        Interpolating the logarithm keeps tail values accurate relative to
        themselves, down to the smallest positive nodal value.
        """
        v = np.asarray(v, dtype=float)
        inside = (v >= self.v[0]) & (v <= self.v[-1])
        out = np.zeros_like(v)
        spline = self._log_spline
        if spline is None:
            out[inside] = np.interp(v[inside], self.v, self.values)
        else:
            # only between positive nodes; zero where the data are zero
            lo, hi = spline.x[0], spline.x[-1]
            ok = inside & (v >= lo) & (v <= hi)
            out[ok] = np.exp(spline(v[ok]))
        return out

    @property
    def c(self) -> NDArray[np.float64]:
        """Scaled nodes :math:`c = (v - u)/\\sqrt{T}`."""
        return (self.v - self.mean) / math.sqrt(self.temperature)

    @property
    def f_values(self) -> NDArray[np.float64]:
        """:math:`f(c)` at :attr:`c`."""
        return math.sqrt(self.temperature) * self.values

    @property
    def f_errors(self) -> NDArray[np.float64] | None:
        """Standard errors of :attr:`f_values` (sampled distributions)."""
        return None if self.errors is None else math.sqrt(self.temperature) * self.errors

    def f(self, c: ArrayLike) -> NDArray[np.float64]:
        """Scaled distribution :math:`f(c) = \\sqrt{T} P(u + c\\sqrt{T})`."""
        s = math.sqrt(self.temperature)
        return s * self.pdf(self.mean + s * np.asarray(c, dtype=float))

    def effective_exponent(self, c: ArrayLike) -> NDArray[np.float64]:
        """Effective exponent :math:`n(c) = d\\ln(-\\ln(P/P_0))/d\\ln v`.

        Computed as :math:`n = v\\,(\\ln P)'(v) / \\ln(P(v)/P(0))` from the cubic
        spline of :math:`\\ln P`, never from differences of :math:`P` itself, so it
        stays accurate where :math:`P` is tiny.  ``v = u + c\\sqrt{T}``, measured from
        the mean.  NaN where :math:`P(v) \\ge P(0)` or outside the data.
        """
        spline = self._log_spline
        if spline is None:
            raise ValueError("too few positive values for an effective exponent")
        c = np.asarray(c, dtype=float)
        s = math.sqrt(self.temperature)
        x = self.mean + s * c
        inside = (x >= spline.x[0]) & (x <= spline.x[-1])
        out = np.full_like(c, np.nan)
        log_ratio = spline(x[inside]) - spline(self.mean)
        slope = spline(x[inside], 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            n = (s * c[inside]) * slope / log_ratio
        out[inside] = np.where(log_ratio < 0, n, np.nan)
        return out

    # ------------------------------------------------------------------ comparison
    def compare(
        self, other: VelocityDistribution, *, c_max: float | None = None, floor: float = 1e-30
    ) -> Comparison:
        """Differences from ``other``: relative T, absolute a2, max relative f(c).

        f(c) is compared on this distribution's scaled nodes with ``|c| <= c_max``
        where both are above ``floor``.

        Examples
        --------
        >>> v = np.linspace(-12, 12, 2401)
        >>> g = VelocityDistribution.from_values(v, np.exp(-v**2 / 2))
        >>> g.compare(g).f_rel_max < 1e-12
        True
        """
        c = self.c
        if c_max is None:
            c_max = float(min(np.abs(self.c).max(), np.abs(other.c).max()))
        mine = self.f_values
        theirs = other.f(c)
        keep = (np.abs(c) <= c_max) & (mine > floor) & (theirs > floor)
        rel = np.abs(mine[keep] / theirs[keep] - 1.0)
        return Comparison(
            temperature_rel=abs(self.temperature / other.temperature - 1.0),
            a2_abs=abs(self.a2 - other.a2),
            f_rel_max=float(rel.max()) if rel.size else float("nan"),
            c_max=float(c_max),
        )

    def rescaled(self, scale: float) -> VelocityDistribution:
        """The same distribution in velocity units multiplied by ``scale``.

        :math:`v \\to s v`, :math:`P \\to P/s`: the exact change of units relating
        solutions at different ``n`` and ``D`` (see :class:`~kinetic_fem.gas.HeatedProblem`).
        """
        k = np.arange(MAX_MOMENT + 1)
        bm = None if self.batch_moments is None else self.batch_moments * scale**k
        return replace(self, v=self.v * scale, values=self.values / scale,
                       errors=None if self.errors is None else self.errors / scale,
                       raw_moments=self.raw_moments * scale**k, batch_moments=bm)

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | Path) -> Path:
        """Write to ``path`` (``.npz`` appended unless it is the suffix); :meth:`load` restores it.

        The path given is the path written (``"alpha0.6"`` writes ``alpha0.6.npz``).
        """
        path = npz_path(path)
        arrays: dict[str, NDArray[Any]] = {"v": self.v, "values": self.values,
                                           "raw_moments": self.raw_moments}
        if self.errors is not None:
            arrays["errors"] = self.errors
        if self.batch_moments is not None:
            arrays["batch_moments"] = self.batch_moments
        for key, s in self.series.items():
            arrays[f"series__{key}"] = s
        meta = {"method": self.method, "params": dict(self.params), "info": asdict(self.info)}
        # (numpy's stub types **kwds of savez as its allow_pickle flag)
        np.savez(path, meta=np.array(json.dumps(meta)), **arrays)  # type: ignore[arg-type]
        return path

    @classmethod
    def load(cls, path: str | Path) -> VelocityDistribution:
        """Read a distribution written by :meth:`save`.

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        kinetic_fem.exceptions.FileFormatError
            If the file is damaged, foreign (not written by :meth:`save`) or holds
            non-finite values, negative values or a negative mass.
        """
        what = "VelocityDistribution .npz (VelocityDistribution.save)"
        data = read_npz(path, what=what, required=("meta", "v", "values", "raw_moments"))
        meta = json_entry(data, "meta", path, what)
        series = {k[len("series__"):]: data[k] for k in data if k.startswith("series__")}
        check_loaded_values(path, v=data["v"], values=data["values"],
                            raw_moments=data["raw_moments"], errors=data.get("errors"),
                            batch_moments=data.get("batch_moments"))
        values, raw = data["values"], data["raw_moments"]
        if (values.ndim != 1 or values.shape != data["v"].shape or raw.ndim != 1
                or not raw.size or raw[0] < 0 or np.any(np.diff(data["v"]) <= 0)
                or values.min(initial=0.0) < -1e-6 * np.abs(values).max(initial=0.0)):
            raise FileFormatError(f"{str(path)!r} holds no valid distribution (v increasing, "
                                  "values >= 0 of its shape, mass >= 0); the file is "
                                  "damaged or edited")
        with reading(path, what):
            return cls(
                v=data["v"], values=values, raw_moments=raw,
                errors=data.get("errors"), batch_moments=data.get("batch_moments"),
                method=meta["method"], params=meta["params"], info=RunInfo(**meta["info"]),
                series=series,
            )

    # ------------------------------------------------------------------ one-line views
    def plot(self, *, ax: Any = None, **options: Any) -> Any:
        """:math:`f(c)` on a log scale with the Gaussian and the error band where known.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (default: a new figure, without pyplot).
        **options
            Of :func:`kinetic_fem.plot.plot_f` (``log``, ``gaussian``, ``errors``,
            ``label``, line style).

        Returns
        -------
        matplotlib Axes
        """
        from .plot import plot_f

        return plot_f(self, ax=ax, **options)

    def to_xarray(self) -> Any:
        """The distribution as an ``xarray.Dataset`` over its nodes.

        See :func:`kinetic_fem.export.distribution_dataset`.
        """
        from .export import distribution_dataset

        return distribution_dataset(self)

    def _repr_html_(self) -> str:
        """A small table for Jupyter (:func:`kinetic_fem.export.distribution_html`)."""
        from .export import distribution_html

        return distribution_html(self)

    # ------------------------------------------------------------------ error estimates
    @cached_property
    def error(self) -> ErrorEstimate:
        """Estimated errors of :attr:`temperature` (relative), :attr:`a2`, zeta and f(c).

        The same names for every method (:class:`~kinetic_fem.error.ErrorEstimate`):
        a particle run's batch standard errors (``error.a2`` is :attr:`a2_error`), a
        deterministic result's a posteriori estimate by its method, computed on first
        read and cached (:mod:`kinetic_fem.error`).  A result without either (loaded,
        unpickled or built by hand) answers NaNs with a ``note`` saying why.

        Examples
        --------
        >>> rng = np.random.default_rng(1)
        >>> d = VelocityDistribution.from_samples(rng.normal(size=200_000))
        >>> d.error.a2 == d.a2_error, d.error.kind
        (True, 'standard error')
        """
        if self.batch_moments is not None:
            return ErrorEstimate.from_batches(self)
        if self.error_recipe is not None:
            return self.error_recipe(self)
        return ErrorEstimate.unavailable(
            f"no error estimate for this result (method {self.method!r}): only solvers' "
            "results and sampled distributions carry one")

    def with_error(self, recipe: ErrorRecipe | None,
                   estimate: ErrorEstimate | None = None) -> VelocityDistribution:
        """A copy whose :attr:`error` is computed by ``recipe`` (solvers call this).

        Parameters
        ----------
        recipe : ErrorRecipe or None
            The estimate's recipe.
        estimate : ErrorEstimate, optional
            The estimate if already computed (e.g. by a solver that refined until it met
            an accuracy): :attr:`error` returns it without calling ``recipe``.
        """
        out = replace(self, error_recipe=recipe)
        if estimate is not None:
            out.__dict__["error"] = estimate  # the cached_property's slot
        return out
