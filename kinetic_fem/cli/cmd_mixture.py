"""``kinetic-fem mixture FILE.toml``: the state of a granular mixture read from a TOML file.

The file's ``[mixture]`` table (:mod:`kinetic_fem.mixture_file`) gives the masses,
fractions, restitution, kernel and forcing; ``--method`` one of the deterministic
mixture methods (:data:`kinetic_fem.mixture_solve.MIXTURE_STATE_METHODS`) or a particle
simulation (``dsmc``, ``md``: imported inside the command only).  Prints the species
temperatures, the ratio :math:`T_1/T_2`, the :math:`a_{2,s}` and, in free cooling,
:math:`\\zeta`.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from . import COMMANDS

__all__ = ["add_parser", "run", "interrupt_note", "PARTICLE_METHODS"]

#: methods of the command that are particle simulations
PARTICLE_METHODS = ("dsmc", "md")

EPILOG = """\
examples:
  kinetic-fem mixture mix.toml                          first-order Sonine theory
  kinetic-fem mixture mix.toml --method dsmc -N 4000 --collisions 300 --seed 1

mix.toml:
  [mixture]
  masses = [1.0, 4.0]
  fractions = [0.5, 0.5]
  alpha = 0.8                 # or [[0.9, 0.8], [0.8, 0.7]]
  forcing = "same_power"      # "same_diffusion", "cooling" or "baths"
"""


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """The ``mixture`` sub-command, added to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``kinetic-fem`` parser.

    Returns
    -------
    argparse.ArgumentParser
    """
    from ..mixture_solve import MIXTURE_STATE_METHODS

    p = sub.add_parser("mixture", help=COMMANDS["mixture"][1], epilog=EPILOG,
                       description=__doc__.splitlines()[0],
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    methods = [*MIXTURE_STATE_METHODS, *PARTICLE_METHODS]
    p.add_argument("file", type=Path, metavar="FILE.toml", help="the [mixture] table")
    p.add_argument("--method", default="sonine", choices=methods,
                   help="deterministic theory or particle simulation (default sonine)")
    p.add_argument("-N", "--particles", type=int, default=2000,
                   help="rods of a particle run (default 2000)")
    p.add_argument("--collisions", type=float, default=200.0,
                   help="collisions per rod of a particle run (default 200)")
    p.add_argument("--seed", type=int, default=None, help="seed of a particle run")
    p.add_argument("--quiet", action="store_true", help="no log messages")
    return p


def interrupt_note(args: argparse.Namespace) -> str:
    """What Ctrl-C leaves behind: nothing (a mixture run writes no files).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    str
    """
    return "nothing was written"


def run(args: argparse.Namespace) -> int:
    """Read the mixture, compute its state, print one line per species.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``file``, ``method`` and the run options).

    Returns
    -------
    int
        The exit status.
    """
    from ..mixture_file import read_mixture
    from ..mixture_solve import solve_mixture

    mixture, density = read_mixture(args.file)
    result: Any
    if args.method in PARTICLE_METHODS:
        if args.method == "dsmc":
            from particles.dsmc_mixture import simulate_mixture
        else:
            from particles.md_mixture import simulate_mixture  # type: ignore[assignment]
        result = simulate_mixture(mixture, args.particles, density=density, seed=args.seed,
                                  collisions_per_particle=args.collisions)
        errors, ratio_error = result.temperature_errors, result.temperature_ratio_error()
    else:
        result = solve_mixture(mixture, density=density, method=args.method)
        errors, ratio_error = None, None
    print(f"mixture {args.file} ({args.method}): masses {list(mixture.masses)}, fractions "
          f"{list(mixture.fractions)}, {'heated' if mixture.heated else 'free cooling'}")
    for s, (t, a2) in enumerate(zip(result.temperatures, result.a2, strict=True)):
        err = "" if errors is None else f" +- {errors[s]:.3g}"
        print(f"  species {s + 1}: T = {t:.8g}{err}, a2 = {a2:.6g}")
    err = "" if ratio_error is None else f" +- {ratio_error:.3g}"
    print(f"  T_1/T_2 = {result.temperature_ratio():.8g}{err}, T = {result.temperature:.8g}")
    if result.zeta is not None:
        print(f"  zeta = {result.zeta:.8g}")
    return 0
