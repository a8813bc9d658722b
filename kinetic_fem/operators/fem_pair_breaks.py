"""Break points and pieces of the inner integrals of the FEM pair rule (numba kernels).

For an outer point :math:`x` the inner integrand of the collision weak form
(:mod:`kinetic_fem.operators.fem_kernels`) is smooth between the mesh vertices, the
point :math:`y = x` and the pre-images of the vertices under :math:`y \\mapsto x'(y)`
(and :math:`y \\mapsto y'(y)` for the full bracket); with a restitution law also where
the law jumps.  :func:`merge_breaks` (constant coefficient) and :func:`law_breaks` (a
law) list them in increasing order; :func:`pieces` turns them into inner pieces, split
geometrically towards :math:`y = x` where the kernel :math:`|g|^\\gamma` or the law is
not smooth there.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from .._jit import jit
from ..model.kernel_base import FAMILY_POWER_LAW
from ..model.restitution import THRESHOLD, restitution_value

__all__ = ["merge_breaks", "law_breaks", "pieces", "kernel_rate", "kernel_numeric",
           "kernel_graded", "preimage_distance",
           "GRADING_RATIO", "GRADING_LEVELS"]

GRADING_RATIO = 0.15
"""Ratio of the geometric pieces towards the singular point y = x."""
GRADING_LEVELS = 12
"""Number of geometric pieces on each side of y = x (graded quadrature only)."""

@jit
def merge_breaks(verts: np.ndarray, x: float, a: float, b: float, buf: np.ndarray,
                  second: bool) -> int:
    """Sorted breakpoints of the inner integrand in [v_0, v_E]; returns their count."""
    lo = verts[0]
    hi = verts[-1]
    nv = verts.size
    i1 = 0
    i2 = 0
    i3 = 0
    done4 = False
    n = 0
    inf = np.inf
    while True:
        c1 = verts[i1] if i1 < nv else inf
        c2 = (verts[i2] - a * x) / b if i2 < nv else inf
        c3 = (verts[i3] - b * x) / a if (second and i3 < nv and a > 0.0) else inf
        c4 = inf if done4 else x
        m = min(min(c1, c2), min(c3, c4))
        if m == inf:
            break
        if m == c1:
            i1 += 1
        elif m == c2:
            i2 += 1
        elif m == c3:
            i3 += 1
        else:
            done4 = True
        if m >= lo and m <= hi:
            buf[n] = m
            n += 1
    return n


def kernel_numeric(kernel: float | tuple[int, float]) -> tuple[int, float]:
    """``(family, parameter)`` of a kernel given as such a pair or as a power-law exponent.

    The compiled pair rule takes a power law as its exponent ``gamma`` (a float), any
    other kernel as its :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.numeric`:
    numba compiles one loop per argument type, so the power-law loop has no family
    branch at run time (the family code is a compile-time constant there).

    Parameters
    ----------
    kernel : float or tuple of (int, float)
        The exponent of a power law, or ``(family, parameter)``.

    Returns
    -------
    tuple of (int, float)
    """
    if isinstance(kernel, tuple):
        return kernel
    return FAMILY_POWER_LAW, float(kernel)


# (numba's TypedDict of jit options omits "cache", which overload accepts)
@overload(kernel_numeric, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _kernel_numeric_compiled(kernel):  # pragma: no cover - compiled
    if isinstance(kernel, types.Float):
        return lambda kernel: (FAMILY_POWER_LAW, kernel)
    return lambda kernel: kernel


@jit
def kernel_rate(kernel: float | tuple[int, float], g: float) -> float:
    """:math:`B(g)` for ``g >= 0`` of the kernel ``(family, parameter)``
    (:attr:`kinetic_fem.model.kernel_base.CollisionKernel.numeric`; a float: the exponent of
    a power law).

    Power law :math:`g^\\gamma` (multiplications for gamma in {0, 1, 2}, so the hard-rod
    and Maxwell rules are unchanged bit for bit; a square root for gamma = 1/2, correctly
    rounded where ``pow`` is within 0.52 ulp); saturating :math:`g/(1 + g/g_0)`.
    """
    family, p = kernel_numeric(kernel)
    if family == FAMILY_POWER_LAW:
        if p == 1.0:
            return g
        if p == 0.0:
            return 1.0
        if p == 2.0:
            return g * g
        if p == 0.5:  # sqrt: 1.3-1.6x faster kernel than pow (1 ulp apart in 0.08 %)
            return np.sqrt(g)
        return g ** p
    return g / (1.0 + g / p)  # FAMILY_SATURATING


@jit
def kernel_graded(kernel: float | tuple[int, float]) -> bool:
    """Whether :math:`B` has a kink of fractional order at :math:`g = 0`, so that the
    pieces next to :math:`y = x` are split geometrically (power laws with gamma not in
    {0, 1, 2}); the saturating kernel is analytic on either side of :math:`y = x`."""
    family, p = kernel_numeric(kernel)
    return family == FAMILY_POWER_LAW and p != 0.0 and p != 1.0 and p != 2.0


@jit
def preimage_distance(code: int, p0: float, p1: float, speed_scale: float, d: float,
                      b_lo: float) -> float:
    """The ``s >= 0`` with :math:`s\\,b(s) = d`, :math:`b(s) = (1 + \\alpha(s))/2`.

    For a law with :math:`s\\,b(s)` increasing (the viscoelastic law: its derivative
    :math:`2 - \\tfrac65 C_1 x + \\tfrac75 C_2 x^2 > 0`, :math:`x = \\delta s^{1/5}`),
    the root lies in :math:`[d, d/b_{lo}]` with :math:`b_{lo} = (1 + \\min\\alpha)/2`;
    regula falsi (Illinois) to round-off.  The law is evaluated at the physical speed
    ``s * speed_scale``.
    """
    if d <= 0.0:
        return 0.0
    lo = d
    hi = d / b_lo
    flo = lo * 0.5 * (1.0 + restitution_value(code, p0, p1, lo * speed_scale)) - d
    fhi = hi * 0.5 * (1.0 + restitution_value(code, p0, p1, hi * speed_scale)) - d
    if flo >= 0.0:
        return lo
    if fhi <= 0.0:
        return hi
    s = lo
    side = 0
    for _ in range(200):
        s = (lo * fhi - hi * flo) / (fhi - flo)
        fs = s * 0.5 * (1.0 + restitution_value(code, p0, p1, s * speed_scale)) - d
        if abs(fs) <= 4e-16 * d or hi - lo <= 4e-16 * hi:
            break
        if fs < 0.0:
            lo = s
            flo = fs
            if side == -1:
                fhi *= 0.5
            side = -1
        else:
            hi = s
            fhi = fs
            if side == 1:
                flo *= 0.5
            side = 1
    return s


@jit
def law_breaks(verts: np.ndarray, x: float, code: int, p0: float, p1: float,
                speed_scale: float, b_lo: float, pre: np.ndarray, buf: np.ndarray) -> int:
    """Sorted breakpoints for a velocity-dependent law; returns their count.

    Vertices, :math:`y = x` and the pre-images of the vertices under
    :math:`y \\mapsto x'(y)`: for the threshold law both linear families (elastic:
    :math:`x' = y`, the vertices themselves; inelastic: :math:`(v_k - a x)/b`) and the
    two jumps :math:`y = x \\pm g_{th}`; for a monotone law (viscoelastic) the root of
    :math:`x + b(|t|)\\,t = v_k`, :math:`t = y - x`.
    """
    nv = verts.size
    lo = verts[0]
    hi = verts[-1]
    if code == THRESHOLD:
        b = 0.5 * (1.0 + p0)
        a = 1.0 - b
        for k in range(nv):
            pre[k] = (verts[k] - a * x) / b
        th = p1 / speed_scale
        extras = (x - th, x, x + th)
        n_extra = 3
    else:
        for k in range(nv):
            d = verts[k] - x
            t = preimage_distance(code, p0, p1, speed_scale, abs(d), b_lo)
            pre[k] = x + t if d >= 0.0 else x - t
        extras = (x, np.inf, np.inf)
        n_extra = 1
    i1 = 0
    i2 = 0
    i3 = 0
    n = 0
    inf = np.inf
    while True:
        c1 = verts[i1] if i1 < nv else inf
        c2 = pre[i2] if i2 < nv else inf
        c3 = extras[i3] if i3 < n_extra else inf
        m = min(c1, min(c2, c3))
        if m == inf:
            break
        if m == c1:
            i1 += 1
        elif m == c2:
            i2 += 1
        else:
            i3 += 1
        if m >= lo and m <= hi:
            buf[n] = m
            n += 1
    return n


@jit
def pieces(buf: np.ndarray, n_br: int, x: float, scale: float, graded: bool,
            starts: np.ndarray, lengths: np.ndarray) -> int:
    """Inner pieces between consecutive breaks; returns their count.

    With ``graded`` the two pieces that end at :math:`y = x` (where :math:`|x-y|^\\gamma`
    or :math:`\\alpha(|x-y|)` is not smooth) are split geometrically towards :math:`x`
    (ratio :data:`GRADING_RATIO`, :data:`GRADING_LEVELS` levels), which restores the
    Gauss order up to the innermost piece of relative length
    :math:`0.15^{12} \\approx 10^{-10}`.
    """
    n_p = 0
    for s in range(n_br - 1):
        y0 = buf[s]
        length = buf[s + 1] - y0
        if length <= 1e-14 * scale:
            continue
        if graded and (buf[s + 1] == x or y0 == x):
            towards_right = buf[s + 1] == x
            outer = length
            for _ in range(GRADING_LEVELS):
                inner = outer * GRADING_RATIO
                starts[n_p] = x - outer if towards_right else x + inner
                lengths[n_p] = outer - inner
                n_p += 1
                outer = inner
            starts[n_p] = x - outer if towards_right else x
            lengths[n_p] = outer
            n_p += 1
        else:
            starts[n_p] = y0
            lengths[n_p] = length
            n_p += 1
    return n_p
