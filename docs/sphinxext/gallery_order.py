"""Order of the gallery: how a user learns, not the alphabet.

``sphinx_gallery_conf["within_subsection_order"]`` names :class:`LearningOrder` by its
qualified name (a class in an importable module keeps the Sphinx configuration
picklable).  Examples not listed in :data:`ORDER` come just before the last one (the
longest study), by file name, so a new example appears without editing this file.
"""

from __future__ import annotations

from pathlib import Path

ORDER = (
    # first solves: the heated steady state and its theory
    "plot_heated_fem.py",
    "plot_sonine_a2.py",
    "plot_heated_fd.py",
    # the same gas by particles
    "plot_dsmc_heated.py",
    "plot_md_heated.py",
    # other models: thermostats, kernels
    "plot_thermostats.py",
    # free cooling
    "plot_cooling_state.py",
    "plot_maxwell_hcs.py",
    "plot_dsmc_cooling.py",
    "plot_md_cooling.py",
    # the quasi-elastic limits and the tail
    "plot_phi.py",
    "plot_psi.py",
    "plot_effective_exponent.py",
    # many runs, and the longest study last
    "plot_sweep.py",
    "plot_relaxation.py",
)


class LearningOrder:
    """Sort key of gallery files: position in :data:`ORDER`, then file name.

    Parameters
    ----------
    src_dir : str
        The gallery folder (given by sphinx-gallery; unused).
    """

    def __init__(self, src_dir: str) -> None:
        self.src_dir = src_dir

    def __call__(self, filename: str) -> tuple[float, str]:
        name = Path(filename).name
        rank = ORDER.index(name) if name in ORDER else len(ORDER) - 1.5
        return (rank, name)

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {', '.join(ORDER)}>"
