"""Validation of plain parameters, where they enter the package.

Every public entry point converts its arguments through these functions, so a bad
value fails at once with a message that says what was wrong and what is allowed;
solvers and kernels below trust what they are given.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["check_times", "check_real", "check_alpha", "check_positive", "check_nonnegative",
           "check_finite_array", "UnsupportedModelError"]


class UnsupportedModelError(ValueError):
    """A method was asked to solve a model (kernel, restitution law, thermostat) it cannot.

    The message names the method, what it was given and what it supports.
    """


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a float; refuse non-numbers, booleans and NaN.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : float
        The value to check.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``value`` is not a real number or is a bool.
    ValueError
        If ``value`` is NaN.

    Examples
    --------
    >>> check_real("gamma", 1)
    1.0
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    value = float(value)
    if math.isnan(value):
        raise ValueError(f"{name} is NaN; a finite real number is required")
    return value


def check_alpha(alpha: object, *, allow_elastic: bool = False) -> float:
    """Validate a restitution coefficient.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    allow_elastic : bool
        Accept ``alpha = 1`` (elastic rods: valid under a Fokker-Planck bath, and the
        limit in which :math:`P(v, t)` is frozen, claim C17).

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``alpha`` is not a real number.
    ValueError
        If ``alpha`` is NaN or outside ``[0, 1)`` (``[0, 1]`` with ``allow_elastic``).

    Examples
    --------
    >>> check_alpha(0.9)
    0.9
    """
    alpha = check_real("alpha", alpha)
    upper_ok = alpha <= 1.0 if allow_elastic else alpha < 1.0
    if not (alpha >= 0.0 and upper_ok):
        allowed = "[0, 1]" if allow_elastic else "[0, 1)"
        raise ValueError(
            f"restitution coefficient alpha={alpha!r} is outside {allowed}"
            + ("" if allow_elastic or alpha != 1.0 else
               "; alpha = 1 (elastic) has no heated steady state under white noise alone: "
               "the energy injected by the noise is never dissipated (a Fokker-Planck bath "
               "with friction > 0 has one)")
        )
    return alpha


def check_positive(name: str, value: object) -> float:
    """Validate a strictly positive, finite real parameter.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : float
        The value to check.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``value`` is not a real number.
    ValueError
        If ``value`` is NaN, infinite, zero or negative.

    Examples
    --------
    >>> check_positive("density", 2)
    2.0
    """
    value = check_real(name, value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name}={value!r} is not allowed; {name} must be finite and > 0")
    return value


def check_nonnegative(name: str, value: object) -> float:
    """Validate a finite real parameter ``>= 0``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : float
        The value to check.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``value`` is not a real number.
    ValueError
        If ``value`` is NaN, infinite or negative.

    Examples
    --------
    >>> check_nonnegative("friction", 0)
    0.0
    """
    value = check_real(name, value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"{name}={value!r} is not allowed; {name} must be finite and >= 0")
    return value


def check_finite_array(name: str, values: object, *, ndim: int | None = None) -> np.ndarray:
    """Return ``values`` as a float array, refusing NaN and infinities.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    values : array_like
        The values to check.
    ndim : int, optional
        Required number of dimensions.

    Returns
    -------
    ndarray
        ``values`` as float64.

    Raises
    ------
    ValueError
        If an entry is not finite or the number of dimensions is wrong.
    """
    array = np.asarray(values, dtype=float)
    if ndim is not None and array.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-d array, got shape {array.shape}")
    bad = ~np.isfinite(array)
    if bad.any():
        first = int(np.flatnonzero(bad.ravel())[0])
        raise ValueError(
            f"{name} contains {int(bad.sum())} non-finite value(s) (first at flat index "
            f"{first}: {array.ravel()[first]!r}); all entries must be finite"
        )
    return array


def check_times(times: ArrayLike) -> np.ndarray:
    """Output times as a float array: finite, >= 0, strictly increasing, not empty.

    Parameters
    ----------
    times : array_like, shape (n_t,)
        Output times.

    Returns
    -------
    ndarray, shape (n_t,)

    Raises
    ------
    ValueError
        If ``times`` is empty, not finite, negative or not strictly increasing.

    Examples
    --------
    >>> check_times([0, 1, 2.5])
    array([0. , 1. , 2.5])
    """
    t = np.atleast_1d(np.asarray(times, dtype=float))
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"times must be a non-empty 1-d sequence, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"times must be finite, got {t}")
    if t[0] < 0:
        raise ValueError(f"times must be >= 0 (the initial state is at t = 0), got {t[0]}")
    if np.any(np.diff(t) <= 0):
        bad = int(np.flatnonzero(np.diff(t) <= 0)[0])
        raise ValueError(f"times must be strictly increasing; times[{bad}]={t[bad]} is "
                         f"followed by {t[bad + 1]}")
    if t[-1] == 0:
        raise ValueError("times must reach beyond t = 0")
    return t
