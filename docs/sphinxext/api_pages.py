"""Generate the API reference pages: every public object documented exactly once.

Each public module of ``kinetic_fem`` and ``particles`` that imports cleanly gets one
page (``docs/api/generated/<module>.rst``).  A module page documents only the names
it *owns*: functions and classes whose ``__module__`` is that module, and data listed
in the ``__all__`` of no deeper module.  Packages that re-export names from their
submodules (``kinetic_fem``, ``kinetic_fem.model``, ...) list those names in a table
that links to the one place where each is documented.  So every object has one anchor,
and the "[docs]" links of the highlighted source (``sphinx.ext.viewcode``) resolve.

The modules are grouped for a reader (:data:`GROUPS`); a module matching no group goes
to "Other modules", so a module added later appears without editing this file.  The
"Start here" table (:data:`START_HERE`) lists the entry points most users need; names
that do not exist (yet) are left out.
"""

from __future__ import annotations

import importlib
import inspect
import logging
import pkgutil
from pathlib import Path
from types import ModuleType

LOG = logging.getLogger("kinetic_fem.docs")

PACKAGES = ("kinetic_fem", "particles")

START_HERE = (
    ("Solve", ("kinetic_fem.solve_heated", "kinetic_fem.solve_cooling",
               "kinetic_fem.evolve_heated", "kinetic_fem.evolve_cooling",
               "kinetic_fem.sweep")),
    ("Time dependence", ("kinetic_fem.evolution.Evolution", "kinetic_fem.model.protocol.Protocol")),
    ("Results", ("kinetic_fem.VelocityDistribution", "kinetic_fem.distribution.Comparison",
                 "kinetic_fem.RunInfo", "kinetic_fem.error.ErrorEstimate")),
    ("Particles", ("particles.dsmc.simulate_heated", "particles.dsmc.simulate_cooling",
                   "particles.md.simulate_heated", "particles.md.simulate_cooling")),
    ("The model", ("kinetic_fem.model.PowerLawKernel",
                   "kinetic_fem.model.ConstantRestitution",
                   "kinetic_fem.model.ThresholdRestitution",
                   "kinetic_fem.model.ViscoelasticRestitution",
                   "kinetic_fem.model.WhiteNoise", "kinetic_fem.model.FokkerPlanckBath",
                   "kinetic_fem.model.HeatedProblem", "kinetic_fem.model.CoolingProblem",
                   "kinetic_fem.model.UnsupportedModelError")),
    ("Quasi-elastic limits and theory", ("kinetic_fem.solvers.scaling.solve_phi",
                                         "kinetic_fem.solvers.scaling.solve_psi",
                                         "kinetic_fem.sonine.a2_first_order")),
)
"""(section title, public names as users write them) of the "Start here" table."""

GROUPS = (
    ("Entry points and results", ("=kinetic_fem", "kinetic_fem.solve", "kinetic_fem.distribution",
                                  "kinetic_fem.error", "kinetic_fem.evolve",
                                  "kinetic_fem.evolution",
                                  "kinetic_fem.sweep")),
    ("The model", ("kinetic_fem.model", "kinetic_fem.gas", "kinetic_fem.model.protocol")),
    ("Deterministic solvers", ("kinetic_fem.solvers", "kinetic_fem.sonine")),
    ("Particle simulations", ("particles",)),
    ("Analysis, plots and files", ("kinetic_fem.analysis", "kinetic_fem.plot",
                                   "kinetic_fem.io")),
    ("Operators: meshes, quadrature, weak and strong forms", ("kinetic_fem.operators",)),
    ("Command line and the reproduce registry", ("kinetic_fem.cli", "kinetic_fem.reproduce")),
)
"""(group title, module prefixes); a module joins the group of its longest matching
prefix (``=name`` matches that module only)."""

PLUGIN_PACKAGES = ("kinetic_fem.figures", "particles.figures")
"""Reproduce plug-ins: documented apart, they are not user API."""


def public_modules(package: str) -> list[ModuleType]:
    """Public modules of ``package`` (recursively) that import without error."""
    pkg = importlib.import_module(package)
    mods = [pkg]
    for info in pkgutil.walk_packages(pkg.__path__, prefix=f"{package}."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        try:
            mod = importlib.import_module(info.name)
        except Exception as exc:  # noqa: BLE001 - a half-written module must not break docs
            LOG.warning("API reference: %s left out (%s: %s)", info.name,
                        type(exc).__name__, exc)
            continue
        if mod.__name__ == info.name:  # an alias module (kinetic_fem.scaling) is its target
            mods.append(mod)
    return sorted(mods, key=lambda m: m.__name__)


def _exported(mod: ModuleType) -> list[str]:
    names = getattr(mod, "__all__", None)
    if names is None:
        names = [n for n, obj in vars(mod).items() if not n.startswith("_")
                 and getattr(obj, "__module__", None) == mod.__name__
                 and (inspect.isfunction(obj) or inspect.isclass(obj))]
    return [n for n in names if hasattr(mod, n)]


def owners(mods: list[ModuleType]) -> dict[str, dict[str, str]]:
    """For each module, its exported names mapped to the module that documents them."""
    by_name = {m.__name__: m for m in mods}
    result: dict[str, dict[str, str]] = {}
    for mod in mods:
        table: dict[str, str] = {}
        for name in _exported(mod):
            obj = getattr(mod, name)
            if inspect.ismodule(obj):
                continue
            home = getattr(obj, "__module__", None)
            if (inspect.isfunction(obj) or inspect.isclass(obj)) and home in by_name \
                    and name in vars(by_name[home]):
                table[name] = home
                continue
            # data: the deepest module exporting it
            deeper = [m.__name__ for m in mods if m.__name__.startswith(mod.__name__ + ".")
                      and name in _exported(m) and getattr(m, name) is obj]
            table[name] = max(deeper, key=len) if deeper else mod.__name__
        result[mod.__name__] = table
    return result


def _title(text: str, char: str = "=") -> list[str]:
    return [text, char * len(text), ""]


def module_page(name: str, table: dict[str, str]) -> str:
    """reST of one module page: docstring, owned members, links to re-exported ones."""
    other = [(n, home) for n, home in table.items() if home != name]
    lines = _title(name)
    lines += [f".. automodule:: {name}", "   :members:"]
    if other:  # re-exported names: documented where they are defined
        lines += [f"   :exclude-members: {', '.join(n for n, _ in other)}"]
    lines += [""]
    if other:
        lines += [".. currentmodule:: None", "",
                  ".. rubric:: Also available here (documented in their own modules)", "",
                  ".. autosummary::", ""]
        lines += [f"   ~{home}.{n}" for n, home in other]
        lines += [""]
    return "\n".join(lines)


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _group_of(name: str) -> str:
    if any(name == p or name.startswith(p + ".") for p in PLUGIN_PACKAGES):
        return "plugins"
    best, group = "", "Other modules"
    for title, prefixes in GROUPS:
        for p in prefixes:
            exact = p.startswith("=")
            p = p.lstrip("=")
            if (name == p or (not exact and name.startswith(p + "."))) and len(p) > len(best):
                best, group = p, title
    return group


def _resolve(public: str, homes: dict[str, dict[str, str]]) -> str | None:
    """Documented full name of ``public`` (``kinetic_fem.solve_heated`` ->
    ``kinetic_fem.solve.solve_heated``), or None if it does not exist."""
    module, _, attr = public.rpartition(".")
    table = homes.get(module)
    if table is None:
        return None
    if attr in table:
        return f"{table[attr]}.{attr}"
    obj = getattr(importlib.import_module(module), attr, None)  # public, not in __all__
    home = getattr(obj, "__module__", None)
    if home in homes and homes[home].get(attr) == home:
        return f"{home}.{attr}"
    return None


def write_api_pages(docs_dir: Path) -> None:
    """Write ``api/generated/*.rst``: module pages, the grouped index, "Start here"."""
    out = docs_dir / "api" / "generated"
    out.mkdir(parents=True, exist_ok=True)
    mods = [m for p in PACKAGES for m in public_modules(p)]
    homes = owners(mods)
    written = set()
    for mod in mods:
        _write(out / f"{mod.__name__}.rst", module_page(mod.__name__, homes[mod.__name__]))
        written.add(f"{mod.__name__}.rst")
    for stale in out.glob("*.rst"):
        if stale.name not in written and stale.name not in ("start_here.rst",
                                                             "modules.rst", "plugins.rst"):
            stale.unlink()

    groups: dict[str, list[str]] = {}
    for mod in mods:
        groups.setdefault(_group_of(mod.__name__), []).append(mod.__name__)
    order = [t for t, _ in GROUPS] + ["Other modules"]
    lines = _title("Modules")
    lines += ["Every public module, grouped by what it is for.  Each object is documented",
              "once, in the module that defines it.", ""]
    for title in order:
        if title not in groups:
            continue
        lines += _title(title, "-")
        lines += [".. autosummary::", ""] + [f"   {n}" for n in groups[title]] + [""]
        lines += [".. toctree::", "   :hidden:", ""] + [f"   {n}" for n in groups[title]]
        lines += [""]
    _write(out / "modules.rst", "\n".join(lines))

    lines = _title("Reproduce plug-ins")
    lines += ["Modules that regenerate the paper's figures and claims for",
              "``kinetic-fem reproduce`` (see :mod:`kinetic_fem.reproduce`).  They plot and",
              "register; they are not meant to be imported by users.", ""]
    plugins = groups.get("plugins", [])
    lines += [".. autosummary::", ""] + [f"   {n}" for n in plugins] + [""]
    lines += [".. toctree::", "   :hidden:", ""] + [f"   {n}" for n in plugins] + [""]
    _write(out / "plugins.rst", "\n".join(lines))

    lines = []
    for title, names in START_HERE:
        resolved = [(n, _resolve(n, homes)) for n in names]
        present = [(n, r) for n, r in resolved if r is not None]
        if not present:
            continue
        lines += [f".. rubric:: {title}", "", ".. autosummary::", ""]
        # the short name, unless two entries share it (dsmc and md)
        short = [r.rpartition(".")[2] for _, r in present]
        lines += [f"   {'~' if short.count(r.rpartition('.')[2]) == 1 else ''}{r}"
                  for _, r in present] + [""]
    lines += solver_options_table()
    _write(out / "start_here.rst", "\n".join(lines))


def solver_options_table() -> list[str]:
    """reST table: for each registered method key, the solver whose options it takes."""
    solve = importlib.import_module("kinetic_fem.solve")
    lines = [".. rubric:: Options of each method", "",
             "``solve_heated(..., method=KEY, **options)`` and ``solve_cooling`` pass",
             "``options`` to the solver registered under ``KEY``; its parameters are the",
             "options (a misspelt one raises ``TypeError``).", "",
             ".. list-table::", "   :header-rows: 1", "", "   * - problem", "     - method",
             "     - solver (its parameters are the options)"]
    for problem, table in (("heated", solve.HEATED_SOLVERS), ("cooling", solve.COOLING_SOLVERS)):
        for key, func in sorted(table.items()):
            target = f"{func.__module__}.{func.__qualname__}"
            lines += [f"   * - {problem}", f"     - ``{key!r}``", f"     - :func:`{target}`"]
    return lines + [""]
