"""Error estimates of a result: one object for every method (``dist.error``).

Every :class:`~kinetic_fem.distribution.VelocityDistribution` answers ``dist.error`` with
an :class:`ErrorEstimate`: the relative error of the temperature, the absolute error of
:math:`a_2`, the relative error of the cooling rate :math:`\\zeta` (cooling states) and
the relative error of :math:`f(c)` as a function of :math:`c` where :math:`f > 10^{-30}`.
A particle run's estimate is its batch standard error (``dist.error.a2`` is
``dist.a2_error``); a deterministic result's is computed a posteriori by its method, as
the difference from a better result :math:`\\tilde Q`:

.. math::

    \\hat e_T = \\kappa\\,|\\tilde T/T - 1|, \\quad
    \\hat e_{a_2} = \\kappa\\,|\\tilde a_2 - a_2|, \\quad
    \\hat e_f(c) = \\kappa \\max_{|c' - c| \\lesssim h} |\\tilde f(c')/f(c') - 1|,

- FEM (heated and cooling): :math:`\\tilde Q` after one Newton step from :math:`u_h`
  on the mesh with every element bisected (:func:`bisected_step_distribution`);
  :math:`\\kappa = 1/(1 - 2^{-(k+1)})` for degree :math:`k`, the share of the error of
  :math:`u_h` that the bisected mesh removes;
- finite differences: the Richardson levels (the best level against the one before);
- Sonine (spectral): the order :math:`P + 2`; when successive orders stop converging
  (the series is asymptotic) the estimate is the largest of the last two differences
  and says so (``asymptotic=True``);
- the quasi-elastic limits :math:`\\phi`, :math:`\\psi`: their constants against the
  coarser grid of their own refinement.

A mixture state's estimate (``state.error``, one of these per species plus the
temperature ratios and the common cooling rate) is :mod:`kinetic_fem.mixture_error`.

:math:`\\hat e_f` is an envelope over neighbouring nodes, an error bar rather than a
signed difference that crosses zero.  Estimates of deterministic results are computed
when first read (``dist.error`` is cached), so a solve costs nothing extra; the recipe
does not survive pickling or :meth:`~kinetic_fem.VelocityDistribution.save` (read
``dist.error`` before).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.ndimage import maximum_filter1d

VelocityDistribution = Any
"""A :class:`kinetic_fem.VelocityDistribution` in annotations (not imported: the
distribution module imports this one, and the import graph stays acyclic)."""

__all__ = ["ErrorEstimate", "ErrorRecipe", "F_FLOOR", "ENVELOPE_NODES", "richardson_factor",
           "geometric_tail", "comparison_recipe"]

F_FLOOR = 1e-30
"""f(c) errors are estimated where f(c) exceeds this (30 decades, the paper's range)."""
ENVELOPE_NODES = 9
"""The relative f error at a node is the largest over this many neighbouring nodes
(about one element of the FEM's quadrature points): an error bar, not a difference that
crosses zero between them."""


@dataclass(frozen=True)
class ErrorEstimate:
    """Estimated errors of a result (``dist.error``), the same names for every method.

    Attributes
    ----------
    temperature : float
        Relative error of the temperature, :math:`|\\delta T|/T` (NaN if unknown).
    a2 : float
        Absolute error of :math:`a_2` (for a particle run, ``dist.a2_error``).
    zeta : float or None
        Relative error of the cooling rate where the result has one (cooling states),
        else None.
    c : ndarray, shape (m,)
        Scaled velocities at which the f error is known (increasing).
    f_relative : ndarray, shape (m,)
        Relative error of :math:`f` at ``c``; NaN where :math:`f \\le` :data:`F_FLOOR`,
        ``inf`` where the method does not resolve :math:`f` (a Sonine tail).
    method : str
        How the estimate was obtained.
    asymptotic : bool
        The method's sequence of approximations stopped converging (a Sonine series
        that is asymptotic): the estimate is the size of the last changes and the error
        may be larger.
    note : str
        Anything else the user should know (e.g. why no estimate is available).
    kind : str
        ``"estimate"`` (a posteriori, deterministic methods) or ``"standard error"``
        (one standard error from independent batches, particle methods).
    """

    temperature: float
    a2: float
    zeta: float | None = None
    c: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0), repr=False)
    f_relative: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0), repr=False)
    method: str = ""
    asymptotic: bool = False
    note: str = ""
    kind: str = "estimate"

    def __repr__(self) -> str:
        """One line: the three scalar errors, the largest f error, how they were made."""
        zeta = "" if self.zeta is None else f", zeta={self.zeta:.2g}"
        flags = ", asymptotic=True" if self.asymptotic else ""
        return (f"ErrorEstimate(temperature={self.temperature:.2g}, a2={self.a2:.2g}{zeta}, "
                f"f_max={self.f_max:.2g}, method={self.method!r}{flags})")

    def f(self, c: ArrayLike) -> NDArray[np.float64]:
        """Relative error of :math:`f(c)` (linear interpolation of the nodal envelope).

        NaN outside the nodes and where :math:`f \\le` :data:`F_FLOOR`.

        Parameters
        ----------
        c : array_like
            Scaled velocities.

        Returns
        -------
        ndarray
        """
        c = np.asarray(c, dtype=float)
        if self.c.size < 2:
            return np.full(c.shape, np.nan)
        # inf (unresolved) carried through the interpolation as a huge finite value
        huge = np.finfo(float).max / 4
        out = np.interp(c, self.c, np.minimum(self.f_relative, huge), left=np.nan,
                        right=np.nan)
        return np.where(out >= huge, np.inf, out)

    @property
    def f_max(self) -> float:
        """Largest relative f error over the nodes where :math:`f >` :data:`F_FLOOR`
        (``inf`` if a method does not resolve f somewhere there)."""
        ok = ~np.isnan(self.f_relative)
        return float(self.f_relative[ok].max()) if ok.any() else float("nan")

    def meets(self, target: float) -> bool:
        """Whether the temperature (relative) and a2 (absolute) errors are below ``target``.

        Parameters
        ----------
        target : float
            The accuracy asked.
        """
        return bool(self.temperature <= target and self.a2 <= target)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def unavailable(cls, reason: str, *, method: str = "none") -> ErrorEstimate:
        """An estimate of NaNs that says why there is none.

        Parameters
        ----------
        reason : str
            Why the result carries no estimate.
        method : str
            Recorded as :attr:`method`.
        """
        return cls(float("nan"), float("nan"), None, method=method, note=reason)

    @classmethod
    def from_batches(cls, dist: VelocityDistribution) -> ErrorEstimate:
        """Standard errors of a sampled distribution from its independent batches.

        Parameters
        ----------
        dist : VelocityDistribution
            A distribution with ``batch_moments`` (and ``errors`` for f).
        """
        t = dist.temperature
        rel_t = dist.observable_error(lambda d: d.temperature) / t
        c = dist.c
        f_rel = np.full(c.shape, np.nan)
        if dist.errors is not None:
            fv = dist.f_values
            ok = fv > F_FLOOR
            f_rel[ok] = dist.errors[ok] / dist.values[ok]
        zeta = None
        return cls(rel_t, dist.a2_error, zeta, c, f_rel, method="batch standard error",
                   kind="standard error")

    @classmethod
    def from_comparison(cls, dist: VelocityDistribution, better: VelocityDistribution, *,
                        method: str, factor: float = 1.0,
                        zeta: tuple[float, float] | None = None, asymptotic: bool = False,
                        note: str = "", envelope: int = ENVELOPE_NODES) -> ErrorEstimate:
        """The estimate ``factor`` times the difference of ``dist`` from ``better``.

        Parameters
        ----------
        dist : VelocityDistribution
            The result (any units: every measure is scale free).
        better : VelocityDistribution
            A more accurate result of the same problem.
        method : str
            How ``better`` was obtained.
        factor : float
            :math:`\\kappa`: the ratio of the result's error to the difference.
        zeta : (float, float), optional
            The result's and the better result's cooling rates.
        asymptotic, note
            As the attributes.
        envelope : int
            Nodes of the running maximum of the f error (:data:`ENVELOPE_NODES`).

        Returns
        -------
        ErrorEstimate
        """
        c = dist.c
        mine = dist.f_values
        theirs = better.f(c)
        f_rel = np.full(c.shape, np.nan)
        ok = mine > F_FLOOR
        pos = ok & (theirs > 0)
        f_rel[pos] = np.abs(mine[pos] / theirs[pos] - 1.0)
        f_rel[ok & ~pos] = 1.0  # the better result is not positive there: no digit
        filled = np.where(ok, f_rel, 0.0)
        env = maximum_filter1d(filled, size=max(1, envelope), mode="nearest")
        f_rel = np.where(ok, factor * env, np.nan)
        d_zeta = None if zeta is None else factor * abs(zeta[1] / zeta[0] - 1.0)
        return cls(factor * abs(better.temperature / dist.temperature - 1.0),
                   factor * abs(better.a2 - dist.a2), d_zeta, c, f_rel, method=method,
                   asymptotic=asymptotic, note=note)

    def scaled(self, factor: float, *, method: str | None = None) -> ErrorEstimate:
        """This estimate with every error multiplied by ``factor``.

        Parameters
        ----------
        factor : float
            Multiplier.
        method : str, optional
            A new :attr:`method`.
        """
        return ErrorEstimate(self.temperature * factor, self.a2 * factor,
                             None if self.zeta is None else self.zeta * factor, self.c,
                             self.f_relative * factor, method=method or self.method,
                             asymptotic=self.asymptotic, note=self.note, kind=self.kind)

    def as_dict(self) -> dict[str, Any]:
        """The scalar errors as a JSON-serialisable dict (``f_max`` for the f error)."""
        return {"temperature": float(self.temperature), "a2": float(self.a2),
                "zeta": None if self.zeta is None else float(self.zeta),
                "f_max": self.f_max, "method": self.method, "asymptotic": self.asymptotic,
                "note": self.note, "kind": self.kind}


class ErrorRecipe:
    """How to compute a deterministic result's :class:`ErrorEstimate` when first asked.

    Holds a callable ``dist -> ErrorEstimate`` (a closure over the solver's state).  It
    does not survive pickling (it pickles as a recipe that reports the estimate as
    unavailable): read ``dist.error`` before sending a result to another process.

    Parameters
    ----------
    compute : callable
        ``dist -> ErrorEstimate``; ``dist`` is the result in its own units.
    method : str
        Short description of the estimate (for the unavailable case).
    """

    def __init__(self, compute: Callable[[VelocityDistribution], ErrorEstimate] | None,
                 method: str) -> None:
        self.compute = compute
        self.method = method

    def __call__(self, dist: VelocityDistribution) -> ErrorEstimate:
        """The estimate of ``dist``."""
        if self.compute is None:
            return ErrorEstimate.unavailable(
                f"the {self.method} estimate was not computed before the result was "
                "pickled; read dist.error in the process that solved", method=self.method)
        return self.compute(dist)

    def __reduce__(self) -> tuple[Any, ...]:
        return (ErrorRecipe, (None, self.method))

    def __repr__(self) -> str:
        return f"ErrorRecipe({self.method!r})"


def richardson_factor(order: int) -> float:
    """:math:`1/(1 - 2^{-(k+1)})`: the error of a degree-``k`` FEM state over its change on
    the bisected mesh (errors of :math:`\\ln P_h` scale as :math:`h^{k+1}`).

    Parameters
    ----------
    order : int
        Lagrange degree.
    """
    return 1.0 / (1.0 - 2.0 ** -(order + 1))


def geometric_tail(differences: list[float]) -> tuple[float, bool]:
    """Error of the last of a sequence of approximations from its last changes.

    ``differences`` are :math:`|Q_{k} - Q_{k-1}|` in order, ending with the change to a
    better approximation than the result (:math:`|Q_{k+1} - Q_k|`, the result being
    :math:`Q_k`).  While they decrease (ratio :math:`r < 1`) the error of :math:`Q_k` is
    the geometric sum :math:`d_{k+1}/(1 - r)`; when they stop decreasing the sequence is
    asymptotic and the estimate is the largest of the last two, flagged.

    Parameters
    ----------
    differences : list of float
        At least one change; the last is the one beyond the result.

    Returns
    -------
    estimate : float
    asymptotic : bool
    """
    last = differences[-1]
    if len(differences) < 2 or not math.isfinite(differences[-2]):
        return last, False
    prev = differences[-2]
    if prev > 0 and last < prev:
        return last / (1.0 - last / prev), False
    return max(last, prev), True


def comparison_recipe(pair: Callable[[], tuple[VelocityDistribution, VelocityDistribution]],
                      method: str, *, factor: float = 1.0,
                      zeta: tuple[float, float] | None = None) -> ErrorRecipe:
    """A recipe comparing two distributions made when it is called.

    Parameters
    ----------
    pair : callable
        ``() -> (result, better)`` in the same units (the result's own units need not
        be those: every measure is scale free).
    method : str
        How ``better`` was obtained.
    factor : float
        As in :meth:`ErrorEstimate.from_comparison`.
    zeta : (float, float), optional
        The result's and the better result's cooling rates.

    Returns
    -------
    ErrorRecipe
    """
    def compute(dist: VelocityDistribution) -> ErrorEstimate:
        mine, better = pair()
        return ErrorEstimate.from_comparison(mine, better, method=method, factor=factor,
                                             zeta=zeta)

    return ErrorRecipe(compute, method)
