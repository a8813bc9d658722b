"""Numba kernel of the mixture DSMC: one collision phase over a block of candidate pairs.

Arrays and scalars in, counters out; the random numbers are drawn by the driver
(:mod:`particles.dsmc_mixture`) from a ``numpy.random.Generator`` and passed in, so a
seed gives the same run with or without the JIT.
"""

from __future__ import annotations

from kinetic_fem.model.restitution import restitution_value

from ._dsmc_model import KERNEL_MAXWELL, kernel_majorant, kernel_value
from ._jit import jit

__all__ = ["collide_block"]


@jit
def collide_block(v, species, masses, lcode, p0, p1, kcode, kparam, g_max, first, second,
                  accept, counts):  # pragma: no cover - compiled
    """Collide the accepted candidate pairs of one time step, in order.

    Candidate ``c`` is the pair ``(first[c], second[c])`` (distinct rods); it collides
    with probability :math:`B(|g|)/B(g_{max})` (``accept[c]`` uniform in [0, 1); every
    candidate for the Maxwell kernel), by :math:`v_s' = v_s - \\mu_{sr}(1+\\alpha_{sr})g`,
    :math:`v_r' = v_r + \\mu_{rs}(1+\\alpha_{sr})g` with :math:`\\alpha_{sr}` the pair's
    restitution law at :math:`|g|` (:func:`kinetic_fem.model.restitution_value`).

    Parameters
    ----------
    v : ndarray, shape (N,)
        Velocities, updated in place.
    species : ndarray of int64, shape (N,)
    masses : ndarray, shape (k,)
    lcode : ndarray of int64, shape (k, k)
        Restitution law code of each pair.
    p0, p1 : ndarray, shape (k, k)
        The laws' parameters (``p0`` the coefficient of a constant law).
    kcode : int
        Kernel code (:mod:`particles._dsmc_model`).
    kparam : float
        Kernel parameter (exponent of a power law, :math:`g_0` of the saturating kernel).
    g_max : float
        Majorant of :math:`|g|` used for the acceptance.
    first, second : ndarray of int64, shape (M,)
    accept : ndarray, shape (M,)
    counts : ndarray of int64, shape (k, k)
        Collisions per pair of species, incremented in place.

    Returns
    -------
    energy_loss : float
        :math:`\\sum \\tfrac12 m_{sr}(1-\\alpha_{sr}^2) g^2` over the collisions
        (:math:`m_{sr}` the reduced mass).
    g_seen : float
        The largest :math:`|g|` met among the candidates (the driver raises ``g_max``
        to it: a candidate above the majorant is accepted with probability one).
    """
    loss = 0.0
    g_seen = 0.0
    b_max = kernel_majorant(kcode, kparam, g_max)
    for c in range(first.size):
        i = first[c]
        j = second[c]
        g = v[i] - v[j]
        ag = abs(g)
        if ag > g_seen:
            g_seen = ag
        if kcode != KERNEL_MAXWELL and accept[c] * b_max >= kernel_value(kcode, kparam, ag):
            continue
        s = species[i]
        r = species[j]
        mi = masses[s]
        mj = masses[r]
        a = restitution_value(lcode[s, r], p0[s, r], p1[s, r], ag)
        share = (1.0 + a) * g / (mi + mj)
        v[i] -= mj * share
        v[j] += mi * share
        loss += 0.5 * mi * mj / (mi + mj) * (1.0 - a * a) * g * g
        counts[s, r] += 1
        if r != s:
            counts[r, s] += 1
    return loss, g_seen
