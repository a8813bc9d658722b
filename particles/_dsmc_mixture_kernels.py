"""Numba kernel of the mixture DSMC: one collision phase over a block of candidate pairs.

Arrays and scalars in, counters out; the random numbers are drawn by the driver
(:mod:`particles.dsmc_mixture`) from a ``numpy.random.Generator`` and passed in, so a
seed gives the same run with or without the JIT.
"""

from __future__ import annotations

from ._jit import jit

__all__ = ["collide_block"]


@jit
def collide_block(v, species, masses, alpha, gamma, g_max, first, second, accept,
                  counts):  # pragma: no cover - compiled
    """Collide the accepted candidate pairs of one time step, in order.

    Candidate ``c`` is the pair ``(first[c], second[c])`` (distinct rods); it collides
    with probability :math:`(|g|/g_{max})^\\gamma` (``accept[c]`` uniform in [0, 1)), by
    :math:`v_s' = v_s - \\mu_{sr}(1+\\alpha_{sr})g`, :math:`v_r' = v_r + \\mu_{rs}
    (1+\\alpha_{sr})g`.

    Parameters
    ----------
    v : ndarray, shape (N,)
        Velocities, updated in place.
    species : ndarray of int64, shape (N,)
    masses : ndarray, shape (k,)
    alpha : ndarray, shape (k, k)
        Constant restitution coefficients per pair.
    gamma : float
        Kernel exponent of :math:`|g|^\\gamma`.
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
    for c in range(first.size):
        i = first[c]
        j = second[c]
        g = v[i] - v[j]
        ag = abs(g)
        if ag > g_seen:
            g_seen = ag
        if gamma > 0.0 and accept[c] * g_max**gamma >= ag**gamma:
            continue
        s = species[i]
        r = species[j]
        mi = masses[s]
        mj = masses[r]
        a = alpha[s, r]
        share = (1.0 + a) * g / (mi + mj)
        v[i] -= mj * share
        v[j] += mi * share
        loss += 0.5 * mi * mj / (mi + mj) * (1.0 - a * a) * g * g
        counts[s, r] += 1
        if r != s:
            counts[r, s] += 1
    return loss, g_seen

