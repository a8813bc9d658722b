"""Binary mixtures by their scalar parameters, and their states by method name.

:func:`binary_mixture` builds a two-species :class:`~kinetic_fem.Mixture` from numbers (the
mass ratio, the fraction of species 1, the three restitution coefficients, the forcing
convention), so that a sweep grid (:func:`kinetic_fem.sweep`), a TOML file of the CLI and
a figure can name them; :func:`solve_binary` computes its heated steady state or
homogeneous cooling state with one of the methods of :data:`MIXTURE_STATE_METHODS`
(each a pair of functions ``(steady_state, cooling_state)`` returning a
:class:`~kinetic_fem.mixture_state.MixtureMoments`).  A method is one entry of that table;
``"fem"`` is the FEM mixture solver (:mod:`kinetic_fem.solvers.fem.mixture`).
"""

from __future__ import annotations

from typing import Any, Callable

from .mixture_state import MixtureMoments
from .model.mixture import FORCING_CONVENTIONS, Mixture
from .model.validation import check_positive

__all__ = ["binary_mixture", "solve_binary", "solve_mixture", "MIXTURE_STATE_METHODS",
           "BINARY_FORCINGS"]

#: the forcings of :func:`binary_mixture`: the two white-noise conventions, or none
BINARY_FORCINGS = (*FORCING_CONVENTIONS, "cooling")

StateFunction = Callable[..., MixtureMoments]


def _sonine() -> tuple[StateFunction, StateFunction]:
    from .solvers import mixture_sonine

    return mixture_sonine.steady_state, mixture_sonine.cooling_state


def _gaussian() -> tuple[StateFunction, StateFunction]:
    from .solvers import mixture_gaussian

    return mixture_gaussian.steady_state, mixture_gaussian.cooling_state


def _maxwell() -> tuple[StateFunction, StateFunction]:
    from .solvers import maxwell_mixture

    return maxwell_mixture.steady_state, maxwell_mixture.cooling_state


def _spectral() -> tuple[StateFunction, StateFunction]:
    """The Sonine Galerkin method of the mixture (order 8)."""
    from .solvers import mixture_spectral

    return mixture_spectral.steady_state, mixture_spectral.cooling_state


def _fem() -> tuple[StateFunction, StateFunction]:
    from .solvers.fem import mixture as fem_mixture

    def steady_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
        return fem_mixture.solve_mixture_heated(mixture, density=density).moments()

    def cooling_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
        return fem_mixture.solve_mixture_cooling(mixture, density=density).moments()

    return steady_state, cooling_state


#: method name -> loader of ``(steady_state, cooling_state)``, each called as
#: ``function(mixture, density=...)``; ``"sonine"`` is first-order Sonine theory,
#: ``"gaussian"`` Gaussian species, ``"maxwell"`` the exact Maxwell mixture (kernel 0),
#: ``"fem"`` the FEM states at their default mesh (:mod:`kinetic_fem.solvers.fem.mixture`;
#: their moments up to the fourth), ``"spectral"`` the Sonine Galerkin method (order 8,
#: :mod:`kinetic_fem.solvers.mixture_spectral`)
MIXTURE_STATE_METHODS: dict[str, Callable[[], tuple[StateFunction, StateFunction]]] = {
    "sonine": _sonine, "gaussian": _gaussian, "maxwell": _maxwell, "spectral": _spectral,
    "fem": _fem}


def binary_mixture(mass_ratio: float, *, fraction: float = 0.5, alpha: float = 0.9,
                   alpha_11: float | None = None, alpha_12: float | None = None,
                   alpha_22: float | None = None, kernel: Any = 1.0,
                   forcing: str = "same_diffusion", diffusion: float = 1.0) -> Mixture:
    """A binary mixture from scalars: species 1 of mass 1, species 2 of mass ``mass_ratio``.

    Parameters
    ----------
    mass_ratio : float
        :math:`m_2/m_1 > 0` (:math:`m_1 = 1`).
    fraction : float
        Number fraction :math:`x_1` of species 1, in (0, 1).
    alpha : float
        Restitution coefficient of every pair not given below.
    alpha_11, alpha_12, alpha_22 : float, optional
        The coefficient of a pair.
    kernel : float or CollisionKernel
        The collision kernel.
    forcing : {"same_diffusion", "same_power", "cooling"}
        White noise with the same :math:`D` for both species or :math:`D_s = D/m_s`
        (:meth:`Mixture.white_noise`), or free cooling.
    diffusion : float
        :math:`D`.

    Returns
    -------
    Mixture

    Examples
    --------
    >>> binary_mixture(4.0, fraction=0.3, alpha_12=0.5).constant_alpha().tolist()
    [[0.9, 0.5], [0.5, 0.9]]
    """
    ratio = check_positive("mass_ratio", mass_ratio)
    x1 = check_positive("fraction", fraction)
    if not x1 < 1.0:
        raise ValueError(f"fraction (x_1 of species 1) must lie in (0, 1), got {fraction!r}")
    if forcing not in BINARY_FORCINGS:
        raise ValueError(f"forcing must be one of {BINARY_FORCINGS}, got {forcing!r}")
    table = [[alpha if alpha_11 is None else alpha_11, alpha if alpha_12 is None else alpha_12],
             [alpha if alpha_12 is None else alpha_12, alpha if alpha_22 is None else alpha_22]]
    masses, fractions = (1.0, ratio), (x1, 1.0 - x1)
    if forcing == "cooling":
        return Mixture(masses, fractions, alpha=table, kernel=kernel)
    return Mixture.white_noise(masses, fractions, alpha=table, kernel=kernel,
                               diffusion=diffusion, convention=forcing)


def solve_mixture(mixture: Mixture, *, density: float = 1.0,
                  method: str = "sonine") -> MixtureMoments:
    """The heated steady state or the homogeneous cooling state of ``mixture``.

    Parameters
    ----------
    mixture : Mixture
    density : float
        Total number density.
    method : str
        A key of :data:`MIXTURE_STATE_METHODS`.

    Returns
    -------
    MixtureMoments
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    if method not in MIXTURE_STATE_METHODS:
        raise ValueError(f"method must be one of {sorted(MIXTURE_STATE_METHODS)} for a "
                         f"mixture, got {method!r}")
    steady, cooling = MIXTURE_STATE_METHODS[method]()
    return (steady if mixture.heated else cooling)(mixture, density=density)


def solve_binary(mass_ratio: float, *, fraction: float = 0.5, alpha: float = 0.9,
                 alpha_11: float | None = None, alpha_12: float | None = None,
                 alpha_22: float | None = None, kernel: Any = 1.0,
                 forcing: str = "same_diffusion", diffusion: float = 1.0,
                 density: float = 1.0, method: str = "sonine") -> MixtureMoments:
    """:func:`solve_mixture` of :func:`binary_mixture`: a sweep function over scalars.

    Parameters
    ----------
    mass_ratio, fraction, alpha, alpha_11, alpha_12, alpha_22, kernel, forcing, diffusion
        As in :func:`binary_mixture`.
    density, method
        As in :func:`solve_mixture`.

    Returns
    -------
    MixtureMoments

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> ds = kf.sweep(solve_binary, {"mass_ratio": [1.0, 4.0], "alpha": [0.5, 0.9]},
    ...               method="gaussian", executor="serial")
    >>> ds.T_ratio.dims, round(float(ds.T_ratio.sel(mass_ratio=1.0, alpha=0.5)), 12)
    (('mass_ratio', 'alpha'), 1.0)
    """
    mix = binary_mixture(mass_ratio, fraction=fraction, alpha=alpha, alpha_11=alpha_11,
                         alpha_12=alpha_12, alpha_22=alpha_22, kernel=kernel, forcing=forcing,
                         diffusion=diffusion)
    return solve_mixture(mix, density=density, method=method)
