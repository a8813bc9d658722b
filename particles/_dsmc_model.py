"""The collision kernel as the DSMC sees it: kernel codes, rates and majorants.

The compiled loops of :mod:`particles._dsmc_kernels` dispatch on an integer kernel code
and one parameter, taken from the kernel's
:attr:`~kinetic_fem.model.kernel_base.CollisionKernel.numeric` by :func:`kernel_model`:
the power laws keep their own codes (Maxwell without rejection, hard rods and
:math:`\\gamma = 2` without a power), other families have a code each.  The candidate
rate of a time step is :math:`nN B(g_{max})/2` with :func:`kernel_majorant`, and a
candidate is accepted with probability :math:`B(|g|)/B(g_{max})`
(:func:`particles._dsmc_kernels.collide_power`).
"""

from __future__ import annotations

from kinetic_fem.model import UnsupportedModelError
from kinetic_fem.model.kernel import as_kernel
from kinetic_fem.model.kernel_base import FAMILY_POWER_LAW, FAMILY_SATURATING, CollisionKernel

from ._jit import jit

__all__ = ["KERNEL_MAXWELL", "KERNEL_HARD_RODS", "KERNEL_SQUARE", "KERNEL_POWER",
           "KERNEL_SATURATING", "kernel_code", "kernel_model", "kernel_majorant",
           "kernel_value", "power_exponent", "saturating_rate"]

KERNEL_MAXWELL = 0
"""Kernel code of :math:`\\gamma = 0` (no rejection)."""
KERNEL_HARD_RODS = 1
"""Kernel code of :math:`\\gamma = 1`."""
KERNEL_SQUARE = 2
"""Kernel code of :math:`\\gamma = 2` (acceptance ``g^2 > U g_max^2``, no power)."""
KERNEL_POWER = 3
"""Kernel code of any other exponent in ``(0, 2)``."""
KERNEL_SATURATING = 4
"""Kernel code of the saturating kernel :math:`|g|/(1 + |g|/g_0)` (parameter :math:`g_0`)."""


def kernel_code(gamma: float | CollisionKernel) -> int:
    """The kernel code of a kernel or of the exponent ``gamma`` of a power law.

    Parameters
    ----------
    gamma : float or CollisionKernel
        The kernel (validated by the model layer).

    Returns
    -------
    int

    Examples
    --------
    >>> kernel_code(0.0), kernel_code(1.0), kernel_code(2.0), kernel_code(0.5)
    (0, 1, 2, 3)
    """
    return kernel_model(gamma)[0]


def kernel_model(kernel: float | CollisionKernel) -> tuple[int, float]:
    """``(kernel code, parameter)`` of the compiled loops, from the kernel's
    :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.numeric`: the exponent of a power
    law (codes 0-3) or :math:`g_0` of the saturating kernel (:data:`KERNEL_SATURATING`).

    Parameters
    ----------
    kernel : float or CollisionKernel
        The kernel, or the exponent of a power law.

    Returns
    -------
    tuple of (int, float)

    Raises
    ------
    UnsupportedModelError
        For a kernel family the DSMC has no acceptance rule for.

    Examples
    --------
    >>> from kinetic_fem.model import SaturatingKernel
    >>> kernel_model(1.0), kernel_model(SaturatingKernel(2.0))
    ((1, 1.0), (4, 2.0))
    """
    family, parameter = as_kernel(kernel).numeric
    if family == FAMILY_POWER_LAW:
        code = {0.0: KERNEL_MAXWELL, 1.0: KERNEL_HARD_RODS, 2.0: KERNEL_SQUARE}.get(
            float(parameter), KERNEL_POWER)
        return code, float(parameter)
    if family == FAMILY_SATURATING:
        return KERNEL_SATURATING, float(parameter)
    raise UnsupportedModelError(f"the DSMC has no acceptance rule for the kernel {kernel!r}")


@jit
def saturating_rate(g, g0):  # pragma: no cover - compiled
    """:math:`B(g) = g/(1 + g/g_0)` for ``g >= 0`` (the saturating kernel)."""
    return g / (1.0 + g / g0)


@jit
def kernel_majorant(kcode, kparam, g_max):  # pragma: no cover - compiled
    """:math:`B(g_{max})`, the majorant of :math:`B` over :math:`|g| \\le g_{max}`
    (exact multiplications for the kernel codes 0, 1, 2)."""
    if kcode == KERNEL_HARD_RODS:
        return g_max
    if kcode == KERNEL_MAXWELL:
        return 1.0
    if kcode == KERNEL_SQUARE:
        return g_max * g_max
    if kcode == KERNEL_SATURATING:
        return saturating_rate(g_max, kparam)
    return g_max**kparam


@jit
def kernel_value(kcode, kparam, g):  # pragma: no cover - compiled
    """:math:`B(g)` for ``g >= 0`` (the kernel codes 0, 1, 2 by exact multiplications, so
    that :math:`B(g) \\le` :func:`kernel_majorant` at :math:`g \\le g_{max}` holds in
    floating point too)."""
    return kernel_majorant(kcode, kparam, g)


def power_exponent(kernel: float | CollisionKernel) -> float | None:
    """The exponent of a power-law kernel, None for another family the DSMC accepts
    (:func:`kernel_model`, which raises for the others).

    >>> from kinetic_fem.model import SaturatingKernel
    >>> power_exponent(1.0), power_exponent(SaturatingKernel(2.0))
    (1.0, None)
    """
    code, parameter = kernel_model(kernel)
    return None if code == KERNEL_SATURATING else parameter
