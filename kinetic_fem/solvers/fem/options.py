"""The mesh of an FEM solve as one object (issue 26).

:class:`MeshOptions` holds the options of the velocity mesh that travel together: the
Lagrange degree, the bulk spacing, the cut-off, explicit vertices and the Gauss degree.
The FEM solvers take it as ``mesh=`` and still take each field by keyword
(``kf.solve_heated(0.5, spacing=0.2)``), through :func:`kinetic_fem.options.gather`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from numpy.typing import ArrayLike

__all__ = ["MeshOptions"]


@dataclass(frozen=True)
class MeshOptions:
    """The velocity mesh of an FEM solve (None: the solver's default).

    Parameters
    ----------
    order : int, optional
        Lagrange degree, 1, 2 or 3.
    spacing : float, optional
        Bulk element size, thermal velocities.
    cutoff : float, optional
        Half-width of the velocity interval, thermal velocities.
    vertices : array_like, optional
        Explicit symmetric vertices (overrides ``spacing`` and ``cutoff``).
    intorder : int, optional
        Gauss degree (default ``2 * order + 1``).

    Examples
    --------
    >>> MeshOptions(order=3, spacing=0.2)
    MeshOptions(order=3, spacing=0.2, cutoff=None, vertices=None, intorder=None)
    """

    order: int | None = None
    spacing: float | None = None
    cutoff: float | None = None
    vertices: ArrayLike | None = field(default=None, compare=False)
    intorder: int | None = None
