"""Weak forms of the thermostat and of the time derivative, for :math:`P_h = e^{u_h}`.

With Lagrange test functions :math:`\\varphi_i` and zero flux at :math:`\\pm V`,

.. math::

    \\int \\varphi_i\\, D\\,\\partial_v^2 P = -D \\int \\varphi_i' P'
    \\quad (:func:`diffusion`), \\qquad
    \\int \\varphi_i\\, \\partial_v(\\xi v P) = -\\xi \\int \\varphi_i'\\, v P
    \\quad (:func:`drift`),

and the time derivative acts on :math:`m_i(P) = \\int \\varphi_i P` (:func:`mass`),
whose derivative in :math:`u` is the weighted mass matrix
:math:`\\int \\varphi_i \\varphi_j P` (:func:`weighted_mass`).  Each term is assembled
without its coefficient, so that time-dependent :math:`D(t)` and :math:`\\xi(t)`
multiply separately assembled vectors.  Since :math:`\\sum_i \\varphi_i \\equiv 1`,
both thermostat terms conserve mass exactly; with P2
(:math:`\\sum_i v_i^2 \\varphi_i \\equiv v^2`) their energy moments are exactly
:math:`2D\\int P` and :math:`-2\\xi\\int v^2 P`.
"""

from __future__ import annotations

from .fem_discretisation import (
    bath_drift,
    bath_drift_jacobian,
    fokker_planck,
    fokker_planck_jacobian,
    mass,
    weighted_mass,
)

__all__ = ["mass", "weighted_mass", "diffusion", "diffusion_jacobian", "drift",
           "drift_jacobian"]

#: :math:`\int \varphi_i' P'` with :math:`P = e^{u}` (the steady solver's form).
diffusion = fokker_planck
#: Derivative of :data:`diffusion` in the direction ``du``.
diffusion_jacobian = fokker_planck_jacobian
#: :math:`\int \varphi_i'\, v\, P` (``w.x`` the quadrature points).
drift = bath_drift
#: Derivative of :data:`drift` in the direction ``du``.
drift_jacobian = bath_drift_jacobian
