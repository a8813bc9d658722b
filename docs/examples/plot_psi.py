r"""
Quasi-elastic free cooling: the hump shape psi
==============================================

In free cooling at small :math:`\epsilon = 1-\alpha`, the scaled distribution of
:math:`x = n\epsilon t v` has two humps at :math:`x = \pm 1` of width
:math:`\epsilon^{1/3}` (claims C10, C11).  Each hump, in :math:`x = -1 + \epsilon^{1/3} y`,
has the shape :math:`\psi(y)` solving (claim C12, derivation in
:doc:`/user_guide/quasi_elastic`)

.. math::

    \psi' + \langle y^2\rangle_\psi \psi + \frac12\psi\int dy'\,\psi(y')
    \big(|y-y'|(y-y') - (y+y')^2\big) = 0,
    \qquad \int\psi = 1,\ \langle y\rangle_\psi = 0.

:func:`kinetic_fem.solvers.scaling.solve_psi` solves its integrated (logarithmic) form by
Newton's method with :math:`\langle y\rangle = 0` as an explicit condition.  We check
the tails, the fourth-order ODE and :math:`\langle y\rangle = 0`; three of the
paper's printed formulas are misprints (right tail, :math:`(\ln\psi)'''' = \psi`, the
sign in the logarithmic form), and the corrected ones hold to the discretisation
error.
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.solvers.scaling import PsiSolution, solve_psi

TEST_KWARGS = {"n_v": 1051}


def main(n_v: int = 4201, domain: tuple[float, float] = (-6.0, 36.0)) -> PsiSolution:
    """Solve for psi on ``n_v`` nodes of ``domain``, with error estimates."""
    return solve_psi(n_v=n_v, domain=domain)


# %%
# Constants with errors, tail fits, the ODE and the mean.

if __name__ == "__main__":
    import matplotlib.pyplot as plt

    psi = main()
    for name, value in psi.constants().items():
        print(f"{name:8s} = {value:.12f} +- {psi.errors[name]:.1e}")
    a = psi.asymptotics()
    lnc = np.log(psi.C)
    print(f"<y> = {a.mean:.1e};  left tail: ln psi = {a.left_log_prefactor:.8f} + "
          f"{a.left_cubic:.10f} y^3  (ln C = {lnc:.8f}, 1/3)")
    print(f"right tail: slope {a.right_slope:.8f} (-<y^2> = {-psi.y2:.8f}; paper -2<y^2>), "
          f"ln C' = {a.right_log_prefactor:.7f} (ln C + <y^3>/3 = {lnc + psi.y3 / 3:.7f})")
    print(f"(ln psi)'''' + 2 psi: {a.ode_residual:.1e};  (ln psi)'''' - psi: "
          f"{a.ode_residual_paper:.2f} (relative to max psi)")

    # %%
    # psi on a log scale with both tails (F11), and the two humps it predicts (F9, F10).
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    y = np.linspace(-5, 25, 500)
    left = y < 1.5
    ax1.semilogy(y, psi(y), "k-", lw=2, label="psi")
    ax1.semilogy(y[left], psi.C * np.exp(y[left] ** 3 / 3), "b--", label="C exp(y^3/3)")
    ax1.semilogy(y, psi.C * np.exp(psi.y3 / 3 - psi.y2 * y), "r-.",
                 label="C exp(<y^3>/3 - <y^2> y)")
    ax1.set(xlabel="y", ylabel="psi(y)", ylim=(1e-16, 1))
    ax1.legend(fontsize=8)
    x = np.linspace(-1.6, 1.6, 2001)
    for eps in (1e-2, 1e-3, 1e-4):
        ax2.plot(x, psi.humps(x, eps), label=f"eps = {eps:g}")
    ax2.set(xlabel="x = n eps t v", ylabel="Phi(x), leading order")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    plt.show()
