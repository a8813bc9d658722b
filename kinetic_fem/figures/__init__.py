"""Figures and claims of the paper computed by the deterministic methods.

Importing this package registers its items with :mod:`kinetic_fem.reproduce`; each
submodule owns the items of one capability.
"""

from . import analytic, cooling, heated, memory, scaling  # noqa: F401
