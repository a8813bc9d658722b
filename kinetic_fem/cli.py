"""The ``kinetic-fem`` command.

Sub-commands:

``reproduce``
    Regenerate the figures of Barrat et al. (2002) as PNG and check its claims,
    writing ``claims.md`` and ``claims.csv`` (measured value beside the paper's)
    into an output folder.  Items come from the registry
    :mod:`kinetic_fem.reproduce`, filled by every installed capability.
``solve-heated``
    Solve for the heated steady state at one restitution coefficient with a
    registered deterministic method; print the temperature and :math:`a_2`;
    optionally save the distribution (``.npz``, ``.vtu`` or ``.xdmf``).

Also runs as ``python -m kinetic_fem``.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import logging
import pkgutil
import sys
import time
from pathlib import Path
from typing import Sequence

from tqdm import tqdm
from tqdm.contrib.logging import logging_redirect_tqdm

from . import io, reproduce
from .distribution import VelocityDistribution
from .solve import COOLING_SOLVERS, HEATED_SOLVERS, solve_cooling, solve_heated

__all__ = ["main", "build_parser"]

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
  kinetic-fem <command> --help                        options of one command
"""

_REPRODUCE_EPILOG = """\
Items are figures (F1..F11, as in the paper) and checks (S1, ...); each reports
the claims (C1..C17) it measures.  Output: one PNG per figure, and claims.md /
claims.csv with columns claim, quantity, measured, paper, agrees, method, note.

examples:
  kinetic-fem reproduce --quick --out reproduce-out
  kinetic-fem reproduce --quick --only F2,F3 --out out --seed 7
  kinetic-fem reproduce --full --out paper-sizes      the paper's sizes (hours)
  kinetic-fem reproduce --list
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``kinetic-fem`` (exposed for the docs and tests)."""
    parser = argparse.ArgumentParser(
        prog="kinetic-fem", description=_DESCRIPTION, epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    rep = sub.add_parser(
        "reproduce", help="regenerate the paper's figures and check its claims",
        description="Regenerate the figures of Barrat et al. (2002) and check its claims.",
        epilog=_REPRODUCE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    size = rep.add_mutually_exclusive_group()
    size.add_argument("--quick", dest="quick", action="store_true", default=True,
                      help="small sizes that finish in minutes (default)")
    size.add_argument("--full", dest="quick", action="store_false",
                      help="the paper's sizes (hours)")
    rep.add_argument("--out", type=Path, default=Path("reproduce-out"), metavar="DIR",
                     help="output folder for PNGs and claims.md/.csv (default: %(default)s)")
    rep.add_argument("--only", type=_split_keys, default=None, metavar="KEYS",
                     help="comma-separated items or claims to run, e.g. F2,F3 or C5")
    rep.add_argument("--list", action="store_true",
                     help="list the registered items and the claims they check, then exit")
    rep.add_argument("--quiet", action="store_true",
                     help="no progress bar and no log messages")
    rep.add_argument("--seed", type=int, default=reproduce.Context.seed, metavar="N",
                     help="root seed of every random stream (default: %(default)s)")

    sol = sub.add_parser(
        "solve-heated", help="steady state of the heated gas at one alpha",
        description="Solve the heated steady state and print T and a2.",
        epilog="examples:\n  kinetic-fem solve-heated 0.9 --method fem --out a09.vtu\n"
               "  kinetic-fem solve-heated 0.5 --method fd -o cutoff=20.0",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _add_solve_arguments(sol, method="fem", diffusion=True, example="spacing=0.05")

    cool = sub.add_parser(
        "solve-cooling", help="homogeneous cooling state (free cooling) at one alpha",
        description="Solve the scaled homogeneous cooling state and print a2 and the "
                    "cooling rate zeta (dT/dt = -2 zeta n T^(3/2)).",
        epilog="examples:\n  kinetic-fem solve-cooling 0.9 --out hcs09.vtu\n"
               "  kinetic-fem solve-cooling 0.5 --method spectral -o order=8",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _add_solve_arguments(cool, method="fd", diffusion=False, example="spacing=0.01")
    return parser


def _add_solve_arguments(parser: argparse.ArgumentParser, *, method: str, diffusion: bool,
                         example: str) -> None:
    """The arguments shared by ``solve-heated`` and ``solve-cooling``."""
    parser.add_argument("alpha", type=float, help="restitution coefficient, 0 <= alpha < 1")
    parser.add_argument("--method", default=method,
                        help="registered solver key (default: %(default)s)")
    parser.add_argument("--density", type=float, default=1.0, metavar="N",
                        help="number density n > 0 (default: %(default)s)")
    if diffusion:
        parser.add_argument("--diffusion", type=float, default=1.0, metavar="D",
                            help="noise strength D > 0 (default: %(default)s)")
    parser.add_argument("--out", type=Path, default=None, metavar="FILE",
                        help="save the distribution: .npz, .vtu or .xdmf")
    parser.add_argument("-o", "--option", dest="options", type=_key_value, action="append",
                        default=[], metavar="KEY=VALUE",
                        help=f"solver option, repeatable, e.g. -o {example} "
                             "(see the solver's documentation)")
    parser.add_argument("--quiet", action="store_true", help="no log messages")


def _version() -> str:
    from . import __version__

    return f"kinetic-fem {__version__}"


def _key_value(text: str) -> tuple[str, object]:
    """``KEY=VALUE`` with VALUE a Python literal (number, bool, string, tuple ...)."""
    key, sep, value = text.partition("=")
    if not sep or not key.strip().isidentifier():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        parsed: object = ast.literal_eval(value)
    except (ValueError, SyntaxError):
        parsed = value  # a plain string
    return key.strip(), parsed


def _split_keys(text: str) -> list[str]:
    keys = [k.strip() for k in text.split(",") if k.strip()]
    if not keys:
        raise argparse.ArgumentTypeError(f"no item given in {text!r}; e.g. --only F2,C5")
    return keys


_PACKAGES = ("kinetic_fem", "particles")


def _setup_logging(quiet: bool) -> None:
    """Log the packages to stderr at INFO (WARNING with ``--quiet``); command only."""
    for name in _PACKAGES:
        log = logging.getLogger(name)
        for old in [h for h in log.handlers if getattr(h, "_kinetic_fem", False)]:
            log.removeHandler(old)  # a second call (tests) writes to the current stderr
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
        handler._kinetic_fem = True  # type: ignore[attr-defined]
        log.addHandler(handler)
        log.setLevel(logging.WARNING if quiet else logging.INFO)


def select_items(only: list[str] | None) -> list[str]:
    """Item keys for ``--only``: item keys as given, claims mapped to their items.

    Raises
    ------
    ValueError
        Naming the unknown keys and what is available.
    """
    items = reproduce.ITEMS
    if only is None:
        return sorted(items, key=reproduce._order)
    keys: list[str] = []
    unknown = []
    for k in only:
        if k in items:
            keys.append(k)
            continue
        matching = [key for key, item in items.items() if k in item.claims]
        if matching:
            keys.extend(matching)
        else:
            unknown.append(k)
    if unknown:
        claims = sorted({c for item in items.values() for c in item.claims})
        raise ValueError(f"unknown item or claim {unknown}; items: "
                         f"{sorted(items, key=reproduce._order)}, claims: {claims}")
    return sorted(dict.fromkeys(keys), key=reproduce._order)


def _list_items(out: list[str]) -> None:
    for key in sorted(reproduce.ITEMS, key=reproduce._order):
        item = reproduce.ITEMS[key]
        claims = f"  [{', '.join(item.claims)}]" if item.claims else ""
        out.append(f"{key:5s} {item.title}{claims}")


def _run_reproduce(args: argparse.Namespace) -> int:
    reproduce.load_plugins()
    if args.list:
        lines: list[str] = []
        _list_items(lines)
        print("\n".join(lines) if lines else "no reproduce items registered")
        return 0
    keys = select_items(args.only)
    ctx = reproduce.Context(out=args.out, quick=args.quick, progress=not args.quiet,
                            seed=args.seed)
    ctx.out.mkdir(parents=True, exist_ok=True)
    rows: list[reproduce.ClaimRow] = []
    start = time.perf_counter()
    loggers = [logging.getLogger(name) for name in _PACKAGES]
    with logging_redirect_tqdm(loggers=loggers):
        bar = tqdm(keys, desc="reproduce", unit="item", disable=args.quiet, file=sys.stderr)
        for key in bar:
            bar.set_postfix_str(key)
            rows.extend(reproduce.run_items(ctx, [key]))
    csv_path, md_path = reproduce.write_table(rows, ctx.out)
    print(md_path.read_text(), end="")
    pngs = sorted(ctx.out.glob("*.png"))
    failed = sum(r.agrees is False for r in rows)
    print(f"\n{len(keys)} item(s), {len(rows)} claim row(s), {failed} disagreeing, "
          f"{time.perf_counter() - start:.1f} s ({'quick' if ctx.quick else 'full'} mode)")
    print(f"figures: {len(pngs)} PNG file(s) in {ctx.out}/")
    print(f"claims table: {md_path} and {csv_path}")
    return 0


def _import_solvers() -> None:
    """Import every public module of ``kinetic_fem`` so that all solvers register."""
    import kinetic_fem

    for mod in pkgutil.iter_modules(kinetic_fem.__path__):
        if not mod.name.startswith("_") and mod.name not in {"cli", "figures"}:
            try:
                importlib.import_module(f"kinetic_fem.{mod.name}")
            except ImportError as exc:  # an optional dependency is missing
                logger.warning("kinetic_fem.%s not loaded: %s", mod.name, exc)


def _check_out(out: Path | None) -> None:
    if out is not None and out.suffix not in {".npz", *io.FORMATS}:
        raise ValueError(f"--out must end in .npz, .vtu or .xdmf, got {str(out)!r}")


def _report(dist: VelocityDistribution, out: Path | None) -> None:
    print(f"a2 = {dist.a2:.10g}")
    print(f"converged={dist.info.converged} iterations={dist.info.iterations} "
          f"wall_time={dist.info.wall_time:.3g} s")
    if out is not None:
        path = dist.save(out) if out.suffix == ".npz" else io.write_distribution(dist, out)
        print(f"saved to {path}")


def _run_solve_heated(args: argparse.Namespace) -> int:
    _import_solvers()
    if not HEATED_SOLVERS:
        raise ValueError("no heated solver is registered in this installation")
    if args.method not in HEATED_SOLVERS:
        raise ValueError(f"unknown method {args.method!r}; available: {sorted(HEATED_SOLVERS)}")
    _check_out(args.out)
    dist = solve_heated(args.alpha, density=args.density, diffusion=args.diffusion,
                        method=args.method, **dict(args.options))
    print(f"method={dist.method or args.method} alpha={args.alpha} density={args.density} "
          f"diffusion={args.diffusion}")
    print(f"T = {dist.temperature:.10g}")
    _report(dist, args.out)
    return 0


def _run_solve_cooling(args: argparse.Namespace) -> int:
    _import_solvers()
    if args.method not in COOLING_SOLVERS:
        raise ValueError(f"unknown method {args.method!r}; available: {sorted(COOLING_SOLVERS)}")
    _check_out(args.out)
    dist = solve_cooling(args.alpha, density=args.density, method=args.method,
                         **dict(args.options))
    print(f"method={dist.method or args.method} alpha={args.alpha} density={args.density} "
          "(scaled state, T = 1)")
    print(f"zeta = {dist.info.extra['zeta']:.10g}  (dT/dt = -2 zeta n T^(3/2))")
    _report(dist, args.out)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``kinetic-fem``; returns the exit status.

    Bad input (an unknown item, an invalid alpha, ...) prints one line
    ``kinetic-fem: error: ...`` and returns 2, without a traceback; a solver that fails
    on valid input prints ``kinetic-fem: solver failed: ...`` and returns 1.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    _setup_logging(args.quiet)
    try:
        if args.command == "reproduce":
            return _run_reproduce(args)
        if args.command == "solve-cooling":
            return _run_solve_cooling(args)
        return _run_solve_heated(args)
    except (ValueError, TypeError) as exc:
        parser.exit(2, f"kinetic-fem: error: {exc}\n")
    except RuntimeError as exc:  # a solver that failed on valid input
        parser.exit(1, f"kinetic-fem: solver failed: {exc}\n")
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
