"""Sphinx configuration of the kinetic-fem documentation.

The API reference is generated from what exists (``docs/sphinxext/api_pages.py``):
every public module of ``kinetic_fem`` and ``particles`` that imports cleanly gets a
page, each object is documented once, in the module that defines it, so a module
added by a later capability appears without editing this file, and a module that
cannot be imported is left out with a message instead of breaking the build.  The
gallery is built from ``docs/examples`` in the order of ``sphinxext/gallery_order.py``;
every example is executed (``-D plot_gallery=0`` skips that) and a failing example
fails the build.
With ``KINETIC_FEM_DOCS_QUICK=1`` in the environment the examples run at the cheap
sizes they state (CI does this).  Maths is rendered by a MathJax copy bundled with
``sphinx-mathjax-offline``, so pages need no network.

Rebuilds are incremental: sphinx-gallery runs only the examples whose source changed
since their output in ``docs/auto_examples`` was written (its MD5 check; deleting that
folder runs them all), and all of them again when ``KINETIC_FEM_DOCS_QUICK`` differs from
the last build (recorded in ``docs/auto_examples/.docs-mode``).  Ctrl-C stops the build
at once (with a line saying so), also while an example runs.
"""

from __future__ import annotations

import os
import signal
import sys
from pathlib import Path

# One BLAS/OpenMP/numba thread for every example, in this process and in the gallery's
# worker processes (which inherit the environment; joblib's loky would otherwise pick
# cores // jobs itself).  Set before numpy is first imported (matplotlib below imports
# it; sphinx does not): the examples' matrices are small, and idle BLAS threads spin on
# a loaded machine (evolve_cooling alpha 0.5 to t = 20 cost 60.4 CPU s with the default
# threads against 16.3 single-threaded at load ~11).
_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS",
                "NUMBA_NUM_THREADS")
if "numpy" in sys.modules:  # sphinx run from a Python session: too late for BLAS here
    print("docs: numpy was imported before conf.py, its BLAS keeps its threads in this "
          "process (the gallery's worker processes run single-threaded)", file=sys.stderr)
for _var in _THREAD_VARS:
    os.environ[_var] = "1"

import matplotlib  # noqa: E402

matplotlib.use("Agg")
sys.path.insert(0, str(Path(__file__).parent / "sphinxext"))

from api_pages import write_api_pages  # noqa: E402  (docs/sphinxext)

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
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static: no CDN at view time
    "sphinx.ext.viewcode",
    "matplotlib.sphinxext.plot_directive",  # the figure of getting_started
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "examples/README.rst",
                    "auto_examples/*.ipynb", "auto_examples/*.py", "**/*.zip"]
html_theme = "pydata_sphinx_theme"
html_title = "kinetic-fem"
toc_object_entries_show_parents = "hide"  # page TOC: "a2", not "VelocityDistribution.a2"
_PAGE_TOC = ["page-toc", "sourcelink"]
html_theme_options = {
    "show_toc_level": 2,
    # gallery pages have no sections: the right column would only narrow the code
    # (non-overlapping patterns: the theme warns when a page matches two)
    "secondary_sidebar_items": {"*": _PAGE_TOC, "user_guide/*": _PAGE_TOC,
                                "api/generated/*": _PAGE_TOC, "auto_examples/*": []},
}
# Pages linked from the top-level toctree have no section navigation: an empty
# left sidebar would only narrow the text (and clip wide equations).
html_sidebars = {
    "index": [], "getting_started": [], "validation": [], "contributing": [],
    "user_guide/*": [], "auto_examples/index": [],
}
html_static_path = ["_static"]
html_css_files = ["custom.css"]

# No network: no intersphinx inventories are fetched.
autosummary_generate = True
autosummary_imported_members = False
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 100)]
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_typehints = "none"  # numpydoc shows the types from the docstrings
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

# Examples shown with their code but not executed, with the reason; remove an entry as
# soon as the example runs again (every example still runs in tests/test_examples.py
# at its TEST_KWARGS).
_NOT_EXECUTED: dict[str, str] = {}

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    # executed: every plot_*.py except those in _NOT_EXECUTED
    "filename_pattern": (r"/plot_(?!(?:" + "|".join(k[len("plot_"):] for k in _NOT_EXECUTED)
                         + r")\.py$)") if _NOT_EXECUTED else r"/plot_",
    "download_all_examples": False,
    "reset_modules": ("matplotlib",),
    "matplotlib_animations": False,
    "write_computation_times": False,
    "within_subsection_order": "gallery_order.LearningOrder",
    # a failing example fails the build (the default, stated)
    "only_warn_on_example_error": False,
}


def _gallery_jobs() -> int | bool:
    """Processes running the examples: ``KINETIC_FEM_DOCS_JOBS``, default 2 (both cores of
    the CI machine), never more than the cores; 1 (or joblib missing) runs them here."""
    raw = os.environ.get("KINETIC_FEM_DOCS_JOBS", "2")
    try:
        jobs = int(raw)
    except ValueError:
        raise ValueError(f"KINETIC_FEM_DOCS_JOBS must be a whole number >= 1, got {raw!r}") \
            from None
    if jobs < 1:
        raise ValueError(f"KINETIC_FEM_DOCS_JOBS must be a whole number >= 1, got {raw!r}")
    jobs = min(jobs, os.cpu_count() or 1)
    if jobs > 1:
        try:
            import joblib  # noqa: F401  (sphinx-gallery's parallel runs use it)
        except ImportError:
            print("docs: joblib is not installed, the examples run one at a time "
                  "(pip install '.[docs]')", file=sys.stderr)
            return False
    return jobs if jobs > 1 else False


# examples in parallel processes (sphinx-gallery >= 0.17, joblib): the longest examples
# then no longer run one after the other
sphinx_gallery_conf["parallel"] = _gallery_jobs()

_HERE = Path(__file__).parent
write_api_pages(_HERE)


def _gallery_mode_changed(gallery: Path) -> bool:
    """Whether the examples in ``gallery`` ran at other sizes (quick or full) than now."""
    mode = "quick" if os.environ.get("KINETIC_FEM_DOCS_QUICK") else "full"
    marker = gallery / ".docs-mode"
    changed = marker.is_file() and marker.read_text().strip() != mode
    gallery.mkdir(exist_ok=True)
    marker.write_text(mode + "\n")
    return changed


# unchanged examples are not run again, unless they ran at the other sizes
sphinx_gallery_conf["run_stale_examples"] = _gallery_mode_changed(_HERE / "auto_examples")


def _stop_build(signum: int, frame: object) -> None:
    """Ctrl-C: stop the whole build now (sphinx-gallery would report the interrupt as an
    error of the running example, or a SystemError from a numba kernel, and go on)."""
    # straight to file descriptor 2: while an example runs, sphinx-gallery has replaced
    # sys.stdout/sys.stderr by its capture, and os._exit flushes nothing
    os.write(2, b"\ndocs build interrupted (Ctrl-C): stopped; unchanged examples keep "
                b"their output for the next build\n")
    os._exit(130)


if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
    try:
        signal.signal(signal.SIGINT, _stop_build)
    except ValueError:  # not the main thread (an embedding application): leave it
        pass

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


_OPTIONAL_PAGES = {"user_guide/exact_solutions": "the exact-solutions page of the user guide"}


def _unlink_missing_pages(app, docname: str, source: list[str]) -> None:
    """Turn ``:doc:`` links to optional pages that do not exist (yet) into plain text.

    Pages written by other capabilities may land later; a dangling link would be a
    warning, and the docs build with warnings as errors.
    """
    for page, text in _OPTIONAL_PAGES.items():
        if not (_HERE / f"{page}.rst").exists():
            source[0] = source[0].replace(f":doc:`{page}`", text)


def setup(app) -> None:
    """Register the source hooks."""
    app.connect("source-read", _drop_empty_glob)
    app.connect("source-read", _unlink_missing_pages)
