"""``kinetic-fem solve-heated`` and ``solve-cooling``: one deterministic solve."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import load_solvers
from ..distribution import VelocityDistribution
from ..solve import COOLING_SOLVERS, HEATED_SOLVERS, solve_cooling, solve_heated
from . import COMMANDS
from .parser import (
    add_model_arguments,
    api_default,
    check_options,
    check_out,
    key_value,
    restitution_of,
    save,
)

__all__ = ["add_parsers", "run_heated", "run_cooling", "interrupt_note"]

HEATED_EPILOG = """\
examples:
  kinetic-fem solve-heated 0.9 --method fem --out a09.vtu
  kinetic-fem solve-heated 0.5 --method fd -o cutoff=20.0
  kinetic-fem solve-heated 0.8 --kernel 0 --friction 0.5      Maxwell model, Fokker-Planck bath
  kinetic-fem solve-heated 0.7 --restitution threshold:0.1    elastic below |g| = 0.1
  kinetic-fem solve-heated --restitution viscoelastic:0.05    alpha(g) of viscoelastic grains
"""

COOLING_EPILOG = """\
examples:
  kinetic-fem solve-cooling 0.9 --out hcs09.vtu
  kinetic-fem solve-cooling 0.8 --method spectral -o order=4
  kinetic-fem solve-cooling 0.8 --kernel 0 --method fem
"""


def add_parsers(sub: argparse._SubParsersAction) -> list[argparse.ArgumentParser]:
    """The ``solve-heated`` and ``solve-cooling`` sub-commands, added to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``kinetic-fem`` parser.

    Returns
    -------
    list of argparse.ArgumentParser
    """
    load_solvers()  # the registered methods are the --method choices
    heated = sub.add_parser(
        "solve-heated", help=COMMANDS["solve-heated"][1],
        description="Solve the heated steady state and print T and a2.",
        epilog=HEATED_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _arguments(heated, HEATED_SOLVERS, api_default(solve_heated, "method"), heated=True,
               example="spacing=0.05")
    cooling = sub.add_parser(
        "solve-cooling", help=COMMANDS["solve-cooling"][1],
        description="Solve the scaled homogeneous cooling state and print a2 and the "
                    "cooling rate zeta (dT/dt = -2 zeta n T^(1+gamma/2)).",
        epilog=COOLING_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _arguments(cooling, COOLING_SOLVERS, api_default(solve_cooling, "method"), heated=False,
               example="spacing=0.01")
    return [heated, cooling]


def _arguments(parser: argparse.ArgumentParser, table: dict, method: str, *, heated: bool,
               example: str) -> None:
    add_model_arguments(parser, heated=heated)
    choices = sorted(table)
    parser.add_argument("--method", default=method if method in table else None,
                        choices=choices, metavar="METHOD",
                        help=f"registered solver, one of: {', '.join(choices)} "
                             "(default: %(default)s)")
    parser.add_argument("--out", type=Path, default=None, metavar="FILE",
                        help="save the distribution: .npz, .vtu or .xdmf")
    parser.add_argument("-o", "--option", dest="options", type=key_value, action="append",
                        default=[], metavar="KEY=VALUE",
                        help=f"solver option, repeatable, e.g. -o {example}; an unknown KEY "
                             "lists the method's valid options")
    parser.add_argument("--quiet", action="store_true",
                        help="no log messages and no progress line (otherwise a solve still "
                             "running after 2 s shows its name and a clock)")


def interrupt_note(args: argparse.Namespace) -> str:
    """What a Ctrl-C kept: nothing (one solve); run the command again.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    str
    """
    return "nothing was kept (a single solve); run the command again"


def _report(dist: VelocityDistribution, out: Path | None) -> None:
    print(f"a2 = {dist.a2:.10g}")
    print(f"converged={dist.info.converged} iterations={dist.info.iterations} "
          f"wall_time={dist.info.wall_time:.3g} s")
    if out is not None:
        print(f"saved to {save(dist, out)}")


def _prepare(args: argparse.Namespace, table: dict, kind: str) -> dict:
    if args.method is None:
        raise ValueError(f"no {kind} solver is registered in this installation")
    check_out(args.out)
    options = dict(args.options)
    check_options(table[args.method], options, f"method {args.method!r}", exclude=("problem",))
    return options


def run_heated(args: argparse.Namespace) -> int:
    """Run ``kinetic-fem solve-heated``: solve, print T and a2, save.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status: 0, or 1 if the solver did not converge (the result is still saved).
    """
    options = _prepare(args, HEATED_SOLVERS, "heated")
    alpha = restitution_of(args)
    dist = solve_heated(alpha, density=args.density, diffusion=args.diffusion,
                        friction=args.friction, kernel=args.kernel, method=args.method,
                        progress=not args.quiet, **options)
    print(f"method={dist.method or args.method} alpha={alpha} density={args.density} "
          f"diffusion={args.diffusion} friction={args.friction} kernel={args.kernel}")
    print(f"T = {dist.temperature:.10g}")
    _report(dist, args.out)
    return 0 if dist.info.converged else 1


def run_cooling(args: argparse.Namespace) -> int:
    """Run ``kinetic-fem solve-cooling``: solve, print zeta and a2, save.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status: 0, or 1 if the solver did not converge (the result is still saved).
    """
    options = _prepare(args, COOLING_SOLVERS, "cooling")
    alpha = restitution_of(args)
    dist = solve_cooling(alpha, density=args.density, kernel=args.kernel, method=args.method,
                         progress=not args.quiet, **options)
    print(f"method={dist.method or args.method} alpha={alpha} density={args.density} "
          f"kernel={args.kernel} (scaled state, T = 1)")
    print(f"zeta = {dist.info.extra['zeta']:.10g}  (dT/dt = -2 zeta n T^(1+gamma/2))")
    _report(dist, args.out)
    return 0 if dist.info.converged else 1
