"""Error estimates of a transient (``ev.error``): the integrator's global error.

The time integrators of :func:`kinetic_fem.evolve_heated` and
:func:`kinetic_fem.evolve_cooling` control the local error per collision time with the
tolerance ``rtol``, so that the global error of :math:`T` (relative), :math:`a_2`
(absolute) and :math:`\\zeta` is proportional to ``rtol``.  The estimate is computed,
not assumed: the same evolution (same mesh, same options) is run again at
``rtol / RTOL_RATIO`` when ``ev.error`` is first read, and for each output time

.. math::

    \\hat e_Q(t_i) = \\kappa\\,|Q_{\\mathrm{rtol}}(t_i) - Q_{\\mathrm{rtol}/r}(t_i)|,
    \\qquad \\kappa = \\frac{1}{1 - 1/r},

the share of the error the tighter run removes if the global error scales as
``rtol`` (:math:`r` = :data:`RTOL_RATIO`).  The f error at each time is the same
comparison of the distributions (:meth:`kinetic_fem.error.ErrorEstimate.from_comparison`).
This is the error of the time integration only: the velocity mesh is the same in both
runs (the steady results' ``dist.error`` estimates a mesh's error).

Cost: one more evolution at the tighter tolerance (BDF2: about :math:`r^{1/3}` = 2.2
times the steps), paid on first read; a solve costs nothing extra.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .error import ErrorEstimate
from .options import option_default

__all__ = ["EvolutionError", "RTOL_RATIO", "TIGHTER_METHOD", "rerun_recipe"]

logger = logging.getLogger(__name__)

RTOL_RATIO = 100.0
"""The estimate's second run uses ``rtol / RTOL_RATIO``."""
TIGHTER_METHOD = "the same evolution at rtol / 100 (the integrator's global error)"


@dataclass(frozen=True)
class EvolutionError:
    """Estimated errors of an :class:`~kinetic_fem.evolution.Evolution` at its output times.

    The same names as a steady result's :class:`~kinetic_fem.error.ErrorEstimate`, as
    arrays over ``ev.times``.

    Attributes
    ----------
    temperature : ndarray, shape (n_t,)
        Relative error of :math:`T(t_i)`.
    a2 : ndarray, shape (n_t,)
        Absolute error of :math:`a_2(t_i)`.
    zeta : ndarray, shape (n_t,), or None
        Relative error of ``ev.series["zeta"]`` (cooling runs), else None.
    at : tuple of ErrorEstimate
        The estimate at each time, with f (``ev.error.at[i].f(c)``).
    method : str
        How the estimate was obtained.
    rtol : float
        The tolerance of the evolution estimated.
    note : str
        Anything else the user should know.
    """

    temperature: NDArray[np.float64]
    a2: NDArray[np.float64]
    zeta: NDArray[np.float64] | None = None
    at: tuple[ErrorEstimate, ...] = field(default=(), repr=False)
    method: str = ""
    rtol: float = float("nan")
    note: str = ""

    def __repr__(self) -> str:
        """One line: the largest errors over time."""
        def top(x: NDArray[np.float64] | None) -> str:
            return "None" if x is None or x.size == 0 else f"{np.nanmax(x):.2g}"
        return (f"EvolutionError(max temperature={top(self.temperature)}, "
                f"a2={top(self.a2)}, zeta={top(self.zeta)}, rtol={self.rtol:g}, "
                f"method={self.method!r})")

    @property
    def f_max(self) -> NDArray[np.float64]:
        """Largest relative f error (where f > 1e-30) at each time, shape (n_t,)."""
        return np.array([e.f_max for e in self.at])

    def meets(self, target: float) -> bool:
        """Whether T (relative) and a2 (absolute) errors are below ``target`` at all times.

        Parameters
        ----------
        target : float
            The accuracy asked.
        """
        return bool(np.all(self.temperature <= target) and np.all(self.a2 <= target))

    @classmethod
    def unavailable(cls, n_t: int, reason: str) -> EvolutionError:
        """NaNs that say why there is no estimate.

        Parameters
        ----------
        n_t : int
            Output times.
        reason : str
            Why.
        """
        nan = np.full(n_t, np.nan)
        return cls(nan, nan.copy(), None, method="none", note=reason)

    @classmethod
    def from_comparison(cls, ev: Any, better: Any, *, rtol: float,
                        ratio: float = RTOL_RATIO) -> EvolutionError:
        """The estimate from the same evolution at a tighter tolerance.

        Parameters
        ----------
        ev : Evolution
            The result.
        better : Evolution
            The same problem at ``rtol / ratio``, the same output times.
        rtol : float
            ``ev``'s tolerance.
        ratio : float
            The ratio of the tolerances.

        Returns
        -------
        EvolutionError
        """
        kappa = 1.0 / (1.0 - 1.0 / ratio)
        zeta = None
        if "zeta" in ev.series and "zeta" in better.series:
            z, zb = np.asarray(ev.series["zeta"]), np.asarray(better.series["zeta"])
            with np.errstate(divide="ignore", invalid="ignore"):
                zeta = kappa * np.abs(zb / z - 1.0)
        at = tuple(ErrorEstimate.from_comparison(ev[i], better[i], method=TIGHTER_METHOD,
                                                 factor=kappa,
                                                 zeta=None if zeta is None else
                                                 (float(ev.series["zeta"][i]),
                                                  float(better.series["zeta"][i])))
                   for i in range(len(ev)))
        return cls(np.array([e.temperature for e in at]), np.array([e.a2 for e in at]),
                   zeta, at, method=TIGHTER_METHOD, rtol=rtol,
                   note="the time integration's error only (same velocity mesh)")


def default_rtol(solver: Callable[..., Any]) -> float:
    """The default ``rtol`` of a transient solver (from its signature).

    Parameters
    ----------
    solver : callable
        A registered transient solver.
    """
    try:
        return float(option_default(solver, "rtol"))  # a parameter or an option's field
    except KeyError:
        raise TypeError(f"{getattr(solver, '__name__', solver)!r} has no default rtol"
                        ) from None


def rerun_recipe(run: Callable[..., Any], solver: Callable[..., Any],
                 options: dict[str, Any]) -> Callable[[Any], EvolutionError]:
    """``ev -> EvolutionError``: rerun at ``rtol / RTOL_RATIO`` (see the module docstring).

    Parameters
    ----------
    run : callable
        ``run(**options) -> Evolution``: the same call with other options.
    solver : callable
        The registered solver (for its default ``rtol``).
    options : dict
        The options of the result's call.

    Returns
    -------
    callable
    """
    def compute(ev: Any) -> EvolutionError:
        # rtol by keyword, else that of an options object passed, else the default
        given = [o.rtol for o in options.values()
                 if dataclasses.is_dataclass(o) and hasattr(o, "rtol")]
        rtol = float(options.get("rtol", given[0] if given else default_rtol(solver)))
        logger.info("error estimate of an evolution: rerun at rtol=%g", rtol / RTOL_RATIO)
        better = run(**{**options, "rtol": rtol / RTOL_RATIO})
        return EvolutionError.from_comparison(ev, better, rtol=rtol)

    return compute
