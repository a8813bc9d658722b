"""One mesher for the symmetric velocity meshes of the FEM solvers (issue 26).

Every mesh of the FEM cooling state is built the same way: vertices marched out from
:math:`c = 0`, each element as large as a *size rule* :math:`h(c)` allows at its inner
vertex, :math:`c_{k+1} = c_k + h(c_k)`, until a stop (a cut-off, or a test on the state
such as "ln f has fallen this far"), then mirrored about 0.  The size rules say how the
drop of :math:`\\ln f` is spread over the elements:

- from a state (or a start that predicts it): at most :math:`e` e-folds of
  :math:`\\ln f` per element, :math:`h = e/|(\\ln f)'(c)|` (:func:`log_drop_size`),
  bounded by a smallest and a largest element (the near-elastic humps'
  :func:`~kinetic_fem.operators.adaptive.hump_vertices`, the band's and the quasi-elastic
  chain's meshes);
- from the model's scales: the same drop per element for the tail the model predicts,
  :math:`\\ln f \\sim -c^\\gamma` (P2 error :math:`h^3 (\\ln f)'''` constant:
  :math:`h \\propto c^{(3-\\gamma)/3}`) or the power tail :math:`c^{-4}` of the Maxwell
  model (geometric elements).

:func:`march` is that one loop; the builders of the solvers are size rules over it, so a
new kernel family's mesh is a size rule, not a new loop.  :func:`log_drop_vertices` is the
rule "from a state" as one call: any :math:`\\ln f` (a callable: a state's ``log_f``, a
predictor of the state, the log of a
:class:`~kinetic_fem.distribution.VelocityDistribution`'s ``f``) and a
:class:`LogDropRule` (the e-folds per element, the smallest and largest element, a
uniform bulk, the depth of the cut-off) give the vertices; the band state's mesh
(:func:`~kinetic_fem.solvers.fem.cooling_band.band_vertices`) is one such rule, and
:func:`~kinetic_fem.solvers.fem.options.mesh_from_state` the public entry.
:class:`ScaleGrading` is the rule "from the model's scales" as one object: elements
:math:`h_0 \\max(1, c/c_b)^\\kappa`, marched (the cooling state's
:func:`~kinetic_fem.solvers.fem.cooling_mesh.hcs_vertices`) or placed uniformly in the
stretched coordinate (the heated state's
:func:`~kinetic_fem.solvers.fem.grading.graded_vertices`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from .grid import symmetric_grid, uniform_grid

__all__ = ["march", "log_drop_size", "LogDropRule", "log_drop_vertices", "ScaleGrading"]


def march(size: Callable[[float], float], stop: float | Callable[[float], bool], *,
          end: Literal["beyond", "snap"] = "beyond") -> NDArray[np.float64]:
    """Symmetric vertices marched from 0 by a size rule.

    Parameters
    ----------
    size : callable
        ``size(c) -> h > 0``: the element that starts at vertex ``c``.
    stop : float or callable
        A cut-off (the march goes on while ``c < stop``), or ``stop(c) -> bool`` tested
        at each vertex before the next element (True: the mesh ends at ``c``).
    end : {"beyond", "snap"}
        With a cut-off: keep the first vertex at or beyond it (``"beyond"``), or end
        exactly at it (``"snap"``: the last vertex is moved to the cut-off, after
        dropping it if it overshoots by more than half its element).

    Returns
    -------
    ndarray
        Increasing vertices, symmetric about 0, including 0.

    Examples
    --------
    >>> march(lambda c: 0.5, 1.2)
    array([-1.5, -1. , -0.5,  0. ,  0.5,  1. ,  1.5])
    >>> march(lambda c: 0.5, 1.2, end="snap")
    array([-1.2, -0.5,  0. ,  0.5,  1.2])
    >>> march(lambda c: 0.5 + c, lambda c: c > 2.0)
    array([-3.5, -1.5, -0.5,  0. ,  0.5,  1.5,  3.5])
    """
    if end not in ("beyond", "snap"):
        raise ValueError(f"end must be 'beyond' or 'snap', got {end!r}")
    nodes = [0.0]
    c = 0.0
    if callable(stop):
        if end != "beyond":
            raise ValueError("end='snap' needs a cut-off, not a stop test")
        while not stop(c):
            c = c + size(c)
            nodes.append(c)
    else:
        while c < stop:
            c = c + size(c)
            nodes.append(c)
    half = np.array(nodes)
    if end == "snap" and not callable(stop):
        if half.size > 2 and half[-1] - stop > 0.5 * (half[-1] - half[-2]):
            half = half[:-1]
        half[-1] = stop
    return np.concatenate([-half[:0:-1], half])


def log_drop_size(slope: float, efolds: float, *, largest: float = np.inf,
                  smallest: float = 0.0) -> float:
    """The element over which :math:`\\ln f` falls by ``efolds`` at ``slope``, within
    [``smallest``, ``largest``].

    Parameters
    ----------
    slope : float
        :math:`|(\\ln f)'|` at the element's inner vertex.
    efolds : float
        The drop of :math:`\\ln f` per element.
    largest, smallest : float
        Bounds of the element size.

    Returns
    -------
    float
        :math:`\\max(s, \\min(L, e/|(\\ln f)'|))` (a zero slope gives ``largest``).

    Examples
    --------
    >>> log_drop_size(4.0, 1.0, largest=0.5)
    0.25
    >>> log_drop_size(0.0, 1.0, largest=0.5)
    0.5
    """
    return max(smallest, min(largest, efolds / max(slope, 1e-300)))


@dataclass(frozen=True)
class LogDropRule:
    """Where vertices go along a given :math:`\\ln f`: a placement rule of
    :func:`log_drop_vertices`.

    Elements of size ``smallest`` out to ``bulk`` (a uniform bulk); beyond, each element
    carries at most ``efolds`` e-folds of :math:`\\ln f` (:func:`log_drop_size`), within
    [``smallest``, ``largest``], where the largest element may grow linearly beyond
    ``bulk``: :math:`L(c) = \\min(` ``largest`` :math:`, s\\,(1 + g (c - c_b)/\\ell))`
    (``growth`` :math:`g`, ``scale`` :math:`\\ell`; :math:`g = 0`: ``largest``).  The mesh
    ends at the first vertex where :math:`\\ln f` has fallen ``decades`` decades below its
    value at 0 (``from_peak``: below its largest value), or at the end of the probe.

    Parameters
    ----------
    efolds : float
        Largest drop of :math:`\\ln f` over one element beyond the bulk.
    smallest : float
        Smallest element, and the element of the bulk.
    largest : float
        Largest element.
    bulk : float
        End of the uniform bulk.
    growth, scale : float
        Linear growth of the largest element beyond the bulk, per ``scale``.
    decades : float
        Depth of the cut-off, decades.
    reach : float
        End of the probe of :math:`\\ln f` (its slope is read on ``probe`` points of
        [0, ``reach``]); the mesh ends there at the latest, or where :math:`\\ln f`
        stops being finite.
    probe : int
        Points of the probe.
    from_peak : bool
        Measure the cut-off's depth from the peak of :math:`\\ln f`, not from its value
        at 0 (a state with humps).

    Examples
    --------
    >>> LogDropRule(efolds=1.0, smallest=0.1).largest
    inf
    """

    efolds: float
    smallest: float
    largest: float = math.inf
    bulk: float = 0.0
    growth: float = 0.0
    scale: float = 1.0
    decades: float = 40.0
    reach: float = 40.0
    probe: int = 40001
    from_peak: bool = False

    def __post_init__(self) -> None:
        for name in ("efolds", "smallest", "largest", "scale", "decades", "reach"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ValueError(f"LogDropRule {name} must be > 0, got {value!r}")
        if self.largest < self.smallest:
            raise ValueError(f"LogDropRule largest ({self.largest!r}) must be at least "
                             f"smallest ({self.smallest!r})")
        if self.bulk < 0.0 or self.growth < 0.0:
            raise ValueError(f"LogDropRule bulk and growth must be >= 0, got {self.bulk!r}, "
                             f"{self.growth!r}")
        if self.probe < 3:
            raise ValueError(f"LogDropRule probe must be >= 3 points, got {self.probe!r}")


def log_drop_vertices(log_f: Callable[[NDArray[np.float64]], NDArray[np.float64]],
                      rule: LogDropRule) -> NDArray[np.float64]:
    """Symmetric vertices on which ``log_f`` drops by at most ``rule.efolds`` per element
    (:class:`LogDropRule`).

    Parameters
    ----------
    log_f : callable
        :math:`\\ln f` (even in :math:`c`) at an array of velocities :math:`c \\ge 0`: a
        state's, a predictor's, or the model's scales' (a Gaussian bulk and its tail).
    rule : LogDropRule
        The placement.

    Returns
    -------
    ndarray
        Increasing vertices, symmetric about 0, including 0.

    Examples
    --------
    >>> rule = LogDropRule(efolds=2.0, smallest=0.2, largest=1.0)
    >>> v = log_drop_vertices(lambda c: -0.5 * c**2, rule)
    >>> bool(v[0] == -v[-1] and np.all(np.diff(v) > 0)), bool(13.5 < v[-1] < 13.8)
    (True, True)
    >>> h = np.diff(v[v >= 0])  # (ln f)' = -c: h = 2/c within [0.2, 1]
    >>> round(float(h.min()), 9), round(float(h.max()), 9)
    (0.2, 1.0)
    """
    probe = np.linspace(0.0, rule.reach, rule.probe)
    start = np.asarray(log_f(probe), dtype=float)
    finite = np.isfinite(start)
    if not finite[0]:
        raise ValueError("log_f must be finite at c = 0")
    if not finite.all():  # a state that ends (f = 0 beyond its data): probe where it is
        end = int(np.argmin(finite))
        probe, start = probe[:end], start[:end]
    top = float(start.max()) if rule.from_peak else float(start[0])
    low = start < top - rule.decades * math.log(10.0)
    cutoff = float(probe[np.argmax(low)]) if low.any() else float(probe[-1])
    slope = np.maximum(-np.gradient(start, probe), 1e-300)
    h0 = rule.smallest

    def size(c: float) -> float:
        if c <= rule.bulk:
            return h0
        largest = rule.largest
        if rule.growth:
            largest = min(largest, h0 * (1.0 + rule.growth * (c - rule.bulk) / rule.scale))
        return log_drop_size(float(np.interp(c, probe, slope)), rule.efolds,
                             largest=largest, smallest=h0)

    return march(size, cutoff)


@dataclass(frozen=True)
class ScaleGrading:
    """Elements from the model's scales: :math:`h(c) = h_0 \\max(1, c/c_b)^\\kappa`.

    For the tail :math:`\\ln f \\sim -c^\\gamma` the P2 error :math:`h^3 (\\ln f)'''` is
    constant with :math:`\\kappa = (3 - \\gamma)/3`; :math:`\\kappa = 0` is a uniform mesh.

    Parameters
    ----------
    spacing : float
        :math:`h_0`, the bulk element.
    grading : float
        :math:`\\kappa \\ge 0`.
    bulk : float
        :math:`c_b`, the end of the uniform bulk.

    Examples
    --------
    >>> ScaleGrading(0.1, 0.5, bulk=2.0).size(8.0)
    0.2
    """

    spacing: float
    grading: float
    bulk: float = 3.0

    def size(self, c: float) -> float:
        """The element at ``c``."""
        return self.spacing * max(1.0, c / self.bulk) ** self.grading

    def marched(self, c_max: float) -> NDArray[np.float64]:
        """Vertices marched by :meth:`size` out to exactly ``c_max`` (:func:`march`,
        ``end="snap"``)."""
        return march(self.size, c_max, end="snap")

    def stretched(self, c_max: float) -> NDArray[np.float64]:
        """Vertices uniform in the stretched coordinate :math:`s(c) = \\int_0^c dc/h(c)`
        (inverted in closed form), :math:`\\lceil s(c_{max}) \\rceil` elements a side (at
        least 2); uniform for :math:`\\kappa = 0`."""
        if self.grading == 0.0:
            half = max(2, int(math.ceil(c_max / self.spacing)))
            return symmetric_grid(uniform_grid(c_max, half + 1))
        total = self._stretch(c_max)
        n_el = max(2, int(math.ceil(total)))
        targets = np.linspace(0.0, total, n_el + 1)
        nodes = np.concatenate([[0.0], self._unstretch(targets[1:-1]), [c_max]])
        return np.concatenate([-nodes[:0:-1], nodes])

    def _stretch(self, c: float) -> float:
        h0, kappa, cb = self.spacing, self.grading, self.bulk
        if c <= cb:
            return c / h0
        if kappa == 1.0:
            return (cb + cb * math.log(c / cb)) / h0
        return (cb + cb / (1.0 - kappa) * ((c / cb) ** (1.0 - kappa) - 1.0)) / h0

    def _unstretch(self, s: NDArray[np.float64]) -> NDArray[np.float64]:
        # the inverse of _stretch in closed form (the former root-finding to 2e-12 took
        # 4 % of a heated state)
        h0, kappa, cb = self.spacing, self.grading, self.bulk
        t = np.asarray(s, dtype=float) * h0 / cb  # the stretched coordinate in units of c_b
        tail = t > 1.0
        out = cb * t
        if kappa == 1.0:
            out[tail] = cb * np.exp(t[tail] - 1.0)
        else:
            out[tail] = cb * (1.0 + (1.0 - kappa) * (t[tail] - 1.0)) ** (1.0 / (1.0 - kappa))
        return out
