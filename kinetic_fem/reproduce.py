"""Registry of the paper's figures and claims, run by ``kinetic-fem reproduce``.

Each capability registers the items it can regenerate with :func:`register`.
An item is a function ``run(ctx) -> list[ClaimRow]``: it may write figures into
``ctx.out`` and returns the measured claims, each beside the paper's value.
Plug-in modules are found through the ``kinetic_fem.reproduce`` entry-point group
(see ``pyproject.toml``), so ``kinetic_fem`` never imports ``particles`` by name.
"""

from __future__ import annotations

import csv
import importlib
import logging
from dataclasses import asdict, dataclass, field
from importlib.metadata import entry_points
from pathlib import Path
from typing import Callable

__all__ = ["Context", "ClaimRow", "Item", "ITEMS", "register", "load_plugins", "run_items",
           "write_table"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Context:
    """What an item needs to run.

    Attributes
    ----------
    out : Path
        Folder for figures and data.
    quick : bool
        Small sizes that finish in CI; ``False`` runs the paper's sizes.
    progress : bool
        Show progress bars.
    seed : int
        Root seed for every random stream of the run.
    """

    out: Path
    quick: bool = True
    progress: bool = False
    seed: int = 20020101


@dataclass(frozen=True)
class ClaimRow:
    """One measured claim: what was measured, the paper's value and the verdict."""

    claim: str
    quantity: str
    measured: str
    paper: str
    agrees: bool | None
    method: str = ""
    note: str = ""


@dataclass(frozen=True)
class Item:
    """A registered figure or claim check."""

    key: str
    title: str
    run: Callable[[Context], list[ClaimRow]]
    claims: tuple[str, ...] = field(default_factory=tuple)


ITEMS: dict[str, Item] = {}


def register(key: str, title: str, *, claims: tuple[str, ...] = ()) -> Callable:
    """Decorator registering ``run(ctx)`` as figure/claim item ``key`` (e.g. ``"F3"``)."""

    def decorate(run: Callable[[Context], list[ClaimRow]]) -> Callable[[Context], list[ClaimRow]]:
        if key in ITEMS:
            raise ValueError(f"reproduce item {key!r} is registered twice")
        ITEMS[key] = Item(key, title, run, tuple(claims))
        return run

    return decorate


def load_plugins() -> list[str]:
    """Import every module of the ``kinetic_fem.reproduce`` entry-point group."""
    loaded = []
    for ep in entry_points(group="kinetic_fem.reproduce"):
        try:
            importlib.import_module(ep.value)
            loaded.append(ep.value)
        except ImportError as exc:  # a plug-in's optional dependency is missing
            logger.warning("reproduce plug-in %s not loaded: %s", ep.value, exc)
    return loaded


def _order(key: str) -> tuple[str, int, str]:
    digits = "".join(ch for ch in key[1:] if ch.isdigit())
    return (key[0], int(digits) if digits else 0, key)


def run_items(ctx: Context, keys: list[str] | None = None) -> list[ClaimRow]:
    """Run the selected items (all by default) in figure order; collect their claims."""
    ctx.out.mkdir(parents=True, exist_ok=True)
    selected = sorted(ITEMS if keys is None else keys, key=_order)
    unknown = [k for k in selected if k not in ITEMS]
    if unknown:
        raise ValueError(f"unknown reproduce item(s) {unknown}; available: "
                         f"{sorted(ITEMS, key=_order)}")
    rows: list[ClaimRow] = []
    for key in selected:
        logger.info("reproduce %s: %s", key, ITEMS[key].title)
        rows.extend(ITEMS[key].run(ctx))
    return rows


def write_table(rows: list[ClaimRow], out: Path) -> tuple[Path, Path]:
    """Write the claims as ``claims.csv`` and ``claims.md`` into ``out``."""
    csv_path, md_path = out / "claims.csv", out / "claims.md"
    names = list(ClaimRow.__dataclass_fields__)
    with csv_path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=names)
        writer.writeheader()
        for row in rows:
            writer.writerow(asdict(row))
    verdict = {True: "yes", False: "NO", None: "n/a"}
    lines = ["| claim | quantity | measured | paper | agrees | method | note |",
             "|---|---|---|---|---|---|---|"]
    lines += [f"| {r.claim} | {r.quantity} | {r.measured} | {r.paper} | {verdict[r.agrees]} "
              f"| {r.method} | {r.note} |" for r in rows]
    md_path.write_text("\n".join(lines) + "\n")
    return csv_path, md_path
