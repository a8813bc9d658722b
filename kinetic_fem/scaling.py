"""Alias of :mod:`kinetic_fem.solvers.scaling` (the quasi-elastic limits phi and psi).

``import kinetic_fem.scaling`` and ``kf.scaling`` keep working since the solvers moved
to :mod:`kinetic_fem.solvers`: this module replaces itself by that one on import.
"""

import sys

from .solvers import scaling

sys.modules[__name__] = scaling
