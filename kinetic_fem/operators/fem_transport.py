"""The thermostat forms of the heated FEM Newton iteration from cached element arrays.

The white-noise term :math:`-\\int\\varphi_i' P'`, the bath drift
:math:`-\\xi\\int\\varphi_i' vP` (:func:`~kinetic_fem.operators.fem_discretisation.fokker_planck`,
:func:`~kinetic_fem.operators.fem_discretisation.bath_drift`), their dense Jacobians and the
mass gradient :math:`\\int\\varphi_i P` (:func:`~kinetic_fem.operators.fem_discretisation.mass`),
:math:`P = e^{u_h}`, as :meth:`FEMDiscretisation.transport
<kinetic_fem.operators.fem_discretisation.FEMDiscretisation.transport>` and scikit-fem's
``asm`` give them, but from the basis values, derivatives and weights at the quadrature
points, evaluated once per discretisation (:class:`TransportArrays`), with plain numpy
sums: the same quadrature, equal to round-off (tested), without the per-call assembly
overhead (issue 16: about 8 % of a heated state).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from skfem import Basis

__all__ = ["TransportArrays"]


class TransportArrays:
    """Basis values, derivatives, weights and points of one scikit-fem basis.

    Parameters
    ----------
    basis : skfem.Basis
        A scalar Lagrange basis on a line mesh.
    friction : float
        Bath friction :math:`\\xi` (0: white noise only).
    """

    def __init__(self, basis: Basis, friction: float = 0.0) -> None:
        self.n_dofs = int(basis.N)
        self.dofs = np.asarray(basis.element_dofs)  # (n_local, n_el)
        self.phi = np.array([np.asarray(f[0]) for f in basis.basis])  # (n_local, n_el, n_q)
        self.dphi = np.array([f[0].grad[0] for f in basis.basis])
        self.dx = np.asarray(basis.dx)  # (n_el, n_q)
        self.x = np.asarray(basis.mapping.F(basis.X)[0])
        self.friction = float(friction)

    def _scatter(self, local: NDArray) -> NDArray:
        return np.bincount(self.dofs.ravel(), local.ravel(), minlength=self.n_dofs)

    def fields(self, u: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """:math:`u_h`, :math:`u_h'` and :math:`P_h = e^{u_h}` at the quadrature points.

        Parameters
        ----------
        u : ndarray, shape (n_dofs,)
            Coefficients of :math:`u_h`.
        """
        local = u[self.dofs]  # (n_local, n_el)
        value = np.einsum("ieq,ie->eq", self.phi, local)
        slope = np.einsum("ieq,ie->eq", self.dphi, local)
        return value, slope, np.exp(value)

    def transport(self, u: NDArray, *, jacobian: bool = False
                  ) -> tuple[NDArray, NDArray | None, NDArray]:
        """The thermostat term, its dense Jacobian (or None) and the mass gradient.

        Parameters
        ----------
        u : ndarray, shape (n_dofs,)
            Coefficients of :math:`u_h = \\ln P_h`.
        jacobian : bool
            Also the dense Jacobian.

        Returns
        -------
        res : ndarray
            :math:`-\\int\\varphi_i'(P' + \\xi vP)`.
        jac : ndarray or None
            Its derivative in :math:`u` (dense).
        mass : ndarray
            :math:`\\int\\varphi_i P`.
        """
        _, slope, p = self.fields(u)
        wp = self.dx * p
        flux = wp * slope
        if self.friction > 0.0:
            flux = flux + self.friction * (wp * self.x)
        res = -self._scatter(np.einsum("ieq,eq->ie", self.dphi, flux))
        mass = self._scatter(np.einsum("ieq,eq->ie", self.phi, wp))
        if not jacobian:
            return res, None, mass
        # d/du_j of the flux: wp (phi_j u' + phi_j') (+ xi x wp phi_j)
        coef = wp * slope
        if self.friction > 0.0:
            coef = coef + self.friction * (wp * self.x)
        local = np.einsum("ieq,jeq,eq->ije", self.dphi, self.phi, coef) \
            + np.einsum("ieq,jeq,eq->ije", self.dphi, self.dphi, wp)
        jac = np.zeros((self.n_dofs, self.n_dofs))
        # one local pair (i, j) at a time: its (row, column) pairs differ between elements,
        # so a buffered add is exact; an entry gets at most two terms (a shared vertex),
        # hence the same sums as np.add.at, bit for bit, without its per-entry cost
        dofs = self.dofs
        for i in range(dofs.shape[0]):
            for j in range(dofs.shape[0]):
                jac[dofs[i], dofs[j]] -= local[i, j]
        return res, jac, mass
