"""Steady states of the FEM heated solver: the state, its interpolation, checks.

:class:`SteadyState` (a converged :math:`u_h = \\ln P_h` with its discretisation),
:func:`check_energy_input` (refuses spurious discrete states) and :func:`nested_coarse`
(the coarse mesh of the mesh sequencing in :func:`kinetic_fem.solvers.fem.steady_state`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...distribution import RunInfo
from ...exceptions import ConvergenceError
from ...operators.fem_discretisation import FEMDiscretisation
from ...operators.fem_kernels import evaluate_field
from .newton import transport_arrays

__all__ = ["SteadyState", "check_energy_input", "nested_coarse", "SEQUENCE_BAND",
           "LazyExtra", "state_temperature"]

SEQUENCE_BAND = 8
"""Elements at each end kept fine in the coarse mesh (:func:`nested_coarse`)."""


def nested_coarse(vertices: NDArray, factor: int, band: int = SEQUENCE_BAND) -> NDArray:
    """Every ``factor``-th vertex from 0 outwards, all of the last ``band`` elements.

    The coarse mesh of the mesh sequencing: nested in ``vertices`` and equal to it at
    the ends, where the zero-flux condition bends :math:`\\ln P_h` in a layer a few
    elements wide (a coarser mesh gets that layer wrong by O(1) in :math:`\\ln P`).

    Parameters
    ----------
    vertices : ndarray
        Symmetric increasing vertices with one at 0.
    factor : int
        Coarsening factor of the interior.
    band : int
        Elements kept at each end.

    Returns
    -------
    ndarray
    """
    half = vertices[vertices >= 0.0]
    n = half.size - 1
    keep = np.union1d(np.arange(0, max(n - band, 0), factor), np.arange(max(n - band, 0), n + 1))
    kept = half[keep]
    return np.concatenate([-kept[:0:-1], kept])


class LazyExtra(dict):
    """A ``dict`` of run figures some of which are computed on first read.

    ``info.extra`` of a heated FEM state: the loss side of C1 costs one collision-kernel
    call (about a residual, 13-20 % of a solve), so it is evaluated only when the figures
    are read (any key lookup, iteration, comparison, copy, pickling or JSON export),
    from the state it was made for, then stored; the value is the eager one bit for
    bit.  Pickles (and :func:`dataclasses.asdict` copies) as a plain ``dict``.

    Parameters
    ----------
    *args, **kwargs
        The figures known now, as for ``dict``.
    lazy : callable, optional
        ``() -> dict`` of the remaining figures (called at most once).
    """

    def __init__(self, *args: Any, lazy: Callable[[], dict[str, Any]] | None = None,
                 **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._lazy = lazy

    def _resolve(self) -> None:
        lazy, self._lazy = self._lazy, None
        if lazy is not None:
            super().update(lazy())

    def __getitem__(self, key: Any) -> Any:
        self._resolve()
        return super().__getitem__(key)

    def __contains__(self, key: object) -> bool:
        self._resolve()
        return super().__contains__(key)

    def __iter__(self) -> Iterator[Any]:
        self._resolve()
        return super().__iter__()

    def __len__(self) -> int:
        self._resolve()
        return super().__len__()

    def __eq__(self, other: object) -> bool:
        self._resolve()
        return super().__eq__(other)

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        self._resolve()
        return super().__repr__()

    def __reduce__(self) -> tuple[Any, ...]:
        self._resolve()
        return (dict, (dict(super().items()),))

    def get(self, key: Any, default: Any = None) -> Any:
        """``dict.get`` (computes the lazy figures first)."""
        self._resolve()
        return super().get(key, default)

    def keys(self):  # type: ignore[override]
        """``dict.keys`` (computes the lazy figures first)."""
        self._resolve()
        return super().keys()

    def items(self):  # type: ignore[override]
        """``dict.items`` (computes the lazy figures first)."""
        self._resolve()
        return super().items()

    def values(self):  # type: ignore[override]
        """``dict.values`` (computes the lazy figures first)."""
        self._resolve()
        return super().values()

    def copy(self) -> dict[str, Any]:  # type: ignore[override]
        """A plain ``dict`` with every figure."""
        self._resolve()
        return dict(super().items())


@dataclass(frozen=True, eq=False)
class SteadyState:
    """A converged steady state at ``n = D = 1``: discretisation, ``u_h = ln P_h``, run info.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation (velocities at ``n = D = 1``).
    u : ndarray, shape (n_dofs,)
        Coefficients of :math:`u_h = \\ln P_h`.
    info : RunInfo
        Convergence report.
    """

    disc: FEMDiscretisation
    u: NDArray[np.float64]
    info: RunInfo

    def initial_guess(self, v: NDArray, temperature: float, *,
                      linear_tail: bool = False) -> NDArray:
        """``ln P`` at ``v`` of this state's f(c) at another ``temperature``.

        Beyond the mesh, ``ln f`` continues as a Gaussian, or with ``linear_tail``
        linearly with its slope at the edge (exponential tails).
        """
        dist = self.disc.distribution(self.u)
        s_old, s_new = math.sqrt(dist.temperature), math.sqrt(temperature)
        c = v / s_new
        edge = 0.999 * self.disc.vertices[-1] / s_old
        c_in = np.clip(c, -edge, edge)
        order = np.argsort(c_in)
        log_f = np.empty_like(c)
        log_f[order] = np.log(self.disc.evaluate(self.u, c_in[order] * s_old) * s_old)
        if linear_tail:
            ends = np.log(self.disc.evaluate(self.u, np.array([0.97, 1.0]) * edge * s_old))
            slope = min((ends[1] - ends[0]) / (0.03 * edge), 0.0)
            return log_f + slope * (np.abs(c) - np.abs(c_in)) - math.log(s_new / s_old)
        return log_f - 0.5 * (c**2 - c_in**2) - math.log(s_new)

    def log_density(self, v: NDArray) -> NDArray:
        """:math:`u_h = \\ln P_h` at points ``v`` inside the mesh (any order).

        Parameters
        ----------
        v : ndarray
            Velocities in ``[v_0, v_E]`` (``n = D = 1``).

        Returns
        -------
        ndarray
        """
        verts, dofs = self.disc.mesh_arrays
        v = np.clip(np.asarray(v, dtype=float), verts[0], verts[-1])
        order = np.argsort(v)
        out = np.empty_like(v)
        out[order] = evaluate_field(verts, dofs, self.disc.order, np.ascontiguousarray(self.u),
                                    np.ascontiguousarray(v[order]))
        return out

    def energy_terms(self) -> tuple[float, float]:
        """Discrete input :math:`-\\sum_i v_i^2 \\int\\varphi_i' (P' + \\xi v P)` and the pair
        loss.

        With P2 and the full bracket the two are equal at a steady state up to the
        Newton tolerance (:math:`\\sum_i v_i^2\\varphi_i = v^2`), with the reduced
        bracket up to the quadrature error; the injection differs from
        :math:`2D \\int P_h` by the quadrature error of one integration by parts.
        """
        x = self.disc.dof_locations
        heat, _ = self.disc.transport(self.u)
        return float(np.sum(x**2 * heat)), float(self.disc.energy_loss(self.u, even=True))


def state_temperature(disc: FEMDiscretisation, u: NDArray) -> float:
    """Temperature of :math:`P_h = e^{u_h}` by the outer quadrature: the figure of
    ``disc.distribution(u).temperature`` (equal to round-off) without the
    :class:`~kinetic_fem.distribution.VelocityDistribution` and its twelve moments (1-2 ms,
    about 2 % of a heated state each time).

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation.
    u : ndarray
        Coefficients of :math:`u_h = \\ln P_h`.

    Returns
    -------
    float
    """
    forms = transport_arrays(disc)
    wp = forms.dx * forms.fields(u)[2]
    x = forms.x
    m0 = float(np.sum(wp))
    m1 = float(np.sum(wp * x)) / m0
    return float(np.sum(wp * x * x)) / m0 - m1 * m1


def check_energy_input(disc: FEMDiscretisation, u: NDArray, temperature: float,
                        alpha: float) -> None:
    """Refuse a spurious discrete state: the discrete energy input must be the
    continuum's :math:`2D - 2\\xi T` (``D = 1``) to the quadrature error (P2; checked to
    1 %, a truncated tail leaks less); a state whose :math:`\\ln P_h` oscillates between
    quadrature points violates it grossly (measured: 0.147 against 2, Maxwell model at
    alpha = 0.9).

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation of the state.
    u : ndarray
        Coefficients of :math:`u_h = \\ln P_h`.
    temperature : float
        The state's temperature (``n = D = 1``).
    alpha : float
        Restitution coefficient, for the message.

    Raises
    ------
    ConvergenceError
        If the energy input is off by more than 1 %.
    """
    x = disc.dof_locations
    injection = float(np.sum(x**2 * transport_arrays(disc).transport(u)[0]))
    expected = 2.0 - 2.0 * disc.friction * temperature
    if abs(injection - expected) > 1e-2 * 2.0:
        raise ConvergenceError(
            f"FEM Newton reached a spurious discrete state at alpha={alpha} (energy input "
            f"{injection:.4g}, the continuum gives {expected:.4g}; ln P oscillates between "
            "quadrature points): refine the mesh (smaller spacing) or give explicit vertices")
