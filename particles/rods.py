"""Hard rods on a ring: the kernel check, the mean free time and initial states.

The geometry that :mod:`particles.md` builds its runs on: MD simulates hard rods only
(:func:`hard_rods` refuses other kernels), rods of length ``sigma`` at density ``n`` on a
ring of length ``L = N/n`` are mapped to points on the reduced ring of length
``L - N sigma``, and :func:`initial_state` places them without overlap.
:func:`check_sample_interval` plans the samples of a heated run (uniform in time).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kinetic_fem.model import (
    CollisionKernel,
    PowerLawKernel,
    UnsupportedModelError,
    as_kernel,
    check_finite_array,
    check_positive,
)

__all__ = ["mean_free_time", "hard_rods", "initial_state", "check_geometry",
           "check_sample_interval", "SAMPLE_CLOCK_RESOLUTION"]

SAMPLE_CLOCK_RESOLUTION = 1e-12
"""Smallest heated ``sample_interval`` per collision per particle of the run: a step of
the sampling clock below it is lost in the double-precision time of the run's end (the
clock stops and the run samples forever)."""


def check_sample_interval(sample_interval: object, collisions_per_particle: float,
                          warmup: float) -> tuple[float, float]:
    """Validate a heated run's ``sample_interval``, in mean free times, and plan its samples.

    A run of ``collisions_per_particle`` lasts about as many mean free times, so sampling
    every ``sample_interval`` of them from ``warmup`` on takes about
    ``(collisions_per_particle - warmup) / sample_interval`` samples (an estimate: the
    run's mean free time can differ from the one the interval is scaled by).

    Parameters
    ----------
    sample_interval : float
        The argument: time between samples in mean free times.
    collisions_per_particle, warmup : float
        The run's length and its warm-up (validated), collisions per particle.

    Returns
    -------
    sample_interval, samples : float
        The interval and the planned number of samples.

    Raises
    ------
    TypeError
        If ``sample_interval`` is not a real number.
    ValueError
        If it is not positive and finite, or below :data:`SAMPLE_CLOCK_RESOLUTION`
        ``* collisions_per_particle``.
    """
    every = check_positive("sample_interval", sample_interval)
    least = SAMPLE_CLOCK_RESOLUTION * collisions_per_particle
    if every < least:
        raise ValueError(f"sample_interval={every:.6g} mean free times is below the "
                         "resolution of the run's clock over collisions_per_particle="
                         f"{collisions_per_particle:g} (about as many mean free times): "
                         f"sample_interval must be >= {least:.3g} "
                         f"({SAMPLE_CLOCK_RESOLUTION:g} * collisions_per_particle)")
    return every, (collisions_per_particle - warmup) / every


def mean_free_time(temperature: float, density: float, sigma: float) -> float:
    """Mean free time of a Gaussian gas of rods, :math:`1/(n_f \\cdot 2\\sqrt{T/\\pi})`.

    :math:`n_f = n/(1 - n\\sigma)` is the density on the reduced ring and
    :math:`2\\sqrt{T/\\pi} = \\langle |v - v'| \\rangle` for :math:`T = \\langle v^2\\rangle`.

    Parameters
    ----------
    temperature : float
        Temperature ``T``.
    density : float
        Number density ``n``.
    sigma : float
        Rod length.

    Returns
    -------
    float
    """
    n_free = density / (1.0 - density * sigma)
    return 1.0 / (n_free * 2.0 * math.sqrt(temperature / math.pi))


def hard_rods(kernel: float | CollisionKernel) -> PowerLawKernel:
    """The kernel of MD, which simulates hard rods only (:math:`\\gamma = 1`).

    Parameters
    ----------
    kernel : float or CollisionKernel
        The requested kernel.

    Returns
    -------
    PowerLawKernel

    Raises
    ------
    UnsupportedModelError
        For any other kernel (with a pointer to the methods that support it).

    Examples
    --------
    >>> hard_rods(1.0).is_hard_rods
    True
    """
    k = as_kernel(kernel)
    if not (isinstance(k, PowerLawKernel) and k.is_hard_rods):
        raise UnsupportedModelError(
            f"MD simulates hard rods only (kernel gamma = 1: rods on a line meet at the rate "
            f"of their relative speed), got the {k.name} kernel {k!r}; for other kernels use "
            f"particles.dsmc (every 0 <= gamma <= 2) or kinetic_fem's solve_heated/"
            f"solve_cooling with method='fem'")
    return k


def check_geometry(n_particles: object, density: float,
                   sigma: float | None) -> tuple[int, float]:
    """Validate the number of rods and their length; default ``sigma = 1/(2n)``.

    Parameters
    ----------
    n_particles : int
        Number of rods, at least 2.
    density : float
        Number density ``n`` (already validated positive).
    sigma : float or None
        Rod length, ``>= 0`` with ``n sigma < 1``; None: half the mean spacing.

    Returns
    -------
    tuple
        ``(n_particles, sigma)``.

    Raises
    ------
    TypeError, ValueError
        For a non-integer or too small ``n_particles`` or an impossible ``sigma``.
    """
    if isinstance(n_particles, bool) or not isinstance(n_particles, (int, np.integer)):
        raise TypeError(f"n_particles must be an int, got {n_particles!r}")
    if n_particles < 2:
        raise ValueError(f"n_particles={n_particles} is not allowed; need at least 2 rods")
    n = density
    sig = 0.5 / n if sigma is None else float(sigma)
    if not (math.isfinite(sig) and sig >= 0.0):
        raise ValueError(f"sigma={sigma!r} is not allowed; the rod length must be >= 0")
    if not n * sig < 1.0:
        raise ValueError(f"density * sigma = {n * sig!r} is not allowed; rods of length "
                         f"sigma={sig} at density {n} must fill less than the ring (n sigma < 1)")
    return int(n_particles), sig


def initial_state(n_particles: int, *, density: float, sigma: float, temperature: float,
                  rng: np.random.Generator, positions: ArrayLike | None = None,
                  velocities: ArrayLike | None = None) -> tuple[NDArray, NDArray]:
    """Reduced-ring positions ``y`` (sorted) and velocities of the initial state.

    Default: rods placed uniformly at random without overlap (uniform points on the
    reduced ring, the equilibrium hard-rod state) and Gaussian velocities of variance
    ``temperature`` with zero total momentum.  Given ``positions`` (rod left ends) are
    sorted along the ring and checked for overlaps.

    Parameters
    ----------
    n_particles : int
        Number of rods ``N``.
    density : float
        Number density ``n`` (rods per unit length).
    sigma : float
        Rod length.
    temperature : float
        Temperature of the Gaussian velocities.
    rng : numpy.random.Generator
        Random source.
    positions : array_like, shape (N,), optional
        Rod left ends (checked for overlaps).
    velocities : array_like, shape (N,), optional
        Initial velocities.

    Returns
    -------
    y : ndarray, shape (N,)
        Sorted positions on the reduced ring.
    v : ndarray, shape (N,)
        Velocities.

    Raises
    ------
    ValueError
        For overlapping rods, a wrong shape or non-finite values.
    """
    big_l = n_particles / density
    free = big_l - n_particles * sigma
    if velocities is None:
        v = rng.normal(scale=math.sqrt(temperature), size=n_particles)
        v -= v.mean()
    else:
        v = check_finite_array("velocities", velocities, ndim=1).copy()
        if v.size != n_particles:
            raise ValueError(f"velocities has {v.size} entries for {n_particles} rods")
    if positions is None:
        y = np.sort(rng.uniform(0.0, free, n_particles))
        return y, v
    pos = check_finite_array("positions", positions, ndim=1)
    if pos.size != n_particles:
        raise ValueError(f"positions has {pos.size} entries for {n_particles} rods")
    pos = np.mod(pos, big_l)
    order = np.argsort(pos, kind="stable")
    pos, v = pos[order], v[order]
    gaps = np.diff(np.append(pos, pos[0] + big_l))
    if np.any(gaps < sigma):
        k = int(np.argmin(gaps))
        raise ValueError(f"initial positions overlap: rods at {pos[k]!r} and "
                         f"{pos[(k + 1) % n_particles]!r} are {gaps[k]!r} apart, less than "
                         f"sigma={sigma}")
    return pos - sigma * np.arange(n_particles), v
