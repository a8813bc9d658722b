"""``kinetic-fem reproduce``: the paper's figures and claims table."""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

from tqdm.contrib.logging import logging_redirect_tqdm

from .. import reproduce
from . import COMMANDS
from .parser import PACKAGES, split_keys

__all__ = ["add_parser", "run", "select_items", "interrupt_note"]

EPILOG = """\
Items are figures (F1..F11, as in the paper) and checks (S1, ...); each reports
the claims (C1..C17) it measures.  Output: one PNG per figure, and claims.md /
claims.csv with columns claim, quantity, measured, paper, agrees, method, note.

examples:
  kinetic-fem reproduce --quick --out reproduce-out
  kinetic-fem reproduce --quick --only F2,F3 --out out --seed 7
  kinetic-fem reproduce --full --out paper-sizes      the paper's sizes (hours)
  kinetic-fem reproduce --list
"""


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """The ``reproduce`` sub-command, added to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``kinetic-fem`` parser.

    Returns
    -------
    argparse.ArgumentParser
    """
    rep = sub.add_parser(
        "reproduce", help=COMMANDS["reproduce"][1],
        description="Regenerate the figures of Barrat et al. (2002) and check its claims.",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    size = rep.add_mutually_exclusive_group()
    size.add_argument("--quick", dest="quick", action="store_true", default=True,
                      help="small sizes that finish in minutes (default)")
    size.add_argument("--full", dest="quick", action="store_false",
                      help="the paper's sizes (hours)")
    rep.add_argument("--out", type=Path, default=Path("reproduce-out"), metavar="DIR",
                     help="output folder for PNGs and claims.md/.csv (default: %(default)s)")
    rep.add_argument("--only", type=split_keys, default=None, metavar="KEYS",
                     help="comma-separated items or claims to run, e.g. F2,F3 or C5")
    rep.add_argument("--list", action="store_true",
                     help="list the registered items and the claims they check, then exit")
    rep.add_argument("--quiet", action="store_true",
                     help="no progress bar and no log messages")
    rep.add_argument("--seed", type=int, default=reproduce.Context.seed, metavar="N",
                     help="root seed of every random stream (default: %(default)s)")
    return rep


def select_items(only: list[str] | None) -> list[str]:
    """Item keys for ``--only``: item keys as given, claims mapped to their items.

    Parameters
    ----------
    only : list of str or None
        Item keys (``F3``) and claim labels (``C5``) from ``--only``; None: every item.

    Returns
    -------
    list of str
        Item keys in figure order.

    Raises
    ------
    ValueError
        Naming the unknown keys and what is available.
    """
    items = reproduce.ITEMS
    if only is None:
        return sorted(items, key=reproduce.item_order)
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
                         f"{sorted(items, key=reproduce.item_order)}, claims: {claims}")
    return sorted(dict.fromkeys(keys), key=reproduce.item_order)


def run(args: argparse.Namespace) -> int:
    """Run ``kinetic-fem reproduce``: list, or run the selected items and write the tables.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (0).
    """
    reproduce.load_plugins()
    if args.list:
        lines = []
        for key in sorted(reproduce.ITEMS, key=reproduce.item_order):
            item = reproduce.ITEMS[key]
            claims = f"  [{', '.join(item.claims)}]" if item.claims else ""
            lines.append(f"{key:5s} {item.title}{claims}")
        print("\n".join(lines) if lines else "no reproduce items registered")
        return 0
    keys = select_items(args.only)
    ctx = reproduce.Context(out=args.out, quick=args.quick, progress=not args.quiet,
                            seed=args.seed)
    ctx.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    loggers = [logging.getLogger(name) for name in PACKAGES]
    with logging_redirect_tqdm(loggers=loggers):
        rows = reproduce.run_items(ctx, keys, progress=not args.quiet)
    csv_path, md_path = reproduce.write_table(rows, ctx.out)
    print(md_path.read_text(), end="")
    pngs = sorted(ctx.out.glob("*.png"))
    print(f"\n{len(keys)} item(s), {time.perf_counter() - start:.1f} s "
          f"({'quick' if ctx.quick else 'full'} mode)")
    print(f"figures: {len(pngs)} PNG file(s) in {ctx.out}/")
    print(f"claims table: {md_path} and {csv_path}")
    return 0


def interrupt_note(args: argparse.Namespace) -> str:
    """What a Ctrl-C kept: the figures written so far; how to finish.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    str
    """
    if args.list:
        return "nothing to keep"
    pngs = len(list(Path(args.out).glob("*.png"))) if Path(args.out).is_dir() else 0
    return (f"{pngs} figure(s) written so far are kept in {args.out}/ (the claims table is "
            "written at the end); rerun with --only KEYS for the items still missing")
