"""The drift, mass and temperature forms of the FEM cooling-state equations.

:func:`cooling_forms` evaluates, from the element arrays of
:class:`~kinetic_fem.operators.fem_transport.TransportArrays` (computed once per
discretisation), what :mod:`kinetic_fem.solvers.fem.cooling_newton` assembled with
scikit-fem's ``asm`` on every Newton residual: the same quadrature, equal to round-off.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ...operators.fem_transport import TransportArrays

__all__ = ["cooling_forms"]


def cooling_forms(arrays: TransportArrays, u: NDArray, jacobian: bool
                  ) -> tuple[NDArray, NDArray, NDArray, NDArray | None]:
    """The drift, mass and temperature forms of the HCS equations from element arrays.

    The same quadrature as scikit-fem's ``asm`` of
    :func:`~kinetic_fem.solvers.fem.bath_drift` (and its Jacobian),
    :func:`~kinetic_fem.solvers.fem.mass` and
    :func:`~kinetic_fem.solvers.fem.cooling_newton.second_moment`, equal to round-off,
    without the per-call assembly (issue 16, eighth round: cooling states 1.02 to 1.11
    times faster, zeta equal to 4e-15).

    Parameters
    ----------
    arrays : TransportArrays
        The basis arrays of the discretisation.
    u : ndarray, shape (n_dofs,)
        Coefficients of :math:`u_h = \\ln f_h`.
    jacobian : bool
        Also the drift's dense Jacobian.

    Returns
    -------
    drift, grad_mass, grad_temp : ndarray, shape (n_dofs,)
        :math:`\\int\\varphi_i' c f_h`, :math:`\\int\\varphi_i f_h`,
        :math:`\\int c^2 \\varphi_i f_h`.
    djac : ndarray, shape (n_dofs, n_dofs) or None
        :math:`\\int\\varphi_i' c \\varphi_j f_h`.
    """
    _, _, p = arrays.fields(u)
    wp = arrays.dx * p
    xwp = arrays.x * wp
    n, flat = arrays.n_dofs, arrays.dofs.ravel()

    def scatter(local: NDArray) -> NDArray:
        return np.bincount(flat, local.ravel(), minlength=n)

    drift = scatter(np.einsum("ieq,eq->ie", arrays.dphi, xwp))
    grad_mass = scatter(np.einsum("ieq,eq->ie", arrays.phi, wp))
    grad_temp = scatter(np.einsum("ieq,eq->ie", arrays.phi, arrays.x * xwp))
    if not jacobian:
        return drift, grad_mass, grad_temp, None
    local = np.einsum("ieq,jeq,eq->ije", arrays.dphi, arrays.phi, xwp)
    n_local = arrays.dofs.shape[0]
    rows = np.repeat(arrays.dofs[:, None, :], n_local, axis=1).ravel()
    cols = np.repeat(arrays.dofs[None, :, :], n_local, axis=0).ravel()
    djac = np.bincount(rows * n + cols, local.ravel(), minlength=n * n).reshape(n, n)
    return drift, grad_mass, grad_temp, djac
