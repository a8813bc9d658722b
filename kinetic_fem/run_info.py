"""How a result was obtained: the status record every solver attaches to its result.

:class:`RunInfo` is the ``info`` of a :class:`~kinetic_fem.VelocityDistribution`
(convergence, iterations, residual, wall time and method-specific figures in
``extra``), like SciPy's ``OdeResult``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

__all__ = ["RunInfo"]


@dataclass(frozen=True)
class RunInfo:
    """How a result was obtained: convergence, iterations, residual and cost.

    Like SciPy's ``OdeResult``.

    Attributes
    ----------
    converged : bool
        Whether the method's stopping criterion was met.
    iterations : int
        Newton iterations, time steps or collisions per particle, as the method counts.
    residual : float
        Final residual in the method's own norm (NaN where meaningless).
    wall_time : float
        Seconds spent in the solver.
    message : str
        Human-readable status.
    extra : dict
        JSON-serialisable method-specific figures (mesh size, seeds, ...).
    """

    converged: bool = True
    iterations: int = 0
    residual: float = float("nan")
    wall_time: float = float("nan")
    message: str = ""
    extra: Mapping[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        """One line: status, counts, cost and the names (not values) of ``extra``.

        Examples
        --------
        >>> RunInfo(iterations=7, residual=3e-13, wall_time=0.25, extra={"n_v": 601})
        RunInfo(converged=True, iterations=7, residual=3e-13, wall_time=0.25 s, extra=['n_v'])
        """
        parts = [f"converged={self.converged}", f"iterations={self.iterations}",
                 f"residual={self.residual:.3g}", f"wall_time={self.wall_time:.3g} s"]
        if self.message:
            msg = self.message if len(self.message) <= 60 else self.message[:57] + "..."
            parts.append(f"message={msg!r}")
        if self.extra:
            parts.append(f"extra={sorted(map(str, self.extra))}")
        return f"RunInfo({', '.join(parts)})"
