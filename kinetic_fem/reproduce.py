"""Registry of the paper's figures and claims, run by ``kinetic-fem reproduce``.

Each capability registers the items it can regenerate with :func:`register`.
An item is a function ``run(ctx) -> list[ClaimRow]``: it may write figures into
``ctx.out`` and returns the measured claims, each beside the paper's value.
Plug-in modules are found through the ``kinetic_fem.reproduce`` entry-point group
(see ``pyproject.toml``), so ``kinetic_fem`` never imports ``particles`` by name.

Quick mode runs small sizes, and some methods then warn that their error bars are
too small (e.g. DSMC batches shorter than the relaxation time).  In quick mode
:func:`run_items` keeps these warnings off the console, marks the rows of the item
that warned as quick-mode estimates (``note``), and :func:`write_table` says once, at
the end of ``claims.md``, which rows they are and why.
"""

from __future__ import annotations

import csv
import importlib
import logging
import re
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, replace
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any, Callable

__all__ = ["Context", "ClaimRow", "Item", "ITEMS", "register", "load_plugins", "run_items",
           "item_order", "write_table", "quick_mode_summary", "QUICK_MARK", "EXPLANATIONS",
           "classify", "verdict_summary"]

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
    """One measured claim: what was measured, the paper's value and the verdict.

    Parameters
    ----------
    claim : str
        Claim label of REPRODUCE.md (``"C1"`` .. ``"C17"``).
    quantity : str
        What was measured.
    measured : str
        The measured value, as printed in the table.
    paper : str
        The paper's value or statement.
    agrees : bool or None
        The verdict (None: not decidable, e.g. a qualitative claim).
    method : str
        The method that gave the number (``"fem"``, ``"dsmc"``, ...).
    note : str
        Anything a reader needs to judge the row.
    explained : str
        Why a verdict ``agrees=False`` is expected, as a key of :data:`EXPLANATIONS`
        (``"misprint"``, ``"peak exponent"``, ``"later stage"``); empty if a disagreement would be
        unexplained.
    """

    claim: str
    quantity: str
    measured: str
    paper: str
    agrees: bool | None
    method: str = ""
    note: str = ""
    explained: str = ""


EXPLANATIONS = {
    "misprint": "misprints (the formula derived from its equations agrees)",
    "peak exponent": "the n(c) peak's exponents (derived: v* ~ eps^(-8/15), "
                     "3 - n* ~ eps^(2/5))",
    "later stage": "our figure's run ends before the stage the paper shows (two compact MD "
                   "clusters and energy plateaus; at our last snapshot the + and - rods are "
                   "still interleaved)",
}
"""Reasons a row may disagree with the paper although the computation is right."""

#: the reasons of :data:`EXPLANATIONS` that are the paper's errors (the others are ours)
PAPER_ERRORS = ("misprint", "peak exponent")


@dataclass(frozen=True)
class Item:
    """A registered figure or claim check.

    Parameters
    ----------
    key : str
        Label of the figure or claim item (``"F3"``, ``"C2-DSMC"``).
    title : str
        One-line description.
    run : callable
        ``run(ctx) -> list[ClaimRow]``: draws the figure into ``ctx.out`` and measures.
    claims : tuple of str
        The claims the item measures.
    """

    key: str
    title: str
    run: Callable[[Context], list[ClaimRow]]
    claims: tuple[str, ...] = field(default_factory=tuple)


ITEMS: dict[str, Item] = {}


def register(key: str, title: str, *, claims: tuple[str, ...] = ()) -> Callable:
    """Decorator registering ``run(ctx)`` as figure/claim item ``key`` (e.g. ``"F3"``).

    Parameters
    ----------
    key : str
        Label of the item (e.g. ``"F3"``); must be new.
    title : str
        One-line description.
    claims : tuple of str
        The claims the item measures.

    Returns
    -------
    callable
        The decorator; it returns the function unchanged.
    """

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


def item_order(key: str) -> tuple[str, int, str]:
    """Sort key of item and claim labels: letter, then number (F2 before F10), then name.

    Parameters
    ----------
    key : str
        An item or claim label.

    Returns
    -------
    tuple
        The sort key ``(letter, number, rest)``.

    Examples
    --------
    >>> sorted(["F10", "C2", "F2-FD", "F2"], key=item_order)
    ['C2', 'F2', 'F2-FD', 'F10']
    """
    digits = "".join(ch for ch in key[1:] if ch.isdigit())
    return (key[0], int(digits) if digits else 0, key)


QUICK_MARK = "quick-mode estimate"
"""Start of the note added to the rows of an item that warned in quick mode."""

_QUICK_NOTE = re.compile(re.escape(QUICK_MARK) + r" \((\d+) warnings? in ([^:]+): (.*)\)$")


def _plugin_packages() -> list[str]:
    """Top-level packages whose loggers the items log to (``kinetic_fem`` and plug-ins)."""
    names = {"kinetic_fem"}
    for ep in entry_points(group="kinetic_fem.reproduce"):
        names.add(ep.value.split(".")[0])
    return sorted(names)


class _Collect(logging.Handler):
    """Keeps the WARNING records (not errors) that reach it."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno == logging.WARNING:
            self.records.append(record)


class _DropWarnings(logging.Filter):
    """Lets through everything but WARNING records of the given packages."""

    def __init__(self, packages: list[str]) -> None:
        super().__init__()
        self.packages = set(packages)

    def filter(self, record: logging.LogRecord) -> bool:
        return not (record.levelno == logging.WARNING
                    and record.name.split(".")[0] in self.packages)


@contextmanager
def _collect_warnings(packages: list[str]):
    """Collect the packages' WARNING records and keep them off every other handler."""
    collector, drop = _Collect(), _DropWarnings(packages)
    loggers = [logging.getLogger(p) for p in packages]
    handlers = {h for lg in [*loggers, logging.getLogger()] for h in lg.handlers}
    for h in handlers:
        h.addFilter(drop)
    for lg in loggers:
        lg.addHandler(collector)
    try:
        yield collector.records
    finally:
        for lg in loggers:
            lg.removeHandler(collector)
        for h in handlers:
            h.removeFilter(drop)


def _mark_quick(rows: list[ClaimRow], key: str,
                records: list[logging.LogRecord]) -> list[ClaimRow]:
    """Rows of item ``key`` with the quick-mode note naming its warnings."""
    first = " ".join(records[0].getMessage().split())
    n = len(records)
    mark = f"{QUICK_MARK} ({n} warning{'s' if n != 1 else ''} in {key}: {first})"
    return [replace(r, note=f"{r.note}; {mark}" if r.note else mark) for r in rows]


def run_items(ctx: Context, keys: list[str] | None = None, *,
              progress: bool | None = None) -> list[ClaimRow]:
    """Run the selected items (all by default) in figure order; collect their claims.

    In quick mode (``ctx.quick``) the warnings the items log are not shown; the rows
    of an item that warned carry a note starting with :data:`QUICK_MARK` (with the
    number of warnings and the first one), which :func:`write_table` summarises once.

    Parameters
    ----------
    ctx : Context
        Output directory, quick or full mode, seeds.
    keys : list of str, optional
        Item labels to run (default: all registered items).
    progress : bool, optional
        A bar naming the running item, its clock refreshed every second (default:
        when interactive, :func:`kinetic_fem.progress.resolve_progress`).

    Returns
    -------
    list of ClaimRow
    """
    from .progress import progress_bar, ticking

    ctx.out.mkdir(parents=True, exist_ok=True)
    selected = sorted(ITEMS if keys is None else keys, key=item_order)
    unknown = [k for k in selected if k not in ITEMS]
    if unknown:
        raise ValueError(f"unknown reproduce item(s) {unknown}; available: "
                         f"{sorted(ITEMS, key=item_order)}")
    rows: list[ClaimRow] = []
    packages = _plugin_packages() if ctx.quick else []
    bar = progress_bar(total=len(selected), progress=progress, desc="reproduce", unit="item",
                       bar_format="{desc} {n_fmt}/{total_fmt} |{bar:20}| {elapsed} {postfix}")
    with bar, ticking(bar):
        for key in selected:
            bar.set_postfix_str(f"{key}: {ITEMS[key].title[:50]}")
            logger.info("reproduce %s: %s", key, ITEMS[key].title)
            if not ctx.quick:
                rows.extend(ITEMS[key].run(ctx))
            else:
                with _collect_warnings(packages) as records:
                    item_rows = ITEMS[key].run(ctx)
                rows.extend(_mark_quick(item_rows, key, records) if records else item_rows)
            bar.update(1)
    return rows


def quick_mode_summary(rows: list[ClaimRow]) -> str:
    """One paragraph naming the rows that are quick-mode estimates ("" if none).

    Parameters
    ----------
    rows : list of ClaimRow
        The rows of a run.

    Returns
    -------
    str

    Examples
    --------
    >>> row = ClaimRow("C2", "tau exponent", "-0.6", "-2/3", True,
    ...                note="quick-mode estimate (4 warnings in C2-DSMC: batches too short)")
    >>> print(quick_mode_summary([row]))
    Quick-mode estimates: 1 row (claims C2) comes from runs that logged 4 warnings
    (item C2-DSMC: batches too short): the quick-mode sizes limit it (the warning says
    how), so its verdict is an estimate; `kinetic-fem reproduce --full` runs the paper's
    sizes.
    """
    marked: dict[str, list[Any]] = {}  # item -> [warnings, reason, rows]
    for r in rows:
        for part in r.note.split("; "):
            m = _QUICK_NOTE.match(part)
            if m:
                marked.setdefault(m.group(2), [int(m.group(1)), m.group(3), []])[2].append(r)
    if not marked:
        return ""
    n_rows = sum(len(v[2]) for v in marked.values())
    n_warn = sum(v[0] for v in marked.values())
    claims = sorted({r.claim for v in marked.values() for r in v[2]}, key=item_order)
    items = "; ".join(f"item {k}: {v[1]}" for k, v in marked.items())
    one = n_rows == 1
    return (f"Quick-mode estimates: {n_rows} row{'' if one else 's'} (claims {', '.join(claims)}) "
            f"{'comes' if one else 'come'} from runs that logged {n_warn} warning"
            f"{'' if n_warn == 1 else 's'}\n({items}): the quick-mode sizes limit "
            f"{'it' if one else 'them'} (the warning says how), so "
            f"{'its verdict is an estimate' if one else 'their verdicts are estimates'}; "
            f"`kinetic-fem reproduce --full` runs the paper's sizes.")


def classify(row: ClaimRow) -> str:
    """The kind of verdict of a row.

    Parameters
    ----------
    row : ClaimRow
        A measured claim.

    Returns
    -------
    str
        ``"agrees"``; ``"not decided"`` (``agrees`` is None: a qualitative or new
        quantity); for a disagreeing row ``"paper: <reason>"`` (its :attr:`ClaimRow.explained`,
        a key of :data:`EXPLANATIONS`), else ``"quick-mode sizes"`` if its item
        warned in quick mode, else ``"unexplained"``.

    Examples
    --------
    >>> classify(ClaimRow("C12", "slope", "-1.0", "-2.0", False, explained="misprint"))
    'paper: misprint'
    """
    if row.agrees is True:
        return "agrees"
    if row.agrees is None:
        return "not decided"
    if row.explained:
        if row.explained not in EXPLANATIONS:
            raise ValueError(f"row {row.claim} {row.quantity!r}: explained={row.explained!r} "
                             f"is not one of {sorted(EXPLANATIONS)}")
        return f"paper: {row.explained}"
    if any(_QUICK_NOTE.match(p) for p in row.note.split("; ")):
        return "quick-mode sizes"
    return "unexplained"


def verdict_summary(rows: list[ClaimRow]) -> str:
    """The closing summary: rows that agree, where the paper is wrong, quick-mode limited.

    Parameters
    ----------
    rows : list of ClaimRow
        The rows of a run.

    Returns
    -------
    str
        A few lines ending in ``0 unexplained`` or the list of unexplained rows.

    Examples
    --------
    >>> rows = [ClaimRow("C1", "T", "1", "1", True),
    ...         ClaimRow("C12", "slope", "-1", "-2", False, explained="misprint")]
    >>> print(verdict_summary(rows))
    2 claim row(s): 1 agree with the paper, 0 not decided (qualitative or new), 1 disagree:
      1 where the paper is wrong, misprints (the formula derived from its equations agrees): C12
      0 limited by quick-mode sizes
      0 unexplained
    """
    kinds: dict[str, list[ClaimRow]] = {}
    for r in rows:
        kinds.setdefault(classify(r), []).append(r)

    def claims(group: list[ClaimRow]) -> str:
        return ", ".join(sorted({r.claim for r in group}, key=item_order))

    n_no = sum(r.agrees is False for r in rows)
    lines = [f"{len(rows)} claim row(s): {len(kinds.get('agrees', []))} agree with the paper, "
             f"{len(kinds.get('not decided', []))} not decided (qualitative or new), "
             f"{n_no} disagree:"]
    for reason, text in EXPLANATIONS.items():
        group = kinds.get(f"paper: {reason}", [])
        if group:
            lead = "where the paper is wrong" if reason in PAPER_ERRORS else "explained"
            lines.append(f"  {len(group)} {lead}, {text}: {claims(group)}")
    quick = kinds.get("quick-mode sizes", [])
    lines.append(f"  {len(quick)} limited by quick-mode sizes"
                 + (f": {claims(quick)} (`--full` runs the paper's sizes)" if quick else ""))
    bad = kinds.get("unexplained", [])
    lines.append(f"  {len(bad)} unexplained" + "".join(
        f"\n    {r.claim} {r.quantity}: measured {r.measured}, paper {r.paper}" for r in bad))
    return "\n".join(lines)


def _short_note(note: str) -> str:
    """The note for the markdown table: quick-mode marks without their warning text."""
    return "; ".join(QUICK_MARK if _QUICK_NOTE.match(p) else p for p in note.split("; ")
                     ) if note else note


def write_table(rows: list[ClaimRow], out: Path) -> tuple[Path, Path]:
    """Write the claims as ``claims.csv`` and ``claims.md`` into ``out``.

    The CSV keeps every note in full; the markdown table shortens quick-mode notes
    and ends with :func:`quick_mode_summary`.

    Parameters
    ----------
    rows : list of ClaimRow
        The rows to write.
    out : Path
        Output directory.

    Returns
    -------
    tuple of Path
        The CSV and the markdown file.
    """
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
              f"| {r.method} | {_short_note(r.note)} |" for r in rows]
    summary = quick_mode_summary(rows)
    if summary:
        lines += ["", summary]
    lines += ["", verdict_summary(rows)]
    md_path.write_text("\n".join(lines) + "\n")
    return csv_path, md_path
