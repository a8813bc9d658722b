"""Sphinx configuration of the kinetic-fem documentation.

The API reference is generated from what exists: every public module of
``kinetic_fem`` and ``particles`` that imports cleanly is listed (see
:func:`_api_modules`), so a module added by a later capability appears without
editing this file, and a module that cannot be imported is left out with a
message instead of breaking the build.  The gallery is built from
``docs/examples`` (``-D plot_gallery=0`` skips running the examples).
"""

from __future__ import annotations

import importlib
import logging
import pkgutil
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import kinetic_fem  # noqa: E402

project = "kinetic-fem"
author = "kinetic-fem developers"
copyright = "2026, kinetic-fem developers"
release = kinetic_fem.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "examples/README.rst",
                    "auto_examples/*.ipynb", "auto_examples/*.py", "**/*.zip"]
html_theme = "pydata_sphinx_theme"
html_title = "kinetic-fem"
html_theme_options = {"show_toc_level": 2}

# No network: no intersphinx inventories are fetched.
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_typehints = "none"  # numpydoc shows the types from the docstrings
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "reset_modules": ("matplotlib",),
    "matplotlib_animations": False,
    "write_computation_times": False,
}

_HERE = Path(__file__).parent
_PACKAGES = ("kinetic_fem", "particles")
_LOG = logging.getLogger("kinetic_fem.docs")


def _api_modules(package: str) -> list[str]:
    """Public modules of ``package`` (recursively) that import without error."""
    pkg = importlib.import_module(package)
    names = [package]
    for mod in pkgutil.walk_packages(pkg.__path__, prefix=f"{package}."):
        if any(part.startswith("_") for part in mod.name.split(".")):
            continue
        try:
            importlib.import_module(mod.name)
        except Exception as exc:  # noqa: BLE001 - a half-written module must not break docs
            _LOG.warning("API reference: %s left out (%s: %s)", mod.name,
                         type(exc).__name__, exc)
            continue
        names.append(mod.name)
    return sorted(names)


_TITLES = {"kinetic_fem": "kinetic_fem: deterministic kinetic theory",
           "particles": "particles: DSMC and event-driven MD"}


def _write_api_lists() -> None:
    """Write one page per package listing its modules (autosummary), for ``api.rst``."""
    out = _HERE / "api" / "generated"
    out.mkdir(parents=True, exist_ok=True)
    for package in _PACKAGES:
        title = f"``{_TITLES[package]}``"
        lines = [title, "=" * len(title), "", ".. autosummary::", "   :toctree: .", ""]
        lines += [f"   {name}" for name in _api_modules(package)]
        text = "\n".join(lines) + "\n"
        target = out / f"{package}_modules.rst"
        if not target.exists() or target.read_text() != text:
            target.write_text(text)


_write_api_lists()

_USER_GUIDE_GLOB = "   user_guide/*\n"
_USER_GUIDE_LISTED = {"physics", "methods", "reproducing"}


def _drop_empty_glob(app, docname: str, source: list[str]) -> None:
    """Drop the ``user_guide/*`` toctree entry while no page beyond the listed ones exists.

    The glob picks up user-guide pages written by later capabilities; an empty glob
    would be a warning, and the docs build with warnings as errors.
    """
    if docname != "index":
        return
    extra = [p for p in (_HERE / "user_guide").glob("*.rst")
             if p.stem not in _USER_GUIDE_LISTED]
    if not extra:
        source[0] = source[0].replace(_USER_GUIDE_GLOB, "")


def setup(app) -> None:
    """Register the index hook."""
    app.connect("source-read", _drop_empty_glob)
