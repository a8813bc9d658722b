"""Issue 16, sixth and seventh rounds: cooling and heated FEM states before and after, in one run.

The persistent workers of ``bench_fem_speed.py`` (one on ``git archive BEFORE``, one on
the working tree; single-threaded BLAS) are driven alternately call by call, so both see
the same machine load; every time is also given in yardstick units (10 LU of
1000 x 1000 in the same worker).

1. ``kf.solve_cooling(alpha)`` with the defaults, cold (the cached state at eps = 0.1 of
   the near-elastic continuation is cleared before each call): nodes, order, seconds,
   units, and the change of zeta and a2 (before -> after).
2. ``kf.solve_heated(alpha)`` on the 25-point curve (best of two per state), and the
   25- and 100-point curves pointwise and by ``heated_curve`` (continuation).

    python benchmarks/bench_fem_interactive.py [--quick] [--before COMMIT]
        [--no-cooling | --no-heated]

Writes ``benchmarks/archive/results/fem_interactive.md`` (``_quick`` with ``--quick``); with
``--no-heated`` (section 1 only, the seventh round's cooling work, e.g. ``--before
d8971af``) ``benchmarks/archive/results/fem_cooling_speed_run.md``.
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_fem_speed import CURVE, CURVE100, ROOT, Worker  # noqa: E402

BEFORE = "5503c25"
"""main at the start of the sixth round."""
COOLING = [0.0, 0.25, 0.5, 0.7, 0.8, 0.9, 0.93, 0.95, 0.96, 0.97, 0.98, 0.99, 0.995, 0.997,
           0.999]
REPEAT_BELOW = 0.9999
"""Cooling states at alpha <= this are timed twice each (best of two)."""


def _units(worker: Worker) -> float:
    return float(worker.ask("yardstick"))  # type: ignore[arg-type]


def cooling_table(before: Worker, after: Worker, alphas: list[float],
                  units: list[list[float]], out: list[str]) -> None:
    """Section 1 (``units``: the yardsticks of each worker, appended to)."""
    out.append("## 1. Cooling state, `kf.solve_cooling(alpha)` defaults, cold\n")
    out.append("| alpha | nodes before | nodes after (order) | before / s | after / s | "
               "before / units | after / units | speed-up | rel dzeta | abs da2 |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    t_after = []
    for alpha in alphas:
        best: list[dict] = [{}, {}]
        for _ in range(2 if alpha <= REPEAT_BELOW else 1):
            for i, w in enumerate((before, after)):
                r = w.ask("cooling", alpha=alpha)
                assert isinstance(r, dict)
                if "error" in r or not best[i] or r["time"] < best[i]["time"]:
                    best[i] = r
        for i, w in enumerate((before, after)):
            units[i].append(_units(w))
        rb, ra = best
        if "error" in rb or "error" in ra:
            out.append(f"| {alpha} | | | {rb.get('error', '')} | {ra.get('error', '')} "
                       "| | | | | |")
            continue
        ub, ua = units[0][-1], units[1][-1]
        t_after.append(ra["time"] / ua)
        out.append(f"| {alpha} | {rb['nodes']} | {ra['nodes']} (P{ra['order']}) | "
                   f"{rb['time']:.2f} | {ra['time']:.2f} | {rb['time'] / ub:.1f} | "
                   f"{ra['time'] / ua:.1f} | {rb['time'] / ra['time']:.1f} | "
                   f"{abs(ra['zeta'] / rb['zeta'] - 1):.1e} | {abs(ra['a2'] - rb['a2']):.1e} |")
    out.append(f"\n(units: the yardstick measured right after each row in the same worker; "
               f"after, mean {np.mean(t_after):.2f} units per state)\n")


def heated_tables(before: Worker, after: Worker, curve: list[float], full: bool,
                  units: list[list[float]], out: list[str]) -> None:
    """Section 2."""
    out.append("## 2. Heated state, `kf.solve_heated(alpha)` defaults\n")
    out.append("| alpha | nodes | before / s | after / s | before / units | after / units |")
    out.append("|---|---|---|---|---|---|")
    sums = [0.0, 0.0]
    for alpha in curve:
        best = [np.inf, np.inf]
        nodes = 0
        for _ in range(2):
            for i, w in enumerate((before, after)):
                r = w.ask("solve", alpha=alpha)
                assert isinstance(r, dict)
                best[i] = min(best[i], r["time"])
                nodes = r["nodes"]
        ub, ua = units[0][-1], units[1][-1]
        sums[0] += best[0] / ub
        sums[1] += best[1] / ua
        out.append(f"| {alpha:.4f} | {nodes} | {best[0]:.3f} | {best[1]:.3f} | "
                   f"{best[0] / ub:.2f} | {best[1] / ua:.2f} |")
    for i, w in enumerate((before, after)):
        units[i].append(_units(w))
    n = len(curve)
    out.append(f"\nsum of the best per-state times: before {sums[0]:.1f} units, after "
               f"{sums[1]:.1f} units; mean per state {sums[0] / n:.2f} / {sums[1] / n:.2f} "
               "units\n")
    out.append("| curve | before | after |")
    out.append("|---|---|---|")
    for alphas, label in ((curve, f"{n}-point"), (CURVE100 if full else [], "100-point")):
        if not alphas:
            continue
        # pointwise kf.solve_heated, then heated_curve (before: warm starts from the
        # previous state; after: continuation from a linear prediction)
        for warm, how in ((None, "pointwise kf.solve_heated"), (True, "heated_curve")):
            tb = before.ask("curve", alphas=alphas, warm=warm)
            ta = after.ask("curve", alphas=alphas, warm=warm)
            for i, w in enumerate((before, after)):
                units[i].append(_units(w))
            assert isinstance(tb, dict) and isinstance(ta, dict)
            out.append(f"| {label}, {how} | {tb['time']:.2f} s = "
                       f"{tb['time'] / units[0][-1]:.1f} units | {ta['time']:.2f} s = "
                       f"{ta['time'] / units[1][-1]:.1f} units |")
    out.append("")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="few alphas, no 100-point curve")
    parser.add_argument("--before", default=BEFORE, help="commit to compare against")
    parser.add_argument("--no-heated", action="store_true", help="section 1 only")
    parser.add_argument("--no-cooling", action="store_true", help="section 2 only")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    out = [f"# FEM states at interactive speed: before ({args.before}) and after (issue 16)\n",
           f"Single-threaded BLAS, 2-core machine shared with other jobs (load average "
           f"{load:.1f} at the start): compare within a row; units are yardsticks (10 LU "
           "of 1000 x 1000) of the same worker.\n"]
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp)
        archive = subprocess.run(["git", "archive", args.before, "kinetic_fem"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        before, after = Worker(old), Worker(ROOT)
        units: list[list[float]] = [[_units(before)], [_units(after)]]
        alphas = [0.5, 0.9, 0.99] if args.quick else COOLING
        if not args.no_cooling:
            cooling_table(before, after, alphas, units, out)
            print("\n".join(out), flush=True)
        if not args.no_heated:
            curve = [0.0, 0.5, 0.9, 0.99] if args.quick else CURVE
            heated_tables(before, after, curve, not args.quick, units, out)
        before.close()
        after.close()
    out.append(f"yardsticks (s): before worker {min(units[0]):.3f} ... {max(units[0]):.3f}, "
               f"after worker {min(units[1]):.3f} ... {max(units[1]):.3f}; load average at the "
               f"end {os.getloadavg()[0]:.1f}\n")
    text = "\n".join(out)
    print(text)
    results = ROOT / "benchmarks" / "archive" / "results"
    name = "fem_interactive_quick.md" if args.quick else "fem_interactive.md"
    if args.no_cooling:
        name = name.replace(".md", "_heated.md")
    if args.no_heated:
        name = "fem_cooling_speed_run.md"
    (results / name).write_text(text + "\n")


if __name__ == "__main__":
    main()
