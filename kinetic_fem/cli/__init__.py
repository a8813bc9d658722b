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
``mixture``
    A granular mixture read from a TOML file: species temperatures, their ratio, the
    kurtosis of each species (Sonine, Gaussian, exact Maxwell, DSMC or MD).
``sweep``
    A parameter sweep (:func:`kinetic_fem.sweep.sweep`) from options or a TOML file,
    persisted point by point, on local processes or a dask scheduler.

Also runs as ``python -m kinetic_fem``.  A mistyped option prints the usage of the
sub-command it was typed in and that sub-command's valid options.  Only the module of
the sub-command being run is imported (:data:`COMMANDS`), so ``kinetic-fem --help``
loads no solver.  Ctrl-C ends any command with one line saying what was kept and how
to resume (each command module's ``interrupt_note``), exit status 130.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from typing import Any, Sequence

__all__ = ["main", "build_parser", "select_items", "COMMANDS", "INTERRUPTED"]

logger = logging.getLogger(__name__)

INTERRUPTED = 130
"""Exit status after Ctrl-C (128 + SIGINT, as a shell reports it)."""

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
  kinetic-fem dsmc 0.9 -N 10000 --collisions 400 --seed 1   a DSMC run, one-line summary
  kinetic-fem sweep --alpha 0.3,0.6,0.9 --store s     a2 against alpha, resumable
  kinetic-fem <command> --help                        options of one command
"""

COMMANDS = {
    "reproduce": ("cmd_reproduce", "regenerate the paper's figures and check its claims"),
    "solve-heated": ("cmd_solve", "steady state of the heated gas at one alpha"),
    "solve-cooling": ("cmd_solve", "homogeneous cooling state (free cooling) at one alpha"),
    "dsmc": ("cmd_particles", "direct simulation monte carlo of the homogeneous boltzmann "
                              "equation (velocities only)"),
    "md": ("cmd_particles", "event-driven molecular dynamics of inelastic rods on a ring"),
    "sweep": ("cmd_sweep", "a parameter sweep (grid of alpha, kernel, ...) persisted point "
                           "by point"),
    "mixture": ("cmd_mixture", "a granular mixture from a TOML file: species temperatures "
                               "and their ratio"),
}
"""Sub-command -> (module of ``kinetic_fem.cli`` that defines and runs it, one-line help).

Only the module of the command being run is imported, so ``kinetic-fem --help`` and a
mistyped command answer without loading the solvers."""

_ADD = {"cmd_reproduce": "add_parser", "cmd_solve": "add_parsers",
        "cmd_particles": "add_parsers", "cmd_sweep": "add_parser",
        "cmd_mixture": "add_parser"}
_RUN = {"reproduce": "run", "solve-heated": "run_heated", "solve-cooling": "run_cooling",
        "dsmc": "run", "md": "run", "sweep": "run", "mixture": "run"}


def _module(name: str) -> Any:
    return importlib.import_module(f"{__name__}.{name}")


def select_items(only: list[str] | None) -> list[str]:
    """Item keys for ``reproduce --only`` (:func:`kinetic_fem.cli.cmd_reproduce.select_items`).

    Parameters
    ----------
    only : list of str or None
        Item keys and claim labels; None: every item.

    Returns
    -------
    list of str
    """
    return _module("cmd_reproduce").select_items(only)  # type: ignore[no-any-return]


def build_parser(command: str | None = "all") -> Any:
    """The argument parser of ``kinetic-fem`` (exposed for the docs and tests).

    ``parser.commands`` maps each fully built sub-command to its own parser.

    Parameters
    ----------
    command : str or None
        Build this sub-command's parser in full (``"all"``, the default: every one);
        the others get their name and one-line help only, so that ``kinetic-fem
        --help`` (``command=None``) imports no solver.

    Returns
    -------
    CommandParser
    """
    from .parser import CommandParser

    parser = CommandParser(prog="kinetic-fem", description=_DESCRIPTION, epilog=_EPILOG,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                parser_class=CommandParser)
    commands: list[argparse.ArgumentParser] = []
    for name, (module, text) in COMMANDS.items():
        if any(p.prog.split()[-1] == name for p in commands):
            continue  # added with its sibling (solve-heated/solve-cooling, dsmc/md)
        if command == "all" or (command in COMMANDS and COMMANDS[command][0] == module):
            added = getattr(_module(module), _ADD[module])(sub)
            commands += added if isinstance(added, list) else [added]
        else:
            sub.add_parser(name, help=text)
    parser.commands = {p.prog.split()[-1]: p for p in commands}  # type: ignore[attr-defined]
    return parser


def _command_of(argv: Sequence[str]) -> str | None:
    """The sub-command named in ``argv`` (its first word that is not an option), if any."""
    word = next((a for a in argv if not a.startswith("-")), None)
    return word if word in COMMANDS else None


def _version() -> str:
    from .. import __version__

    return f"kinetic-fem {__version__}"


def _interrupted(exc: BaseException) -> bool:
    """A Ctrl-C, also when it surfaced through a numba kernel as a SystemError."""
    while exc is not None:
        if isinstance(exc, KeyboardInterrupt):
            return True
        exc = exc.__cause__ or exc.__context__  # type: ignore[assignment]
    return False


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``kinetic-fem``; returns the exit status.

    Bad input (an unknown item, an invalid alpha, a mistyped option ...) prints one
    line ``kinetic-fem: error: ...`` (for options: the sub-command's usage and valid
    options) and exits with status 2, without a traceback; a solver that fails on valid
    input prints ``kinetic-fem: solver failed: ...`` and exits with status 1; Ctrl-C
    prints ``kinetic-fem: interrupted: ...`` (what was kept, how to resume) and exits
    with status 130.

    Parameters
    ----------
    argv : sequence of str, optional
        Command-line arguments without the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 on success, 1 if a solver failed, 2 for bad input, 130 after
        Ctrl-C.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    command = _command_of(argv)
    args: argparse.Namespace | None = None
    try:
        parser = build_parser(command)
        args, extra = parser.parse_known_args(argv)
        if extra:
            parser.commands.get(args.command, parser).reject_unknown(extra)
        if args.command is None:
            parser.print_help()
            return 0
        from .parser import setup_logging

        setup_logging(args.quiet)
        module = _module(COMMANDS[args.command][0])
        return int(getattr(module, _RUN[args.command])(args))
    except (ValueError, TypeError) as exc:
        parser.exit(2, f"kinetic-fem: error: {exc}\n")
    except OSError as exc:  # an output path that cannot be written, a missing file
        parser.exit(2, f"kinetic-fem: error: {exc}\n")
    except (RuntimeError, MemoryError) as exc:  # a solver that failed on valid input
        parser.exit(1, f"kinetic-fem: solver failed: {exc}\n")
    except (KeyboardInterrupt, SystemError) as exc:
        if not _interrupted(exc):
            raise
        note = "nothing was kept; run the command again"
        if args is not None and args.command is not None:
            module = _module(COMMANDS[args.command][0])
            note = getattr(module, "interrupt_note", lambda a: note)(args)
        sys.stderr.write(f"\nkinetic-fem: interrupted: {note}\n")
        return INTERRUPTED
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
