"""kinetic-fem: velocity distributions of the one-dimensional inelastic gas.

Deterministic solvers of the homogeneous Boltzmann equation

.. math::

    \\partial_t P - D\\partial_v^2 P = -n\\int dv'\\,|v-v'|P(v)P(v')
    + \\frac{4n}{(1+\\alpha)^2}\\int dv'\\,|v-v'|P(v')
      P\\Big(\\frac{2v-(1-\\alpha)v'}{1+\\alpha}\\Big)

(heated steady state, free cooling), its quasi-elastic limits, and the common
result type :class:`VelocityDistribution`.  Particle methods live in the
``particles`` package.

``import kinetic_fem`` is light (no scipy, numba or scikit-fem): every public name and
submodule is imported on first use (PEP 562 module ``__getattr__``), and the solver
modules register themselves with the solver registry the first time a solver, a
registry or ``register_solver`` is looked up (:func:`load_solvers`).
"""

from __future__ import annotations

import importlib as _importlib
import logging as _logging
import sys as _sys
import types as _types
from typing import Any as _Any

__version__ = "0.1.0"
__all__ = [
    "InelasticGas", "HeatedProblem", "CoolingProblem", "VelocityDistribution", "RunInfo",
    "solve_heated", "solve_cooling", "register_solver", "HEATED_SOLVERS", "COOLING_SOLVERS",
    "PowerLawKernel", "SaturatingKernel", "ThresholdRestitution", "ViscoelasticRestitution",
    "WhiteNoise", "FokkerPlanckBath", "sonine", "scaling", "grid", "gas", "model",
    "evolve_heated", "evolve_cooling", "relaxation_spectrum", "sweep", "load_solvers",
    "Mixture",
]

_NAMES = {
    "distribution": ("RunInfo", "VelocityDistribution"),
    "evolve": ("evolve_cooling", "evolve_heated"),
    "model": ("CoolingProblem", "FokkerPlanckBath", "HeatedProblem", "InelasticGas",
              "Mixture", "PowerLawKernel", "SaturatingKernel", "ThresholdRestitution",
              "ViscoelasticRestitution", "WhiteNoise"),
    "solve": ("COOLING_SOLVERS", "HEATED_SOLVERS", "register_solver", "solve_cooling",
              "solve_heated"),
    "solvers.relaxation": ("relaxation_spectrum",),
    "sweep": ("sweep",),  # kf.sweep is the function, kinetic_fem.sweep the package
}
_HOME = {name: module for module, names in _NAMES.items() for name in names}
"""Public name -> the module (relative to the package) that defines it."""

_SOLVER_MODULES = {"fd_cooling": "fd_cooling", "fem": "fem.heated", "fem_cooling": "fem.cooling",
                   "fem_mixture": "fem.mixture", "finite_difference": "finite_difference",
                   "mixture_spectral": "mixture_spectral",
                   "scaling": "scaling", "spectral": "spectral"}
"""Modules of :mod:`kinetic_fem.solvers` that register solvers; public as ``kf.<name>``
(``kf.fem`` is :mod:`kinetic_fem.solvers.fem.heated`, ``kf.fem_cooling``
:mod:`kinetic_fem.solvers.fem.cooling`)."""

_MODULES = {**{name: f"solvers.{path}" for name, path in _SOLVER_MODULES.items()},
            "grid": "operators.grid"}
"""Public module names that live elsewhere (``kf.scaling`` is kinetic_fem.solvers.scaling)."""

_SUBMODULES = ("analysis", "distribution", "evolution", "evolve", "exceptions", "gas", "io",
               "jit_cache", "model", "moments", "operators", "plot", "progress", "reproduce",
               "run_info", "solve", "solvers", "sonine")


def load_solvers() -> None:
    """Import every solver module, so that each registers its methods (once per process).

    :func:`solve_heated`, :func:`solve_cooling` and the registries call it; importing
    ``kinetic_fem`` alone does not, so that the import stays light.
    """
    if _LOADED:
        return
    _LOADED.append(True)
    for path in _SOLVER_MODULES.values():
        _importlib.import_module(f"{__name__}.solvers.{path}")


_LOADED: list[bool] = []


def __getattr__(name: str) -> _Any:
    """Import a public name or submodule on first use (PEP 562)."""
    if name in _HOME:
        if _HOME[name] == "solve":
            load_solvers()
        value = getattr(_importlib.import_module(f"{__name__}.{_HOME[name]}"), name)
    elif name in _MODULES:
        value = _importlib.import_module(f"{__name__}.{_MODULES[name]}")
    elif name in _SUBMODULES:
        value = _importlib.import_module(f"{__name__}.{name}")
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The public names (and the loaded submodules), not the helpers of this module."""
    loaded = [k for k, v in globals().items()
              if isinstance(v, _types.ModuleType) and not k.startswith("_")]
    return sorted({*__all__, *_MODULES, *_SUBMODULES, *loaded, "__version__"})


class _Package(_types.ModuleType):
    """The package's module type: ``kf.sweep`` stays the function when the
    ``kinetic_fem.sweep`` package is imported (the import system would set the
    attribute to the package)."""

    def __setattr__(self, name: str, value: _Any) -> None:
        if name == "sweep" and isinstance(value, _types.ModuleType):
            value = value.sweep
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package

# ``import kinetic_fem.scaling`` keeps working (kinetic_fem/scaling.py is an alias of
# kinetic_fem.solvers.scaling, where the quasi-elastic solvers moved).

_logging.getLogger(__name__).addHandler(_logging.NullHandler())
