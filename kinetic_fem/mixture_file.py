"""A mixture from a TOML file: :func:`read_mixture` (used by ``kinetic-fem mixture``).

The file holds a ``[mixture]`` table::

    [mixture]
    masses = [1.0, 4.0]
    fractions = [0.5, 0.5]
    alpha = 0.9                 # or a symmetric table [[0.9, 0.8], [0.8, 0.7]]
    # a restitution law in place of a number (here or in the table; particles, FEM heated):
    # "viscoelastic:DELTA", or "threshold:ALPHA:SPEED" (elastic below |g| = SPEED)
    kernel = 1.0                # gamma of |g|^gamma
    forcing = "same_diffusion"  # "same_power", "cooling" or "baths"
    diffusion = 1.0             # D (white noise)
    # forcing = "baths": one bath per species
    # baths = [{friction = 1.0, diffusion = 1.0}, {friction = 1.0, diffusion = 0.25}]
    density = 1.0

Every error names the file and the key (``[mixture] masses[1]: ...``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .model.mixture import FORCING_CONVENTIONS, Mixture
from .model.restitution import ThresholdRestitution, ViscoelasticRestitution
from .model.thermostat import FokkerPlanckBath
from .model.validation import check_positive

__all__ = ["read_mixture", "mixture_from_table", "MIXTURE_KEYS"]

#: the keys of a ``[mixture]`` table
MIXTURE_KEYS = ("masses", "fractions", "alpha", "kernel", "forcing", "diffusion", "baths",
                "density")
_FORCINGS = (*FORCING_CONVENTIONS, "cooling", "baths")


def mixture_from_table(table: dict[str, Any], where: str = "[mixture]"
                       ) -> tuple[Mixture, float]:
    """The mixture and the density of a ``[mixture]`` table (a dict).

    Parameters
    ----------
    table : dict
        The keys of :data:`MIXTURE_KEYS` (``masses`` and ``fractions`` required).
    where : str
        Prefix of the error messages (the file and table).

    Returns
    -------
    mixture : Mixture
    density : float

    Raises
    ------
    ValueError
        Naming the key: unknown or missing keys, and every invalid value (the message
        of :class:`~kinetic_fem.Mixture` behind the key).

    Examples
    --------
    >>> mix, n = mixture_from_table({"masses": [1, 2], "fractions": [0.5, 0.5]})
    >>> mix.masses, mix.heated, n
    ((1.0, 2.0), True, 1.0)
    """
    if not isinstance(table, dict):
        raise ValueError(f"{where} must be a table with keys {list(MIXTURE_KEYS)}")
    unknown = sorted(set(table) - set(MIXTURE_KEYS))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {list(MIXTURE_KEYS)}")
    missing = [key for key in ("masses", "fractions") if key not in table]
    if missing:
        raise ValueError(f"{where}: missing key(s) {missing} (one value per species)")
    forcing = table.get("forcing", "same_diffusion")
    if forcing not in _FORCINGS:
        raise ValueError(f"{where} forcing: must be one of {list(_FORCINGS)}, got {forcing!r}")
    if ("baths" in table) != (forcing == "baths"):
        raise ValueError(f"{where} baths: give baths = [...] exactly with forcing = 'baths'")
    if forcing in ("cooling", "baths") and "diffusion" in table:
        raise ValueError(f"{where} diffusion: not used with forcing = {forcing!r}")
    try:
        density = check_positive("density", table.get("density", 1.0))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where} density: {exc}") from None
    try:
        alpha = _laws(table.get("alpha", 0.9))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where} alpha: {exc}") from None
    args = {"alpha": alpha, "kernel": table.get("kernel", 1.0)}
    key = "masses"
    try:
        if forcing in FORCING_CONVENTIONS:
            key = "diffusion"
            diffusion = check_positive("diffusion", table.get("diffusion", 1.0))
            key = ""
            mix = Mixture.white_noise(table["masses"], table["fractions"], convention=forcing,
                                      diffusion=diffusion, **args)
        else:
            thermostats = None
            if forcing == "baths":
                key = "baths"
                thermostats = tuple(_bath(i, b) for i, b in enumerate(table["baths"]))
            key = ""
            mix = Mixture(table["masses"], table["fractions"], thermostats=thermostats, **args)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where} {key}: {exc}" if key else f"{where}: {exc}") from None
    return mix, density


def _laws(alpha: Any) -> Any:
    """``alpha`` with every ``"viscoelastic:DELTA"`` or ``"threshold:ALPHA:SPEED"``
    string (alone or in a table) replaced by its restitution law."""
    if isinstance(alpha, list):
        return [_laws(entry) for entry in alpha]
    if not isinstance(alpha, str):
        return alpha
    kind, *values = [part.strip() for part in alpha.split(":")]
    try:
        numbers = [float(value) for value in values]
    except ValueError:
        numbers = []
    if kind == "viscoelastic" and len(numbers) == 1:
        return ViscoelasticRestitution(numbers[0])
    if kind == "threshold" and len(numbers) == 2:
        return ThresholdRestitution(numbers[0], numbers[1])
    raise ValueError(f"a restitution coefficient, \"viscoelastic:DELTA\" or "
                     f"\"threshold:ALPHA:SPEED\", got {alpha!r}")


def _bath(i: int, entry: Any) -> FokkerPlanckBath:
    if not isinstance(entry, dict) or set(entry) != {"friction", "diffusion"}:
        raise ValueError(f"baths[{i}] must be {{friction = ..., diffusion = ...}}, got "
                         f"{entry!r}")
    return FokkerPlanckBath(entry["friction"], entry["diffusion"])


def read_mixture(path: str | Path) -> tuple[Mixture, float]:
    """The mixture and density of the ``[mixture]`` table of a TOML file.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    mixture : Mixture
    density : float

    Raises
    ------
    ValueError
        An unreadable file, invalid TOML, no ``[mixture]`` table, or a bad key (named).
    """
    from .files import read_toml

    config = read_toml(path, f"the mixture file {str(path)!r}")
    if set(config) != {"mixture"}:
        raise ValueError(f"{str(path)!r} must hold exactly one [mixture] table, got tables "
                         f"{sorted(config)}")
    return mixture_from_table(config["mixture"], where=f"{str(path)!r} [mixture]")
