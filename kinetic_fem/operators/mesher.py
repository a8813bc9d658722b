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
new kernel family's mesh is a size rule, not a new loop.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray

__all__ = ["march", "log_drop_size"]


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
