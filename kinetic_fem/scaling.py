"""Alias of :mod:`kinetic_fem.solvers.scaling` (the quasi-elastic limits phi and psi).

``import kinetic_fem.scaling`` and ``kf.scaling`` keep working since the solvers moved
to :mod:`kinetic_fem.solvers`: this module replaces itself by that one on import (the
names below are for type checkers and readers; at run time the module is that one).
"""

import sys

from .solvers import scaling
from .solvers.scaling import (  # noqa: F401 - the public names of the alias
    LAMBDA_PAPER,
    PhiAsymptotics,
    PhiSolution,
    PsiAsymptotics,
    PsiSolution,
    phi_grid,
    solve_phi,
    solve_psi,
)

sys.modules[__name__] = scaling
