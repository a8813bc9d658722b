r"""
First-order Sonine theory: a2 over alpha
========================================

The kurtosis coefficient of the heated one-dimensional gas in first-order Sonine
theory (van Noije and Ernst 1998) is

.. math::

    a_2(\alpha) = \frac{16 (1 - 2\alpha^2)}{129 + 30\alpha^2},

positive for :math:`\alpha < 1/\sqrt2`, negative above, with the elastic limit
:math:`a_2 \to -16/159` (claim C3).  Sonine coefficients of any distribution come
from its moments; here we build the first-order Sonine distribution

.. math::

    f(c) = \Phi(c)\,\big(1 + a_2 S_2(c^2)\big), \qquad
    S_2(c^2) = L_2^{(-1/2)}(c^2/2) = \tfrac{c^4}{8} - \tfrac{3c^2}{4} + \tfrac38,

on a velocity mesh, and check that :class:`~kinetic_fem.VelocityDistribution`
recovers :math:`a_2`, gives :math:`a_3 = \dots = a_6 = 0`, and that a Gaussian has
all :math:`a_p = 0` and an effective exponent :math:`n(c) = 2`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from kinetic_fem import VelocityDistribution
from kinetic_fem.sonine import A2_ELASTIC_LIMIT, a2_first_order

TEST_KWARGS = {"n_alpha": 11, "n_v": 401}


@dataclass(frozen=True)
class SonineA2Result:
    """What :func:`main` computes.

    Attributes
    ----------
    alpha, a2_theory : ndarray, shape (n_alpha,)
        Restitution coefficients and the first-order Sonine :math:`a_2`.
    sonine : VelocityDistribution
        The first-order Sonine distribution at ``alpha_check``.
    gaussian : VelocityDistribution
        A Gaussian of temperature 2 on the same mesh.
    a2_check : float
        :math:`a_2` of the theory at ``alpha_check`` (to compare with ``sonine.a2``).
    """

    alpha: NDArray[np.float64]
    a2_theory: NDArray[np.float64]
    sonine: VelocityDistribution
    gaussian: VelocityDistribution
    a2_check: float


def main(n_alpha: int = 201, n_v: int = 2001, alpha_check: float = 0.3) -> SonineA2Result:
    """Tabulate :math:`a_2(\\alpha)` and check the Sonine machinery on two distributions.

    Parameters
    ----------
    n_alpha : int
        Number of restitution coefficients in ``[0, 1]``.
    n_v : int
        Number of velocity nodes on ``[-12, 12]`` (in units of the thermal velocity).
    alpha_check : float
        Restitution coefficient of the first-order Sonine distribution.
    """
    alpha = np.linspace(0.0, 1.0, n_alpha)
    a2_theory = a2_first_order(alpha)
    a2 = a2_first_order(alpha_check)
    c = np.linspace(-12.0, 12.0, n_v)
    s2 = c**4 / 8 - 3 * c**2 / 4 + 3 / 8
    phi = np.exp(-(c**2) / 2) / np.sqrt(2 * np.pi)
    sonine = VelocityDistribution.from_values(c, phi * (1 + a2 * s2), method="sonine",
                                              params={"alpha": alpha_check})
    v = np.sqrt(2.0) * c  # temperature 2
    gaussian = VelocityDistribution.from_values(v, np.exp(-(v**2) / 4), method="gaussian")
    return SonineA2Result(alpha, a2_theory, sonine, gaussian, a2)


# %%
# Run it and print the Sonine coefficients: the first-order distribution returns
# the :math:`a_2` it was built with and no higher coefficients; the Gaussian none.
result = main(**TEST_KWARGS)
print(f"a2 built in {result.a2_check:+.6f}, measured {result.sonine.a2:+.6f}")
for p in range(2, 7):
    print(f"p={p}: a_p(sonine) = {result.sonine.sonine_coefficient(p):+.2e}, "
          f"a_p(gaussian) = {result.gaussian.sonine_coefficient(p):+.2e}")
print("Gaussian n(c) at c = 1, 2, 3:", result.gaussian.effective_exponent([1.0, 2.0, 3.0]))
print(f"a2(alpha -> 1) = {a2_first_order(1.0):.10f}, -16/159 = {A2_ELASTIC_LIMIT:.10f}")

# %%
# Plot :math:`a_2(\alpha)` and the scaled distribution against the Gaussian.
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    result = main()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.5))
    ax1.plot(result.alpha, result.a2_theory, "k-", label="first-order Sonine")
    ax1.axhline(A2_ELASTIC_LIMIT, color="gray", ls=":", label="-16/159")
    ax1.set_xlabel(r"$\alpha$")
    ax1.set_ylabel(r"$a_2$")
    ax1.legend()
    c = np.linspace(-5, 5, 201)
    ax2.semilogy(c, result.sonine.f(c), label=rf"Sonine, $\alpha$ = {0.3}")
    ax2.semilogy(c, result.gaussian.f(c), "--", label="Gaussian")
    ax2.set_xlabel("c")
    ax2.set_ylabel("f(c)")
    ax2.legend()
    fig.tight_layout()
    plt.show()
