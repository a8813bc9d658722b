"""The ``kinetic-fem`` command.

Sub-commands:

``reproduce``
    Regenerate the figures of Barrat et al. (2002) as PNG and check its claims,
    writing ``claims.md`` and ``claims.csv`` (measured value beside the paper's)
    into an output folder.  Items come from the registry
    :mod:`kinetic_fem.reproduce`, filled by every installed capability.
``solve-heated``, ``solve-cooling``
    One deterministic solve with a registered method and the model options (kernel,
    friction, restitution law); print T, a2 (zeta); optionally save the distribution
    (``.npz``, ``.vtu`` or ``.xdmf``).
``dsmc``, ``md``
    One particle simulation (N, run length, seed, checkpoint and resume, progress),
    a one-line summary and an optional saved distribution.
``sweep``
    A parameter sweep (:func:`kinetic_fem.sweep.sweep`) from options or a TOML file,
    persisted point by point, on local processes or a dask scheduler.

Also runs as ``python -m kinetic_fem``.  A mistyped option prints the usage of the
sub-command it was typed in and that sub-command's valid options.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import pkgutil
import sys
from typing import Sequence

from . import cmd_particles, cmd_reproduce, cmd_solve, cmd_sweep
from .cmd_reproduce import select_items
from .parser import CommandParser, setup_logging

__all__ = ["main", "build_parser", "select_items"]

logger = logging.getLogger(__name__)

_DESCRIPTION = """\
kinetic-fem computes velocity distributions P(v) of the one-dimensional inelastic
(granular) gas: rods colliding with restitution coefficient 0 <= alpha < 1 at
density n, either heated by white noise of strength D (steady state) or freely
cooling.  Deterministic solvers of the Boltzmann equation (finite elements, the
paper's finite-difference iteration, Sonine expansion, quasi-elastic limits) and
particle simulations (DSMC, event-driven MD) all return the same result type, and
reproduce the figures and claims of Barrat et al., J. Phys. A 35 (2002) 463.
"""

_EPILOG = """\
examples:
  kinetic-fem reproduce --quick --out reproduce-out   every figure, CI-sized (minutes)
  kinetic-fem reproduce --list                        what can be reproduced
  kinetic-fem solve-heated 0.9 --method fem           T and a2 of the heated gas at alpha=0.9
  kinetic-fem dsmc 0.9 -N 10000 --seed 1              a DSMC run, one-line summary
  kinetic-fem sweep --alpha 0.3,0.6,0.9 --store s     a2 against alpha, resumable
  kinetic-fem <command> --help                        options of one command
"""

_RUN = {"reproduce": cmd_reproduce.run, "solve-heated": cmd_solve.run_heated,
        "solve-cooling": cmd_solve.run_cooling, "dsmc": cmd_particles.run,
        "md": cmd_particles.run, "sweep": cmd_sweep.run}


def _import_solvers() -> None:
    """Import every public module of ``kinetic_fem`` so that all solvers register."""
    import kinetic_fem

    for mod in pkgutil.iter_modules(kinetic_fem.__path__):
        if not mod.name.startswith("_") and mod.name not in {"cli", "figures", "plot"}:
            try:
                importlib.import_module(f"kinetic_fem.{mod.name}")
            except ImportError as exc:  # an optional dependency is missing
                logger.warning("kinetic_fem.%s not loaded: %s", mod.name, exc)


def build_parser() -> CommandParser:
    """The argument parser of ``kinetic-fem`` (exposed for the docs and tests).

    ``parser.commands`` maps each sub-command to its own parser.
    """
    _import_solvers()
    parser = CommandParser(prog="kinetic-fem", description=_DESCRIPTION, epilog=_EPILOG,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                parser_class=CommandParser)
    commands = [cmd_reproduce.add_parser(sub), *cmd_solve.add_parsers(sub),
                *cmd_particles.add_parsers(sub), cmd_sweep.add_parser(sub)]
    parser.commands = {p.prog.split()[-1]: p for p in commands}  # type: ignore[attr-defined]
    return parser


def _version() -> str:
    from .. import __version__

    return f"kinetic-fem {__version__}"


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``kinetic-fem``; returns the exit status.

    Bad input (an unknown item, an invalid alpha, a mistyped option ...) prints one
    line ``kinetic-fem: error: ...`` (for options: the sub-command's usage and valid
    options) and exits with status 2, without a traceback; a solver that fails on valid
    input prints ``kinetic-fem: solver failed: ...`` and exits with status 1.

    Parameters
    ----------
    argv : sequence of str, optional
        Command-line arguments without the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 on success, 1 if a solver failed, 2 for bad input.
    """
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:
        parser.commands.get(args.command, parser).reject_unknown(extra)  # type: ignore[attr-defined]
    if args.command is None:
        parser.print_help()
        return 0
    setup_logging(args.quiet)
    try:
        return _RUN[args.command](args)
    except (ValueError, TypeError) as exc:
        parser.exit(2, f"kinetic-fem: error: {exc}\n")
    except OSError as exc:  # an output path that cannot be written, a missing file
        parser.exit(2, f"kinetic-fem: error: {exc}\n")
    except (RuntimeError, MemoryError) as exc:  # a solver that failed on valid input
        parser.exit(1, f"kinetic-fem: solver failed: {exc}\n")
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
