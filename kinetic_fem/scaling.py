"""Quasi-elastic limits: the phi (heated) and psi (free cooling) equations.

Placeholder module; the solvers land with issue 4.
"""

__all__: list[str] = []
