"""Regenerate the gamma = 2 anchor states (a thin wrapper of the package's generator).

The table is ``kinetic_fem/solvers/fem/data/gamma2_anchors.json``; its generator is
``python -m kinetic_fem.solvers.fem.cooling_generate gamma2`` (module notes of
:mod:`kinetic_fem.solvers.fem.cooling_generate`).

    python benchmarks/gamma2_anchors.py [--count 36] [--points 65] [--eps-max 1]
        [--eps-min 5e-4] [--out FILE]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import logging  # noqa: E402
import sys  # noqa: E402

from kinetic_fem.solvers.fem.cooling_generate import main  # noqa: E402

if __name__ == "__main__":
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    main(["gamma2", *sys.argv[1:]])
