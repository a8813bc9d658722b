"""Generator of the stored cooling states (the data files of :mod:`.cooling_stored`).

Each table is recomputed by the path it replaces and written as JSON (floats round-trip
exactly; the sampled values rounded to 8 significant digits as stored):

- ``gamma2``: the gamma = 2 anchor at each of ``count`` inelasticities from ``eps_max``
  down to ``eps_min`` (geometric), by the continuation the anchored start replaces (at
  alpha <= 0.5 the pseudo-transient iteration from a Gaussian;
  :func:`~.cooling_alpha.alpha_chain` from alpha 0.5 on the default mesh,
  :func:`~.cooling_quasi.quasi_elastic_chain` below eps 0.01), reached through
  ``cooling_state(..., vertices=...)`` (an explicit mesh skips the anchored start),
  sampled by :func:`~.cooling_gamma2.anchor_samples`;
- ``seeds``: the hard-rod link states at :data:`~.cooling_seeds.SEED_EPS`, solved
  from the coarse state at eps = 0.1 (:func:`seed_state`).

::

    python -m kinetic_fem.solvers.fem.cooling_generate gamma2 [--count 36] [--points 65]
        [--eps-max 1] [--eps-min 5e-4] [--out FILE]
    python -m kinetic_fem.solvers.fem.cooling_generate seeds [--out FILE]

Without ``--out`` the file in the package is rewritten.
"""

from __future__ import annotations

import argparse
import json
import logging
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ...model import CoolingProblem
from .cooling import cooling_state
from .cooling_alpha import DIRECT_EPS, quasi_seed_vertices
from .cooling_gamma2 import anchor_samples
from .cooling_hump import HUMP_FAST_LINK, HumpStepOptions
from .cooling_links import HUMP_EPS, HUMP_STEP_TOL, chain_state
from .cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices
from .cooling_newton import CoolingState
from .cooling_seeds import SEED_EPS
from .regimes import link_start

__all__ = ["anchor_state", "gamma2_table", "seed_state", "seed_nodes", "seeds_table",
           "to_json", "main"]

logger = logging.getLogger(__name__)

GAMMA2_DESCRIPTION = (
    "Anchor states of the gamma = 2 cooling state (kinetic_fem.solvers.fem.cooling_gamma2):"
    " per anchor the inelasticity eps, zeta/eps, the end c_end of the sampled range and "
    "eps ln f at `points` equally spaced c in [0, c_end] (8 significant digits).")
SEEDS_DESCRIPTION = (
    "Stored starts of the near-elastic hard-rod cooling state "
    "(kinetic_fem.solvers.fem.cooling_seeds): per inelasticity eps the cooling rate zeta "
    "of a converged link state and ln f at its vertices c >= the last vertex at or below "
    "1/2 (8 significant digits).")


def _rounded(values: Sequence[float] | np.ndarray, digits: int) -> list[float]:
    return [float(f"{v:.{digits - 1}e}") for v in values]


def anchor_state(eps: float) -> CoolingState:
    """The gamma = 2 state at ``eps`` by the continuation (explicit vertices: no anchors).

    Parameters
    ----------
    eps : float
        Inelasticity.

    Returns
    -------
    CoolingState
    """
    problem = CoolingProblem.from_parameters(1.0 - eps, kernel=2.0)
    if eps < DIRECT_EPS:
        verts = quasi_seed_vertices(2.0, 2)
    else:
        verts = hcs_vertices(hcs_cutoff(problem), hcs_spacing(problem), gamma=2.0,
                             bulk=hcs_bulk(eps))
    return cooling_state(problem, vertices=verts)


def gamma2_table(eps_values: Sequence[float], points: int = 65) -> dict[str, Any]:
    """The content of ``gamma2_anchors.json`` for the anchors at ``eps_values``.

    Parameters
    ----------
    eps_values : sequence of float
        Inelasticities, decreasing.
    points : int
        Samples per anchor.

    Returns
    -------
    dict
    """
    anchors = []
    for eps in eps_values:
        state = anchor_state(eps)
        zeta_ratio, c_end, values = anchor_samples(state, eps, points)
        anchors.append({"eps": float(eps), "zeta_ratio": float(zeta_ratio),
                        "c_end": float(c_end), "eps_log_f": _rounded(values, 8)})
        logger.info("gamma 2 anchor eps %.6g: zeta/eps %.12f, %d dofs", eps, zeta_ratio,
                    state.u.size)
    return {"description": GAMMA2_DESCRIPTION,
            "generator": "python -m kinetic_fem.solvers.fem.cooling_generate gamma2",
            "points": points, "anchors": anchors}


def seed_state(eps: float) -> CoolingState:
    """The link state a seed stores, solved from the coarse state at eps = 0.1.

    Parameters
    ----------
    eps : float
        Inelasticity (at least
        :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_COARSE_EPS`).

    Returns
    -------
    CoolingState
        P2 at :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_FAST_LINK` hump widths,
        cut off where its start fell 45 decades, Newton tolerance
        :data:`~kinetic_fem.solvers.fem.cooling_links.HUMP_STEP_TOL`.
    """
    final = HumpStepOptions(resolution=HUMP_FAST_LINK, order=2, tol=HUMP_STEP_TOL,
                            max_iter=100)
    return chain_state(1.0 - eps, link_start(2, None), HUMP_EPS, final, order=2)


def seed_nodes(state: CoolingState) -> tuple[np.ndarray, np.ndarray]:
    """The nodes a seed stores: the vertices from the last at or below 1/2, and ln f.

    Parameters
    ----------
    state : CoolingState
        A link state (:func:`seed_state`).

    Returns
    -------
    c, log_f : ndarray
    """
    verts = state.disc.vertices
    c = verts[verts >= verts[verts <= 0.5].max()]
    return c, state.log_f(c)


def seeds_table(eps_values: Sequence[float] = SEED_EPS) -> dict[str, Any]:
    """The content of ``hard_rod_seeds.json``.

    Parameters
    ----------
    eps_values : sequence of float
        Inelasticities of the seeds.

    Returns
    -------
    dict
    """
    seeds = []
    for eps in eps_values:
        state = seed_state(eps)
        c, log_f = seed_nodes(state)
        seeds.append({"eps": float(eps), "zeta": float(state.zeta), "c": _rounded(c, 8),
                      "log_f": _rounded(log_f, 8)})
    return {"description": SEEDS_DESCRIPTION,
            "generator": "python -m kinetic_fem.solvers.fem.cooling_generate seeds",
            "seeds": seeds}


def to_json(table: dict[str, Any]) -> str:
    """The text of a data file: one key per line, each array on one line.

    Parameters
    ----------
    table : dict
        :func:`gamma2_table` or :func:`seeds_table`.

    Returns
    -------
    str
    """
    def block(value: Any, indent: str) -> str:
        if isinstance(value, dict):
            items = [f'{indent} {json.dumps(k)}: {block(v, indent + " ")}'
                     for k, v in value.items()]
            return "{\n" + ",\n".join(items) + "\n" + indent + "}"
        if isinstance(value, list) and value and isinstance(value[0], dict):
            items = [indent + " " + block(v, indent + " ") for v in value]
            return "[\n" + ",\n".join(items) + "\n" + indent + "]"
        return json.dumps(value)

    return block(table, "") + "\n"


def main(argv: Sequence[str] | None = None) -> None:
    """Command line: regenerate one table (module notes).

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``): ``gamma2`` or ``seeds``, and for
        ``gamma2`` ``--count``, ``--points``, ``--eps-max``, ``--eps-min``; ``--out FILE``.
    """
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("table", choices=("gamma2", "seeds"))
    parser.add_argument("--count", type=int, default=36)
    parser.add_argument("--points", type=int, default=65)
    parser.add_argument("--eps-max", type=float, default=1.0)
    parser.add_argument("--eps-min", type=float, default=5e-4)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.table == "gamma2":
        eps_values = [float(e) for e in np.geomspace(args.eps_max, args.eps_min, args.count)]
        table = gamma2_table(eps_values, args.points)
        name = "gamma2_anchors.json"
    else:
        table = seeds_table()
        name = "hard_rod_seeds.json"
    out = args.out or Path(str(resources.files(__package__).joinpath("data").joinpath(name)))
    out.write_text(to_json(table), encoding="utf-8")
    logger.info("wrote %s", out)


if __name__ == "__main__":  # pragma: no cover
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    main()
