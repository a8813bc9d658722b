"""The Galerkin discretisation shared by the FEM solvers (heated, transient, cooling).

Lagrange elements (scikit-fem) on a velocity mesh; the unknown is :math:`u_h = \\ln P_h`.
Weak forms: the white-noise term :math:`\\int\\varphi_i' P'`
(:func:`fokker_planck`), the bath drift :math:`\\int \\varphi_i' v P` (:func:`bath_drift`),
the mass :math:`\\int\\varphi_i P`, each with its Jacobian; the collision weak form
(any kernel :math:`B(g)`, any restitution law) by the pair rule of
:mod:`kinetic_fem.operators.fem_kernels`.  See :mod:`kinetic_fem.solvers.fem` for the equations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse
from numpy.typing import NDArray
from skfem import (
    Basis,
    BilinearForm,
    ElementH1,
    ElementLineP1,
    ElementLineP2,
    LinearForm,
    MeshLine,
    asm,
)
from skfem.helpers import dot, grad
from skfem.refdom import RefLine

from ..distribution import VelocityDistribution
from ..model import CollisionKernel, RestitutionLaw, as_kernel
from ..model.kernel_base import FAMILY_POWER_LAW
from ..model.restitution import CONSTANT
from .fem_kernels import evaluate_field
from .fem_pair_parallel import collision

__all__ = ["FEMDiscretisation", "ELEMENTS", "LAGRANGE_ELEMENTS", "ElementLineP3",
           "fokker_planck", "fokker_planck_jacobian", "bath_drift", "bath_drift_jacobian",
           "mass", "weighted_mass"]



class ElementLineP3(ElementH1):
    """Piecewise cubic Lagrange element (dofs: left and right vertex, then the points
    1/3 and 2/3 of the element)."""

    nodal_dofs = 1
    interior_dofs = 2
    maxdeg = 3
    dofnames = ["u", "u", "u"]
    doflocs = np.array([[0.0], [1.0], [1.0 / 3.0], [2.0 / 3.0]])
    refdom = RefLine

    def lbasis(self, X, i):
        """Value and gradient of the ``i``-th shape function at the points ``X``."""
        x = X[0]
        if i == 0:
            return (-4.5 * (x - 1 / 3) * (x - 2 / 3) * (x - 1),
                    np.array([-4.5 * (3 * x**2 - 4 * x + 11 / 9)]))
        if i == 1:
            return (4.5 * x * (x - 1 / 3) * (x - 2 / 3),
                    np.array([4.5 * (3 * x**2 - 2 * x + 2 / 9)]))
        if i == 2:
            return (13.5 * x * (x - 2 / 3) * (x - 1),
                    np.array([13.5 * (3 * x**2 - 10 / 3 * x + 2 / 3)]))
        if i == 3:
            return (-13.5 * x * (x - 1 / 3) * (x - 1),
                    np.array([-13.5 * (3 * x**2 - 8 / 3 * x + 1 / 3)]))
        return self._index_error()


LAGRANGE_ELEMENTS = {1: ElementLineP1, 2: ElementLineP2, 3: ElementLineP3}
"""Lagrange elements by degree (P3: the heated steady state's default for the paper's
model)."""
ELEMENTS = {1: ElementLineP1, 2: ElementLineP2}
"""The degrees every FEM solver supports (the cooling and transient solvers: P1, P2)."""


@LinearForm
def fokker_planck(v, w):
    """:math:`\\int \\varphi_i' P'` with :math:`P = e^{u}` (``w.u`` the current iterate)."""
    return np.exp(w.u) * dot(grad(w.u), grad(v))


@BilinearForm
def fokker_planck_jacobian(du, v, w):
    """Derivative of :func:`fokker_planck` in direction ``du``."""
    return np.exp(w.u) * (du * dot(grad(w.u), grad(v)) + dot(grad(du), grad(v)))


@LinearForm
def bath_drift(v, w):
    """:math:`\\int \\varphi_i' \\, v P` with :math:`P = e^{u}`: the weak form of
    :math:`-\\partial_v(vP)` (times the friction :math:`\\xi`; zero flux at the ends)."""
    return w.x[0] * np.exp(w.u) * grad(v)[0]


@BilinearForm
def bath_drift_jacobian(du, v, w):
    """Derivative of :func:`bath_drift` in direction ``du``."""
    return w.x[0] * np.exp(w.u) * du * grad(v)[0]


@LinearForm
def mass(v, w):
    """:math:`\\int \\varphi_i e^{u}` (also the gradient of the total mass)."""
    return np.exp(w.u) * v


@BilinearForm
def weighted_mass(du, v, w):
    """:math:`\\int \\varphi_i \\varphi_j e^{u}`, the derivative of :func:`mass`."""
    return np.exp(w.u) * du * v


@dataclass(frozen=True, eq=False)
class FEMDiscretisation:
    """The Galerkin discretisation of the heated problem at ``n = D = 1``.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    vertices : ndarray, shape (E + 1,)
        Mesh vertices, symmetric about 0 with a vertex at 0.
    order : int
        Lagrange degree, 1, 2 or 3.
    intorder : int
        Degree of exactness of the Gauss rule (outer points and inner pieces).
    symmetric : bool
        Full collision bracket, exact conservation for any P (default: the reduced
        bracket, more accurate as alpha -> 1; see
        :func:`kinetic_fem.operators.fem_kernels.collision_operator`); constant laws only.
    gamma : float or CollisionKernel
        The collision kernel (a float: the exponent of :math:`B(g) = |g|^\\gamma`); the
        pair rule evaluates it through its
        :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.numeric`.
    law : RestitutionLaw, optional
        A velocity-dependent restitution law (evaluated at ``speed_scale`` times the
        relative speed); ``None``: the constant ``alpha``.
    friction : float
        Scaled friction :math:`\\xi` of a Fokker-Planck bath (0: white noise).
    speed_scale : float
        Physical speed of a unit of mesh velocity.
    """

    alpha: float
    vertices: NDArray[np.float64]
    order: int = 2
    intorder: int = 5
    symmetric: bool = False
    gamma: float | CollisionKernel = 1.0
    law: RestitutionLaw | None = None
    friction: float = 0.0
    speed_scale: float = 1.0

    def __post_init__(self) -> None:
        if self.symmetric and self.law is not None and self.law.constant is None:
            raise ValueError("symmetric=True (the full collision bracket) needs a constant "
                             f"restitution coefficient, got {self.law!r}; use the default "
                             "reduced bracket")

    @cached_property
    def kernel(self) -> CollisionKernel:
        """The collision kernel (:attr:`gamma` as a kernel object)."""
        return as_kernel(self.gamma)

    @cached_property
    def _kernel_argument(self) -> float | tuple[int, float]:
        """The kernel for the compiled pair rule: a power law as its exponent (numba
        specialises on the type, so the power-law loop is the one from before, bit for bit
        and at the same speed), another family as its ``(family, parameter)``."""
        family, parameter = self.kernel.numeric
        return float(parameter) if family == FAMILY_POWER_LAW else (family, float(parameter))

    @cached_property
    def _law_arrays(self) -> tuple[int, float, float, float]:
        """``(code, p0, p1, b_lo)`` of the law for the kernels."""
        law = self.law
        if law is None or law.constant is not None:
            alpha = self.alpha if law is None or law.constant is None else law.constant
            return CONSTANT, alpha, 0.0, 0.5 * (1.0 + alpha)
        p0, p1 = law.parameters
        return law.code, p0, p1, 0.5 * (1.0 + law.min_alpha)

    @cached_property
    def basis(self) -> Basis:
        """The scikit-fem basis (owns the outer quadrature)."""
        return Basis(MeshLine(self.vertices), LAGRANGE_ELEMENTS[self.order](),
                     intorder=self.intorder)

    @cached_property
    def points(self) -> tuple[NDArray, NDArray, NDArray]:
        """Outer quadrature points, weights and element indices, flattened."""
        x = self.basis.mapping.F(self.basis.X)[0]  # (E, nq)
        w = self.basis.dx
        e = np.repeat(np.arange(x.shape[0]), x.shape[1]).reshape(x.shape)
        return x.ravel(), w.ravel(), e.ravel()

    @cached_property
    def mesh_arrays(self) -> tuple[NDArray, NDArray]:
        """Vertices, shape (n_v,), and element dofs, shape (n_e, n_local), contiguous
        arrays for the numba kernels."""
        verts = np.ascontiguousarray(self.basis.mesh.p[0], dtype=float)
        dofs = np.ascontiguousarray(self.basis.element_dofs.T, dtype=np.int64)
        return verts, dofs

    @property
    def dof_locations(self) -> NDArray[np.float64]:
        """Velocity of each degree of freedom."""
        return self.basis.doflocs[0]

    @cached_property
    def symmetry(self) -> scipy.sparse.csr_matrix:
        """Sparse ``S`` with ``u = S u_even``: even fields from the dofs at ``v >= 0``."""
        x = self.dof_locations
        scale = np.abs(x).max()
        key = np.round(np.abs(x) / scale * 2**40).astype(np.int64)
        keep = np.flatnonzero(x >= 0)
        lookup = dict(zip(key[keep].tolist(), range(keep.size), strict=True))
        try:
            cols = np.array([lookup[k] for k in key.tolist()])
        except KeyError as err:
            raise ValueError("the mesh must be symmetric about v = 0") from err
        return scipy.sparse.csr_matrix((np.ones(x.size), (np.arange(x.size), cols)),
                                       shape=(x.size, keep.size))

    @cached_property
    def mirror(self) -> NDArray[np.int64]:
        """The dof at :math:`-v` of each dof (the mesh must be symmetric about 0)."""
        sym = self.symmetry
        x = self.dof_locations
        keep = np.flatnonzero(x >= 0)
        by_even = np.full(sym.shape[1], -1, dtype=np.int64)
        by_even[sym.indices[keep]] = keep  # even index -> its dof at v >= 0
        positive = by_even[sym.indices]  # dof at |v| of each dof
        mirror = np.empty(x.size, dtype=np.int64)
        neg = np.flatnonzero(x < 0)
        pos = np.flatnonzero(x > 0)
        mirror[neg] = positive[neg]
        mirror[positive[neg]] = neg
        zero = np.setdiff1d(np.arange(x.size), np.concatenate([neg, pos]))
        mirror[zero] = zero
        return mirror

    def field(self, u: NDArray[np.float64]):
        """``u`` as a scikit-fem field at the quadrature points."""
        return self.basis.interpolate(u)

    def _collide(self, u: NDArray[np.float64], jacobian: bool,
                 energy_power: int, even: bool = False) -> tuple[NDArray, NDArray, float, float]:
        # energy_power < 0: no pair moments (the kernel skips them)
        verts, dofs = self.mesh_arrays
        xq, wq, eq = self.points
        ref_x, ref_w = self.basis.quadrature
        code, p0, p1, b_lo = self._law_arrays
        args = (verts, dofs, self.order, np.ascontiguousarray(u), xq, wq, eq,
                np.ascontiguousarray(ref_x[0]), ref_w, p0, 1.0, jacobian, int(energy_power),
                self.symmetric, self._kernel_argument, code, p0, p1, float(self.speed_scale),
                b_lo)
        out = collision(*args, self.mirror) if even else collision(*args)
        if energy_power >= 0:
            # the loss moment does not depend on energy_power or the Jacobian (same sums
            # in the same order): energy_loss at the same u reuses it
            self._last_loss.clear()
            self._last_loss[even] = (np.array(u, dtype=float), out[3])
        return out

    @cached_property
    def _last_loss(self) -> dict[bool, tuple[NDArray, float]]:
        """The coefficients and loss moment of the last collision call (by ``even``)."""
        return {}

    def collision(self, u: NDArray[np.float64], *, jacobian: bool = False,
                  energy_power: int | None = 3, even: bool = False
                  ) -> tuple[NDArray, NDArray, float]:
        """Weak collision term, its Jacobian and the pair moment ``<|g|^p>``.

        Parameters
        ----------
        u : ndarray, shape (N,)
            Coefficients of :math:`u_h = \\ln P_h`.
        jacobian : bool
            Also the dense Jacobian (else a (1, 1) placeholder).
        energy_power : int or None
            ``p >= 0`` of the pair moment; ``None``: no moment (returned as 0, a few per
            cent faster).
        even : bool
            ``u`` is even (symmetric mesh): visit only the outer points at
            :math:`v > 0` and mirror them, half the cost (equal to round-off).
        """
        if energy_power is None:
            return self._collide(u, jacobian, -1, even)[:3]
        if energy_power < 0:
            raise ValueError(f"energy_power must be a non-negative integer, got {energy_power}")
        return self._collide(u, jacobian, energy_power, even)[:3]

    def energy_loss(self, u: NDArray[np.float64], *, even: bool = False) -> float:
        """Pair-quadrature energy loss :math:`\\tfrac14\\langle(1-\\alpha(g)^2)
        |g|^{\\gamma+2}\\rangle` (``n = 1``), the loss side of C1 (``even``: see
        :meth:`collision`); the moment of the last :meth:`collision` call at the same
        ``u`` is reused (the sums are the same, so the value is too)."""
        last = self._last_loss.get(even)
        if last is not None and np.array_equal(last[0], u):
            return 0.25 * last[1]
        return 0.25 * self._collide(u, False, 0, even)[3]

    def transport(self, u: NDArray[np.float64], *, jacobian: bool = False
                  ) -> tuple[NDArray, NDArray | None]:
        """Weak thermostat term :math:`-\\int\\varphi_i'(P' + \\xi v P)` and its Jacobian."""
        field = self.field(u)
        res = -asm(fokker_planck, self.basis, u=field)
        if self.friction > 0.0:
            res -= self.friction * asm(bath_drift, self.basis, u=field)
        if not jacobian:
            return res, None
        jac = asm(fokker_planck_jacobian, self.basis, u=field)
        if self.friction > 0.0:
            jac = jac + self.friction * asm(bath_drift_jacobian, self.basis, u=field)
        return res, -jac.toarray()

    def residual(self, u: NDArray[np.float64], *, jacobian: bool = False, even: bool = False
                 ) -> tuple[NDArray, NDArray | None]:
        """:math:`R_i = -\\int \\varphi_i' (P' + \\xi v P) + C_i` and optionally its dense
        Jacobian (``even``: see :meth:`collision`)."""
        coll, cjac, _ = self.collision(u, jacobian=jacobian, energy_power=None, even=even)
        heat, hjac = self.transport(u, jacobian=jacobian)
        res = coll + heat
        if not jacobian:
            return res, None
        return res, cjac + hjac

    def values(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """:math:`P_h = e^{u_h}` at the outer quadrature points."""
        return np.exp(np.asarray(self.field(u))).ravel()

    def evaluate(self, u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
        """:math:`P_h(v) = e^{u_h(v)}` at increasing points ``v`` inside the mesh."""
        verts, dofs = self.mesh_arrays
        return np.exp(evaluate_field(verts, dofs, self.order, np.ascontiguousarray(u),
                                     np.ascontiguousarray(v, dtype=float)))

    def gaussian(self, temperature: float) -> NDArray[np.float64]:
        """Coefficients of :math:`\\ln` of the normalised Gaussian (exact in P2)."""
        x = self.dof_locations
        return -0.5 * x**2 / temperature - 0.5 * math.log(2.0 * math.pi * temperature)

    def distribution(self, u: NDArray[np.float64], **kwargs) -> VelocityDistribution:
        """The result on the quadrature points with the quadrature weights."""
        xq, wq, _ = self.points
        return VelocityDistribution.from_values(xq, self.values(u), weights=wq, **kwargs)
