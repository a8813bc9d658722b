"""Issue 16: the saturating kernel's heated states, before / after, in CPU units.

Two worker processes (``bench_fem_heated_speed.py --serve``), one per source tree
(``--before`` and ``--after``: commits exported with ``git archive``, or ``tree`` for
this working tree), asked alternately state by state: ``kf.solve_heated``'s path for
``SaturatingKernel(g0)`` (white noise) at ``--points`` alphas over [0, 0.99], best of
``--repeat`` CPU times per state and tree; CPU units: CPU seconds over the CPU seconds of
the yardstick (10 LU of 1000 x 1000, single-threaded BLAS) in the same worker, mean of
the yardsticks before and after the sweep.  With ``--errors`` also T, a2 and f(c)
against P2 at half the default spacing (the before tree's code), as in
``bench_fem_heated_speed.py --compare``.  Control models (``--control``, indices of
``bench_fem_heated_speed.MODELS``) can run alongside.

    python benchmarks/bench_saturating_speed.py --before 0761ab0 [--after tree]
        [--points 12] [--repeat 2] [--errors] [--control 0 1 3]

Prints a markdown table (no file written).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]  # the repository (this file is in benchmarks/archive)
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_fem_heated_speed import MODELS, Worker, _errors  # noqa: E402

SATURATING = 5
"""Index of the saturating kernel (g0 = 1) in ``MODELS``."""


def _tree(spec: str) -> Path:
    """This working tree for ``"tree"``, else the commit exported to a temporary folder."""
    if spec == "tree":
        return ROOT
    tree = Path(tempfile.mkdtemp(prefix=f"saturating_{spec}_"))
    subprocess.run(f"git -C {ROOT} archive {spec} | tar -x -C {tree}", shell=True, check=True)
    return tree


def run(model: int, alphas: list[float], workers: tuple[Worker, Worker], repeat: int,
        errors: bool) -> list[str]:
    """One model: markdown rows (summary and per alpha)."""
    units = [np.array([w.ask("yardstick") for w in workers])]
    cpu = np.full((2, len(alphas)), np.inf)
    nodes = np.zeros((2, len(alphas)), dtype=int)
    err = np.zeros((2, len(alphas), 3))
    for k, alpha in enumerate(alphas):
        ref = workers[0].ask("reference", model=model, alpha=alpha) if errors else None
        for rep in range(repeat):
            order = workers if rep % 2 == 0 else workers[::-1]
            for w in order:
                i = workers.index(w)
                r = w.ask("state", model=model, alpha=alpha,
                          c_top=None if ref is None else ref["c_top"])
                cpu[i, k] = min(cpu[i, k], r["cpu"])
                nodes[i, k] = r["nodes"]
                if ref is not None and rep == 0:
                    err[i, k] = _errors(r, ref)
    units.append(np.array([w.ask("yardstick") for w in workers]))
    unit = 0.5 * (units[0] + units[1])
    mean = cpu.mean(axis=1) / unit
    raw = cpu.mean(axis=1)
    rows = [f"| {MODELS[model][0]} | {mean[0]:.3f} | {mean[1]:.3f} | "
            f"{mean[0] / mean[1]:.2f} | {raw[0] / raw[1]:.2f} | {cpu[1].max() / unit[1]:.2f} | "
            f"{nodes[0].min()}-{nodes[0].max()} | {nodes[1].min()}-{nodes[1].max()} | "
            + (f"{err[0, :, 0].max():.1e} / {err[1, :, 0].max():.1e} | "
               f"{err[0, :, 1].max():.1e} / {err[1, :, 1].max():.1e} | "
               f"{err[0, :, 2].max():.1e} / {err[1, :, 2].max():.1e} |" if errors
               else "| | |") + f" {unit[0]:.3f} / {unit[1]:.3f} |"]
    per = " ".join(f"{a}: {c0 / unit[0]:.2f}/{c1 / unit[1]:.2f} ({n0}/{n1})"
                   for a, c0, c1, n0, n1 in zip(alphas, cpu[0], cpu[1], nodes[0], nodes[1],
                                                strict=True))
    rows.append(f"|  | per alpha, units before/after (nodes): {per} | | | | | | | | | | |")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default="main", help="commit of the before tree")
    parser.add_argument("--after", default="tree", help="commit of the after tree, or tree")
    parser.add_argument("--points", type=int, default=12, help="alphas over [0, 0.99]")
    parser.add_argument("--repeat", type=int, default=2, help="best of this many per state")
    parser.add_argument("--errors", action="store_true", help="errors against P2 at h/2")
    parser.add_argument("--control", type=int, nargs="*", default=[],
                        help="also these MODELS indices")
    args = parser.parse_args()
    workers = (Worker(_tree(args.before)), Worker(_tree(args.after)))
    alphas = [round(float(a), 6) for a in np.linspace(0.0, 0.99, args.points)]
    out = [f"before {args.before}, after {args.after}; load average at the start "
           f"{os.getloadavg()[0]:.1f}\n",
           "| model | before units | after units | ratio (units) | ratio (CPU s) | worst after, "
           "units | nodes before "
           "| nodes after | max dT/T before / after | max da2 before / after | max df/f "
           "before / after | yardstick CPU s before / after |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(out), flush=True)
    models = [SATURATING, *args.control]
    for model in models:
        rows = run(model, alphas, workers, args.repeat, args.errors)
        print("\n".join(rows), flush=True)
    print(f"\nload average at the end {os.getloadavg()[0]:.1f}")
    for w in workers:
        w.close()


if __name__ == "__main__":
    main()
