"""Fits to solutions: the far-tail amplitude (claim C4) and relaxation times (claim C2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..distribution import VelocityDistribution
from ..sonine import tail_exponent_amplitude

__all__ = ["TailFit", "tail_fit", "relaxation_fit"]


@dataclass(frozen=True)
class TailFit:
    """Fit of :math:`\\ln f = -A c^{3/2} + \\beta \\ln c + \\gamma` over ``c_range``.

    Parameters
    ----------
    amplitude : float
        Fitted :math:`A` (units of c).
    predicted : float
        The C4 prediction :math:`A_c = \\tfrac23 T^{3/4}`.
    beta : float
        Fitted power of the prefactor.
    c_range : tuple of float
        Range of ``c`` fitted.
    """

    amplitude: float
    predicted: float
    beta: float
    c_range: tuple[float, float]


def tail_fit(dist: VelocityDistribution, *, f_range: tuple[float, float] = (1e-60, 1e-30)
             ) -> TailFit:
    """Far-tail amplitude (C4) in units of c, from nodes with f in ``f_range``.

    Parameters
    ----------
    dist : VelocityDistribution
        A heated steady state resolved to ``f`` below ``f_range[0]``.
    f_range : tuple of float
        Fit the nodes with ``f`` in this range.

    Returns
    -------
    TailFit
    """
    c, f = dist.c, dist.f_values
    sel = (c > 0) & (f > f_range[0]) & (f < f_range[1])
    basis = np.stack([-c[sel] ** 1.5, np.log(c[sel]), np.ones(sel.sum())], axis=1)
    coef = np.linalg.lstsq(basis, np.log(f[sel]), rcond=None)[0]
    predicted = tail_exponent_amplitude(temperature=dist.temperature)
    return TailFit(float(coef[0]), predicted, float(coef[1]),
                   (float(c[sel].min()), float(c[sel].max())))


def relaxation_fit(dist: VelocityDistribution, *, window: tuple[float, float] = (1e-2, 1e-5)
                   ) -> float:
    """Relaxation time of T(t) in ``dist.series``: exponential fit of :math:`|T - T_\\infty|`.

    The fit uses the times where the deviation lies between ``window`` times its initial
    value, i.e. the late, linear approach to the steady state.

    Parameters
    ----------
    dist : VelocityDistribution
        A transient with ``dist.series["time"]`` and ``["temperature"]``.
    window : tuple of float
        Fit where the deviation lies between these fractions of its initial value.

    Returns
    -------
    float
        The relaxation time.
    """
    t, temp = dist.series["t"], dist.series["temperature"]
    dev = np.abs(temp - dist.temperature)
    sel = (dev < window[0] * dev[0]) & (dev > window[1] * dev[0])
    if sel.sum() < 3:
        raise ValueError("too few points of the transient in the fit window")
    return float(-1.0 / np.polyfit(t[sel], np.log(dev[sel]), 1)[0])
