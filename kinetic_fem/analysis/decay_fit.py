"""Late exponential decay of an ensemble of relaxation curves, with error bars.

Near a steady state :math:`T(t) = T_\\infty + \\sum_k A_k e^{-\\lambda_k t}`; once the
faster modes have died out the slowest rate :math:`\\lambda_1` is the slope of
:math:`\\ln|T - T_\\infty|`.  :func:`fit_decay` fits :math:`T_\\infty + A e^{-\\lambda t}`
(three parameters: the particle method's own :math:`T_\\infty` may carry a small
finite-``N`` or time-step bias) to the ensemble mean of replica curves on a window,
weighted by the standard errors, and takes the error bars of :math:`\\lambda` from a
delete-one-group jackknife over the replicas (so correlations between output times
of one replica are accounted for).  The bias of the window (faster modes not yet
gone) is measured separately, by fitting a noise-free curve of known rate on the same
window (e.g. the first-Sonine curve, :func:`window_bias`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import curve_fit

__all__ = ["DecayFit", "fit_decay", "window_bias"]


@dataclass(frozen=True)
class DecayFit:
    """A fitted decay :math:`T_\\infty + A e^{-\\lambda t}`.

    Attributes
    ----------
    rate, rate_error : float
        :math:`\\lambda` and its standard error (jackknife; 0 for one curve).
    asymptote, asymptote_error : float
        :math:`T_\\infty` and its standard error.
    amplitude : float
        :math:`A`.
    window : (float, float)
        Fitted time window.
    chi2_dof : float
        :math:`\\chi^2` per degree of freedom of the mean curve (diagonal weights).
    """

    rate: float
    rate_error: float
    asymptote: float
    asymptote_error: float
    amplitude: float
    window: tuple[float, float]
    chi2_dof: float


def _model(t: NDArray[np.float64], t_inf: float, amp: float, rate: float) -> NDArray[np.float64]:
    return t_inf + amp * np.exp(-rate * t)


def _fit(t: NDArray[np.float64], y: NDArray[np.float64], sigma: NDArray[np.float64] | None,
         guess: tuple[float, float, float]) -> NDArray[np.float64]:
    popt, _ = curve_fit(_model, t, y, p0=guess, sigma=sigma, absolute_sigma=True, maxfev=20000)
    return np.asarray(popt, dtype=float)


def fit_decay(times: ArrayLike, replicas: ArrayLike, window: tuple[float, float], *,
              rate_guess: float, groups: int = 16) -> DecayFit:
    """Fit :math:`T_\\infty + A e^{-\\lambda t}` to the mean of replica curves on a window.

    Parameters
    ----------
    times : array_like, shape (n_t,)
        Output times.
    replicas : array_like, shape (R, n_t)
        One curve per replica (``R = 1``: a deterministic curve, no error bars).
    window : (float, float)
        Times ``t0 <= t <= t1`` used.
    rate_guess : float
        Starting value of :math:`\\lambda`.
    groups : int
        Jackknife groups (at most ``R``).

    Returns
    -------
    DecayFit

    Raises
    ------
    ValueError
        With fewer than 4 times in the window or a non-positive ``rate_guess``.

    Examples
    --------
    >>> t = np.linspace(0.0, 5.0, 51)
    >>> fit = fit_decay(t, [2.0 - np.exp(-0.7 * t)], (1.0, 5.0), rate_guess=1.0)
    >>> round(fit.rate, 8), round(fit.asymptote, 8)
    (0.7, 2.0)
    """
    t = np.asarray(times, dtype=float)
    y = np.atleast_2d(np.asarray(replicas, dtype=float))
    if y.shape[1] != t.size:
        raise ValueError(f"replicas have {y.shape[1]} times, expected {t.size}")
    if not (math.isfinite(rate_guess) and rate_guess > 0):
        raise ValueError(f"rate_guess={rate_guess!r} must be finite and > 0")
    sel = (t >= window[0]) & (t <= window[1])
    if sel.sum() < 4:
        raise ValueError(f"the window {window} holds {int(sel.sum())} times; need >= 4")
    ts, ys = t[sel], y[:, sel]
    r = ys.shape[0]
    mean = ys.mean(axis=0)
    sigma = ys.std(axis=0, ddof=1) / math.sqrt(r) if r > 1 else None
    span = math.exp(-rate_guess * ts[0]) - math.exp(-rate_guess * ts[-1])
    amp0 = (mean[0] - mean[-1]) / max(span, 1e-300)
    guess = (float(mean[-1] - amp0 * math.exp(-rate_guess * ts[-1])), float(amp0),
             float(rate_guess))
    best = _fit(ts, mean, sigma, guess)
    resid = (mean - _model(ts, *best)) / (sigma if sigma is not None else 1.0)
    chi2 = float(np.sum(resid**2) / max(ts.size - 3, 1))
    if r == 1:
        return DecayFit(float(best[2]), 0.0, float(best[0]), 0.0, float(best[1]),
                        (float(window[0]), float(window[1])), chi2)
    g = min(groups, r)
    labels = np.arange(r) % g
    jack = []
    for k in range(g):
        keep = ys[labels != k]
        sig = keep.std(axis=0, ddof=1) / math.sqrt(keep.shape[0])
        jack.append(_fit(ts, keep.mean(axis=0), sig, tuple(best)))
    jk = np.array(jack)
    err = np.sqrt((g - 1) / g * np.sum((jk - jk.mean(axis=0)) ** 2, axis=0))
    return DecayFit(float(best[2]), float(err[2]), float(best[0]), float(err[0]),
                    float(best[1]), (float(window[0]), float(window[1])), chi2)


def window_bias(times: ArrayLike, curve: ArrayLike, window: tuple[float, float],
                true_rate: float) -> float:
    """Relative bias of :func:`fit_decay` on ``window`` for a noise-free curve.

    Parameters
    ----------
    times : array_like, shape (n_t,)
        Output times.
    curve : array_like, shape (n_t,)
        A deterministic relaxation curve whose slowest rate is ``true_rate``.
    window : (float, float)
        The fit window.
    true_rate : float
        The known slowest rate.

    Returns
    -------
    float
        ``fitted / true_rate - 1``.
    """
    fit = fit_decay(times, [np.asarray(curve, dtype=float)], window, rate_guess=true_rate)
    return fit.rate / true_rate - 1.0
