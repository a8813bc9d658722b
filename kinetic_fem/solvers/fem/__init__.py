"""The Galerkin finite-element engine (scikit-fem) of the homogeneous Boltzmann equation.

One engine for every FEM problem (:doc:`/architecture`):

- :mod:`.heated`: the heated steady state (Newton on :math:`\\ln P_h`), with
  :mod:`.state` (the state, its interpolation and checks), :mod:`.defaults` (the model
  as the solver sees it: scales, cut-offs, meshes), :mod:`.grading` and :mod:`.start`;
- :mod:`.newton`: the FEM side of the shared Newton driver
  (:mod:`kinetic_fem.solvers.newton`): equilibrated LU, the log update, chord steps;
- :mod:`.cooling`: the homogeneous cooling state, its regimes as one table
  (:mod:`.regimes`), its forms, Newton and meshes (``cooling_*``), and the stored states
  (:mod:`.cooling_stored`, data files in ``data/`` with their generator
  ``python -m kinetic_fem.solvers.fem.cooling_generate``);
- :mod:`.curve` and :mod:`.cooling_curve`: curves over the restitution coefficient;
- :mod:`.transient`: the time integrator (:class:`~.transient.BDF2`) used by
  :mod:`.evolution` (heated transients) and :mod:`.cooling_transient` (free cooling);
- :mod:`.error`: a posteriori error estimates;
- :mod:`.mixture`: the coupled states of a granular mixture (one mesh per species);
- :mod:`.options`: :class:`~.options.MeshOptions`, the mesh options that travel together.

The public names of the heated solver (formerly the module ``kinetic_fem.solvers.fem``)
stay importable from here, loaded on first use.
"""

from __future__ import annotations

import importlib
from typing import Any


def __getattr__(name: str) -> Any:
    """The heated solver's public names (``kinetic_fem.solvers.fem.steady_state``, ...)."""
    heated = importlib.import_module(f"{__name__}.heated")
    try:
        return getattr(heated, name)
    except AttributeError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
