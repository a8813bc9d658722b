"""Protocols: thermostat parameters and restitution that change in time.

A transient of the heated gas (:func:`kinetic_fem.evolve_heated`) solves

.. math::

    \\partial_t P = Q_{\\alpha(t)}[P] + \\partial_v(\\xi(t)\\, v P) + D(t)\\,\\partial_v^2 P,

with a noise strength :math:`D(t) > 0`, a friction :math:`\\xi(t) \\ge 0` (bath
temperature :math:`D/\\xi`) and a restitution coefficient (or law) that may change at
given times.  A :class:`Protocol` holds these three schedules; each of :math:`D` and
:math:`\\xi` is a constant, a :class:`Schedule` (piecewise constant steps or piecewise
linear ramps through given knots) or a callable ``t -> value``.  Values are validated
where they enter: negative or non-finite values and times out of order raise
``ValueError`` with a message that says what is allowed; a callable is checked each
time it is evaluated.

Time integrators restart at the discontinuities (:meth:`Protocol.breakpoints`), so a
step in :math:`D` or a change of :math:`\\alpha` is resolved exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Union

import numpy as np

from . import RestitutionLaw, as_restitution, check_real

__all__ = ["Schedule", "Protocol", "steps", "ramp"]


@dataclass(frozen=True)
class Schedule:
    """A parameter as a function of time: steps or a piecewise linear ramp.

    Parameters
    ----------
    times : tuple of float, shape (k,)
        Strictly increasing switch times (``kind="step"``) or knots (``"linear"``), >= 0.
    values : tuple of float
        ``kind="step"``: ``k + 1`` values, ``values[j]`` on ``[times[j-1], times[j])``
        (``values[0]`` before the first switch).  ``kind="linear"``: ``k`` values at the
        knots, linear between them and constant outside.
    kind : {"step", "linear"}

    Raises
    ------
    ValueError
        For non-finite or negative values, times out of order or wrong lengths.

    Examples
    --------
    >>> s = Schedule((1.0,), (2.0, 0.5))
    >>> s(0.5), s(1.0), s.discontinuities
    (2.0, 0.5, (1.0,))
    >>> Schedule((0.0, 2.0), (1.0, 3.0), kind="linear")(1.0)
    2.0
    """

    times: tuple[float, ...]
    values: tuple[float, ...]
    kind: str = "step"
    name: str = "value"

    def __post_init__(self) -> None:
        times = tuple(_finite(f"{self.name} schedule time", t) for t in self.times)
        values = tuple(_finite(f"{self.name}", v) for v in self.values)
        if self.kind not in ("step", "linear"):
            raise ValueError(f"schedule kind must be 'step' or 'linear', got {self.kind!r}")
        if any(t < 0 for t in times):
            raise ValueError(f"{self.name} schedule times must be >= 0, got {times}")
        if len(times) > 1 and np.any(np.diff(times) <= 0):
            raise ValueError(f"{self.name} schedule times must be strictly increasing, "
                             f"got {times}")
        need = len(times) + 1 if self.kind == "step" else len(times)
        if len(values) != need or need == 0:
            rule = ("one before the first switch and one after each" if self.kind == "step"
                    else "one per knot, at least one")
            raise ValueError(f"a {self.kind} schedule with {len(times)} time(s) needs {need} "
                             f"value(s) ({rule}), got {len(values)}")
        if any(v < 0 for v in values):
            raise ValueError(f"{self.name} must be >= 0 at all times, got the values {values}")
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "values", values)

    def __call__(self, t: float, *, left: bool = False) -> float:
        """The value at time ``t`` (right-continuous at a switch; ``left``: the left limit)."""
        if self.kind == "step":
            times = np.asarray(self.times, dtype=np.float64)
            index = (np.searchsorted(times, t, side="left") if left
                     else np.searchsorted(times, t, side="right"))
            return self.values[int(index)]
        return float(np.interp(t, self.times, self.values))

    @property
    def discontinuities(self) -> tuple[float, ...]:
        """Times where the value jumps (steps) or the slope does (ramps)."""
        return self.times

    @property
    def extreme_values(self) -> tuple[float, float]:
        """Smallest and largest value taken."""
        return min(self.values), max(self.values)


Parameter = Union[float, Schedule, Callable[[float], float], None]


def steps(times, values, *, name: str = "value") -> Schedule:
    """Piecewise-constant :class:`Schedule` (``len(values) == len(times) + 1``).

    Parameters
    ----------
    times : array_like, shape (m,)
        Increasing switching times.
    values : array_like, shape (m + 1,)
        Finite value before ``times[0]``, between successive times and after the last.
    name : str
        Name of the quantity, used in error messages.

    Returns
    -------
    Schedule
    """
    return Schedule(tuple(np.atleast_1d(times).tolist()), tuple(np.atleast_1d(values).tolist()),
                    "step", name)


def ramp(times, values, *, name: str = "value") -> Schedule:
    """Piecewise-linear :class:`Schedule` through ``(times[j], values[j])``.

    Parameters
    ----------
    times : array_like, shape (m,)
        Increasing times of the knots.
    values : array_like, shape (m,)
        Finite values at the knots; constant before the first and after the last.
    name : str
        Name of the quantity, used in error messages.

    Returns
    -------
    Schedule
    """
    return Schedule(tuple(np.atleast_1d(times).tolist()), tuple(np.atleast_1d(values).tolist()),
                    "linear", name)


def _finite(name: str, value: object) -> float:
    value = check_real(name, value)
    if not math.isfinite(value):
        raise ValueError(f"{name}={value!r} is not allowed; it must be finite")
    return value


def _evaluate(param: Parameter, t: float, default: float, name: str, left: bool) -> float:
    if param is None:
        return default
    if isinstance(param, bool) or not (isinstance(param, (int, float)) or callable(param)):
        raise TypeError(f"the {name} protocol must be a number, a Schedule or a callable of "
                        f"t, got {param!r}")
    if isinstance(param, (int, float)):
        return float(param)
    value = param(t, left=left) if isinstance(param, Schedule) else param(t)
    try:
        value = _finite(f"{name}({t:g})", value)
    except TypeError as err:
        raise TypeError(f"the {name} protocol must return a real number, got {value!r} "
                        f"at t={t:g}") from err
    if value < 0:
        raise ValueError(f"the {name} protocol returned {value!r} < 0 at t={t:g}; {name} "
                         "must be >= 0 at all times")
    return value


@dataclass(frozen=True)
class Protocol:
    """Time dependence of the noise strength, the friction and the restitution.

    Parameters
    ----------
    diffusion, friction : float, Schedule or callable, optional
        :math:`D(t)` and :math:`\\xi(t)`; None keeps the value passed to the solver.
        A callable must be continuous (the integrator restarts only at the
        ``breakpoints`` given); :math:`D` must stay > 0, :math:`\\xi \\ge 0`.
    restitution : sequence of (time, alpha) pairs
        At each ``time`` the restitution coefficient (or law) changes to ``alpha``.
    breakpoints_extra : sequence of float
        Further times where a callable changes abruptly (the integrator restarts there).

    Raises
    ------
    ValueError
        For negative or non-finite values, negative times, or times out of order.

    Examples
    --------
    >>> p = Protocol(diffusion=steps([5.0], [1.0, 2.0]), restitution=[(3.0, 0.5)])
    >>> p.diffusion_at(6.0, 1.0), p.restitution_at(1.0, 0.9).alpha
    (2.0, 0.9)
    >>> p.breakpoints(10.0)
    (3.0, 5.0)
    """

    diffusion: Parameter = None
    friction: Parameter = None
    restitution: tuple = field(default_factory=tuple)
    breakpoints_extra: tuple = field(default_factory=tuple)

    def __post_init__(self) -> None:
        for name in ("diffusion", "friction"):
            param = getattr(self, name)
            if param is None or isinstance(param, Schedule):
                continue
            if isinstance(param, (int, float)) and not isinstance(param, bool):
                value = _finite(name, param)
                if value < 0 or (name == "diffusion" and value == 0):
                    raise ValueError(f"{name}={value!r} is not allowed; diffusion must be > 0"
                                     " and friction >= 0")
                object.__setattr__(self, name, value)
            elif not callable(param):
                raise TypeError(f"{name} must be a number, a Schedule or a callable t -> "
                                f"value, got {type(param).__name__}")
        changes = []
        for item in self.restitution:
            try:
                t, law = item
            except (TypeError, ValueError):
                raise ValueError("restitution changes must be (time, alpha) pairs, got "
                                 f"{item!r}") from None
            t = _finite("restitution change time", t)
            if t < 0:
                raise ValueError(f"restitution change time {t} must be >= 0")
            changes.append((t, as_restitution(law)))
        times = [t for t, _ in changes]
        if len(times) > 1 and np.any(np.diff(times) <= 0):
            raise ValueError(f"restitution change times must be strictly increasing, got "
                             f"{times}")
        object.__setattr__(self, "restitution", tuple(changes))
        extra = tuple(sorted(_finite("breakpoint", t) for t in self.breakpoints_extra))
        object.__setattr__(self, "breakpoints_extra", extra)

    def diffusion_at(self, t: float, default: float, *, left: bool = False) -> float:
        """:math:`D(t)` (``left``: the left limit); ``default`` if the protocol leaves it
        constant."""
        value = _evaluate(self.diffusion, t, default, "diffusion", left)
        if value <= 0:
            raise ValueError(f"the diffusion protocol gives D={value!r} at t={t:g}; D must be "
                             "> 0 at all times")
        return value

    def friction_at(self, t: float, default: float, *, left: bool = False) -> float:
        """:math:`\\xi(t)` (``left``: the left limit); ``default`` if constant."""
        return _evaluate(self.friction, t, default, "friction", left)

    def restitution_at(self, t: float, default: float | RestitutionLaw) -> RestitutionLaw:
        """The restitution law in force at ``t`` (right-continuous at a change)."""
        law = as_restitution(default)
        for t_change, new in self.restitution:
            if t >= t_change:
                law = new
        return law

    def breakpoints(self, t_end: float) -> tuple[float, ...]:
        """Sorted times in ``(0, t_end)`` where the integrator must stop and restart."""
        points = set(self.breakpoints_extra)
        points.update(t for t, _ in self.restitution)
        for param in (self.diffusion, self.friction):
            if isinstance(param, Schedule):
                points.update(param.discontinuities)
        return tuple(sorted(t for t in points if 0.0 < t < t_end))

    def restitution_laws(self, default: float | RestitutionLaw) -> tuple[RestitutionLaw, ...]:
        """Every law in force at some time, the initial one first."""
        return (as_restitution(default),) + tuple(law for _, law in self.restitution)
