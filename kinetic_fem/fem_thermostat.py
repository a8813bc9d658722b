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

import numpy as np
from skfem import BilinearForm, LinearForm
from skfem.helpers import dot, grad

__all__ = ["mass", "weighted_mass", "diffusion", "diffusion_jacobian", "drift",
           "drift_jacobian"]


@LinearForm
def mass(v, w):
    """:math:`m_i = \\int \\varphi_i e^{u}` (``w.u`` the current iterate)."""
    return np.exp(w.u) * v


@BilinearForm
def weighted_mass(du, v, w):
    """:math:`\\int \\varphi_i \\varphi_j e^{u}`, the derivative of :func:`mass`."""
    return np.exp(w.u) * du * v


@LinearForm
def diffusion(v, w):
    """:math:`\\int \\varphi_i' P'` with :math:`P = e^{u}`."""
    return np.exp(w.u) * dot(grad(w.u), grad(v))


@BilinearForm
def diffusion_jacobian(du, v, w):
    """Derivative of :func:`diffusion` in the direction ``du``."""
    return np.exp(w.u) * (du * dot(grad(w.u), grad(v)) + dot(grad(du), grad(v)))


@LinearForm
def drift(v, w):
    """:math:`\\int \\varphi_i'\\, x\\, P` (``w.x`` the quadrature points)."""
    return np.exp(w.u) * w.x[0] * grad(v)[0]


@BilinearForm
def drift_jacobian(du, v, w):
    """Derivative of :func:`drift` in the direction ``du``."""
    return np.exp(w.u) * w.x[0] * grad(v)[0] * du
