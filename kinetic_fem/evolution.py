"""The result of a time-dependent computation: :class:`Evolution`.

An evolution holds the velocity distribution :math:`P(v, t_i)` at the requested
output times :math:`t_i` (each on its own nodes with its own quadrature weights, so
that a cooling gas whose temperature falls by many decades keeps its resolution), and
the observables over time computed from them:

.. math::

    T(t) = \\langle v^2 \\rangle, \\qquad
    a_2(t) = \\frac{\\langle v^4 \\rangle}{3T^2} - 1, \\qquad
    a_p(t) = \\langle S_p(c^2) \\rangle / \\mathcal N_p \\ (p \\le 6),

with :math:`c = v/\\sqrt T` (see :mod:`kinetic_fem.distribution`).  ``ev[i]`` is the
:class:`~kinetic_fem.distribution.VelocityDistribution` at ``ev.times[i]``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from .distribution import MAX_SONINE, RunInfo, VelocityDistribution
from .files import check_loaded_values, json_entry, npz_path, read_npz, reading

__all__ = ["Evolution"]


@dataclass(frozen=True)
class Evolution:
    """Velocity distributions at a sequence of times, with observables over time.

    Attributes
    ----------
    times : ndarray, shape (n_t,)
        Output times (physical units).
    grid : ndarray, shape (n_t, n_v)
        Velocities of the nodes at each time.
    values : ndarray, shape (n_t, n_v)
        :math:`P(v, t_i)` at ``grid[i]``.
    weights : ndarray, shape (n_t, n_v)
        Quadrature weights of ``grid[i]``.
    method : str
        Registry key of the method (``"fem"``).
    params : dict
        Problem parameters (and a description of the protocol).
    info : RunInfo
        Steps taken and rejected, Newton iterations, wall time.
    series : dict of str to ndarray, shape (n_t,)
        Further quantities at the output times (``"zeta"`` of a cooling run,
        ``"diffusion"``, ``"friction"``, ``"mass"``).
    error_recipe : callable, optional
        ``ev -> EvolutionError``: how :attr:`error` is computed when first read (set by
        :func:`kinetic_fem.evolve_heated` and :func:`kinetic_fem.evolve_cooling`; not
        saved).
    """

    times: NDArray[np.float64]
    grid: NDArray[np.float64]
    values: NDArray[np.float64]
    weights: NDArray[np.float64]
    method: str = ""
    params: Mapping[str, Any] = field(default_factory=dict)
    info: RunInfo = field(default_factory=RunInfo)
    series: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    error_recipe: Callable[[Any], Any] | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        times = np.asarray(self.times, dtype=float)
        shape = (times.size, np.shape(self.grid)[-1])
        for name in ("grid", "values", "weights"):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.shape != shape:
                raise ValueError(f"{name} must have shape (n_t, n_v) = {shape}, got {arr.shape}")
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "series", {k: np.asarray(v, dtype=float)
                                            for k, v in self.series.items()})
        dists = tuple(VelocityDistribution.from_values(
            self.grid[i], self.values[i], weights=self.weights[i], normalize=False)
            for i in range(times.size))
        object.__setattr__(self, "_dists", dists)

    # ------------------------------------------------------------------ access
    def __len__(self) -> int:
        return int(self.times.size)

    def __getitem__(self, i: int) -> VelocityDistribution:
        """The distribution at ``times[i]`` (with this run's method, params and info)."""
        d = self._dists[i]  # type: ignore[attr-defined]
        return VelocityDistribution(v=d.v, values=d.values, raw_moments=d.raw_moments,
                                    method=self.method, params=dict(self.params),
                                    info=self.info)

    def __repr__(self) -> str:
        t = self.times
        span = f"t={t[0]:.4g}..{t[-1]:.4g}" if t.size else "no times"
        temp = f", T={self.temperature[0]:.4g}->{self.temperature[-1]:.4g}" if t.size else ""
        return (f"Evolution(method={self.method!r}, {t.size} times {span}{temp}, "
                f"{self.grid.shape[1]} nodes, {self.info.iterations} steps)")

    # ------------------------------------------------------------------ observables
    def _observable(self, fn) -> NDArray[np.float64]:
        return np.array([fn(d) for d in self._dists])  # type: ignore[attr-defined]

    @property
    def temperature(self) -> NDArray[np.float64]:
        """:math:`T(t_i) = \\langle (v - u)^2 \\rangle`, shape (n_t,)."""
        return self._observable(lambda d: d.temperature)

    @property
    def mass(self) -> NDArray[np.float64]:
        """:math:`\\int P(v, t_i)\\,dv` by the nodes' quadrature, shape (n_t,)."""
        return self._observable(lambda d: d.raw_moments[0])

    @property
    def a2(self) -> NDArray[np.float64]:
        """Kurtosis excess :math:`a_2(t_i)`, shape (n_t,)."""
        return self._observable(lambda d: d.a2)

    def moment(self, k: int) -> NDArray[np.float64]:
        """Central moment :math:`\\langle (v-u)^k \\rangle(t_i)`, shape (n_t,)."""
        return self._observable(lambda d: d.moment(k))

    def sonine_coefficient(self, p: int) -> NDArray[np.float64]:
        """:math:`a_p(t_i)`, ``2 <= p <= 6``, shape (n_t,)."""
        if not 2 <= p <= MAX_SONINE:
            raise ValueError(f"Sonine order p={p!r} is outside 2..{MAX_SONINE}")
        return self._observable(lambda d: d.sonine_coefficient(p))

    @property
    def sonine(self) -> NDArray[np.float64]:
        """:math:`a_2 \\dots a_6` over time, shape (n_t, 5)."""
        return np.stack([self.sonine_coefficient(p) for p in range(2, MAX_SONINE + 1)], axis=1)

    # ------------------------------------------------------------------ error estimate
    @cached_property
    def error(self) -> Any:
        """Estimated errors at the output times (an
        :class:`~kinetic_fem.evolution_error.EvolutionError`).

        ``ev.error.temperature`` (relative), ``ev.error.a2``, ``ev.error.zeta`` (cooling)
        are arrays over :attr:`times`; ``ev.error.at[i]`` is the
        :class:`~kinetic_fem.error.ErrorEstimate` at ``times[i]`` (with f).  Computed
        when first read by rerunning at a tighter tolerance
        (:mod:`kinetic_fem.evolution_error`) and cached; NaNs with a note for an
        evolution without a recipe (loaded or built by hand).
        """
        from .evolution_error import EvolutionError

        if self.error_recipe is None:
            return EvolutionError.unavailable(
                len(self), "no error estimate for this evolution: only the results of "
                "kinetic_fem.evolve_heated / evolve_cooling carry one (not saved)")
        return self.error_recipe(self)

    def with_error(self, recipe: Callable[[Any], Any] | None) -> Evolution:
        """A copy whose :attr:`error` is computed by ``recipe`` (the entry points call this).

        Parameters
        ----------
        recipe : callable or None
            ``ev -> EvolutionError``.
        """
        return replace(self, error_recipe=recipe)

    # ------------------------------------------------------------------ io, plot
    def save(self, path: str | Path) -> Path:
        """Write to ``.npz`` (arrays; parameters and run info as JSON).

        Examples
        --------
        >>> import tempfile, os
        >>> v = np.linspace(-8, 8, 161)[None, :]
        >>> ev = Evolution([0.0], v, np.exp(-v**2 / 2) / np.sqrt(2 * np.pi),
        ...                np.full_like(v, 0.1), method="test")
        >>> back = Evolution.load(ev.save(os.path.join(tempfile.mkdtemp(), "ev.npz")))
        >>> bool(np.allclose(back.temperature, ev.temperature)), back.method
        (True, 'test')
        """
        path = npz_path(path)
        meta = {"method": self.method, "params": dict(self.params),
                "info": {"converged": self.info.converged,
                         "iterations": self.info.iterations,
                         "residual": self.info.residual, "wall_time": self.info.wall_time,
                         "message": self.info.message, "extra": dict(self.info.extra)}}
        arrays: dict[str, Any] = {f"series_{k}": v for k, v in self.series.items()}
        np.savez_compressed(path, times=self.times, grid=self.grid, values=self.values,
                            weights=self.weights, meta=np.array(json.dumps(meta, default=str)),
                            **arrays)
        return path

    @classmethod
    def load(cls, path: str | Path) -> Evolution:
        """Read what :meth:`save` wrote.

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        kinetic_fem.exceptions.FileFormatError
            If the file is damaged, foreign or holds non-finite values.
        """
        what = "Evolution .npz (Evolution.save)"
        data = read_npz(path, what=what, required=("meta", "times", "grid", "values", "weights"))
        meta = json_entry(data, "meta", path, what)
        check_loaded_values(path, times=data["times"], grid=data["grid"], values=data["values"],
                            weights=data["weights"])
        series = {k[len("series_"):]: data[k] for k in data if k.startswith("series_")}
        with reading(path, what):
            return cls(data["times"], data["grid"], data["values"], data["weights"],
                       method=meta["method"], params=meta["params"],
                       info=RunInfo(**meta["info"]), series=series)

    def plot(self, path: str | Path | None = None, *, axes=None, label: str | None = None,
             logx: bool = False):
        """Plot :math:`T(t)` and :math:`a_2(t)`; save to ``path`` if given.

        The figure is made without pyplot (:func:`kinetic_fem.plot.new_axes`), so no
        backend is chosen; :func:`kinetic_fem.plot.save_figure` writes it.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plot import new_axes, save_figure

        if axes is None:
            axes = new_axes(2, width=4.5, height=3.5)
            fig = axes[0].figure
        else:
            fig = axes[0].figure
        t = self.times
        temp = self.temperature
        axes[0].plot(t, temp, label=label)
        axes[1].plot(t, self.a2, label=label)
        if temp.min() > 0 and temp.max() / temp.min() > 100:
            axes[0].set_yscale("log")
        for ax, name in zip(axes, ("temperature $T$", "$a_2$"), strict=True):
            ax.set_xlabel("time $t$")
            ax.set_ylabel(name)
            if logx:
                ax.set_xscale("log")
        if label is not None:
            axes[0].legend()
        if path is not None:
            save_figure(fig, path)
        return fig

    # ------------------------------------------------------------------ one-line views
    def to_xarray(self) -> Any:
        """An ``xarray.Dataset`` over time (:func:`kinetic_fem.export.evolution_dataset`)."""
        from .export import evolution_dataset

        return evolution_dataset(self)

    def _repr_html_(self) -> str:
        """A small table for Jupyter (:func:`kinetic_fem.export.evolution_html`)."""
        from .export import evolution_html

        return evolution_html(self)
