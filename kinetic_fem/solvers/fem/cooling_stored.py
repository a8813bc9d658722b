"""Stored states of the FEM cooling solver: the data files and their reader (issue 26).

Two tables of solver output start Newton's method where the continuation they replace
is slow; they are data files in ``kinetic_fem/solvers/fem/data/`` (JSON: every float
round-trips exactly), written by their generator
``python -m kinetic_fem.solvers.fem.cooling_generate`` (:mod:`.cooling_generate`):

- ``gamma2_anchors.json``: 36 anchor states of the gamma = 2 cooling state at
  inelasticities from 1 to 5e-4, each :math:`\\zeta/\\varepsilon`, the end of its sampled
  range and :math:`\\varepsilon\\ln f` at 65 velocities (2,448 numbers,
  :mod:`.cooling_gamma2`);
- ``hard_rod_seeds.json``: three near-elastic hard-rod link states (eps 0.04, 0.01,
  0.0025), each :math:`\\zeta` and :math:`\\ln f` at its vertices from :math:`c = 1/2`
  (717 numbers, :mod:`.cooling_seeds`).

They decide the start (and, for gamma = 2, the mesh) but the state returned solves the
discrete equations to the Newton tolerance; ``CoolingOptions(stored=False)``
(:mod:`.regimes`) solves without them.
"""

from __future__ import annotations

import functools
import json
from importlib import resources
from typing import Any

__all__ = ["DATA_FILES", "read_data", "gamma2_anchors", "hard_rod_seeds"]

DATA_FILES = ("gamma2_anchors.json", "hard_rod_seeds.json")
"""The stored tables (in ``kinetic_fem/solvers/fem/data/``)."""

Anchor = tuple[float, float, float, tuple[float, ...]]
"""One gamma = 2 anchor: ``(eps, zeta/eps, c_end, eps ln f at equally spaced c)``."""


def read_data(name: str) -> dict[str, Any]:
    """The content of one stored table.

    Parameters
    ----------
    name : str
        One of :data:`DATA_FILES`.

    Returns
    -------
    dict
        The JSON object.

    Raises
    ------
    ValueError
        For a name not in :data:`DATA_FILES`.
    """
    if name not in DATA_FILES:
        raise ValueError(f"name must be one of {DATA_FILES}, got {name!r}")
    text = resources.files(__package__).joinpath("data").joinpath(name).read_text(encoding="utf-8")
    return json.loads(text)


@functools.lru_cache(maxsize=None)
def gamma2_anchors() -> tuple[int, tuple[Anchor, ...]]:
    """The gamma = 2 anchors (read once: the file is the only input).

    Returns
    -------
    points : int
        Samples per anchor.
    anchors : tuple
        ``(eps, zeta/eps, c_end, eps ln f)`` per anchor, eps decreasing.

    Examples
    --------
    >>> points, anchors = gamma2_anchors()
    >>> points, len(anchors), anchors[0][0], anchors[-1][0]
    (65, 36, 1.0, 0.0005)
    """
    data = read_data("gamma2_anchors.json")
    anchors = tuple((float(a["eps"]), float(a["zeta_ratio"]), float(a["c_end"]),
                     tuple(float(v) for v in a["eps_log_f"])) for a in data["anchors"])
    return int(data["points"]), anchors


@functools.lru_cache(maxsize=None)
def hard_rod_seeds() -> dict[float, tuple[float, tuple[float, ...], tuple[float, ...]]]:
    """The hard-rod seeds (read once: the file is the only input).

    Returns
    -------
    dict
        ``eps -> (zeta, c, ln f)``.

    Examples
    --------
    >>> sorted(hard_rod_seeds())
    [0.0025, 0.01, 0.04]
    """
    data = read_data("hard_rod_seeds.json")
    return {float(s["eps"]): (float(s["zeta"]), tuple(float(v) for v in s["c"]),
                              tuple(float(v) for v in s["log_f"])) for s in data["seeds"]}
