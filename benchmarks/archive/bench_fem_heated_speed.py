"""Issue 16: heated FEM states, the a2(alpha) curves by continuation, and the mean time
per state for every kernel, in one process on one core.

1. The 25- and 100-point a2(alpha) curves over [0, 0.99] with the defaults: pointwise
   ``kf.solve_heated`` against :func:`kinetic_fem.solvers.fem_curve.heated_curve`
   (continuation from a linear prediction in alpha), alternately, best of ``--repeat``;
   seconds, yardstick units, the collision-kernel calls of each (Jacobians, residuals,
   loss moments, weighted by size^2.1 in residuals at 700 nodes), and the largest
   difference of T and a2 between the two.
2. The mean time per heated state over alpha in [0, 0.99] (``--points`` values) for
   gamma = 0, 0.5, 1, 2 with white noise, hard rods in a Fokker-Planck bath (friction 1)
   and the saturating kernel (g0 = 1), defaults, best of two per state; against the
   issue's target of 0.1 s, about 0.4 units at the issue's 0.25 s yardstick.
3. ``--compare``: before (commit ``--before``, exported with ``git archive``) and after
   (this tree) in two worker processes asked alternately, state by state: CPU seconds and
   units, nodes, and the errors of both against P2 at half the default spacing (the
   Maxwell model also against its exact T and a2).  Appends (or replaces) its section
   of ``benchmarks/archive/results/fem_heated_speed_compare.md``; the second round's section
   there came from this script at 39f99a9 (toggles in one process).

Units: the yardstick (10 LU factorisations of 1000 x 1000, single-threaded BLAS) measured
in this process (in each worker) before and after each row.

    python benchmarks/bench_fem_heated_speed.py [--quick] [--repeat 2] [--points 12]
    python benchmarks/bench_fem_heated_speed.py --compare [--quick] [--before 39f99a9]

Writes ``benchmarks/archive/results/fem_heated_speed.md`` (``_quick`` with ``--quick``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]  # the repository (this file is in benchmarks/archive)
if "--serve" not in sys.argv:  # a worker imports the package of its own tree (PYTHONPATH)
    sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_fem_speed import CURVE, CURVE100, cpu_yardstick, yardstick  # noqa: E402
from bench_fem_speed import Worker as SpeedWorker  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.model import SaturatingKernel  # noqa: E402
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation  # noqa: E402
from kinetic_fem.solvers.fem_curve import heated_curve  # noqa: E402

MODELS = [("gamma 0 (Maxwell)", 0.0, 0.0), ("gamma 0.5", 0.5, 0.0),
          ("gamma 1 (hard rods, the paper)", 1.0, 0.0), ("gamma 2", 2.0, 0.0),
          ("gamma 1, bath (friction 1)", 1.0, 1.0),
          ("saturating, g0 = 1", SaturatingKernel(1.0), 0.0)]
"""(label, gamma, friction) of section 2."""
TARGET_SECONDS = 0.1
ISSUE_YARDSTICK = 0.25
"""The issue's yardstick on its machine (s): 0.1 s is 0.4 units."""

CALLS: dict[str, float] = {}


def _count_calls() -> None:
    """Count the collision-kernel calls (by kind, weighted by size^2.1)."""
    collide = FEMDiscretisation._collide

    def counted(self, u, jacobian, energy_power, even=False):
        kind = "J" if jacobian else ("loss" if energy_power >= 0 else "R")
        CALLS[kind] = CALLS.get(kind, 0.0) + 1
        CALLS["work"] = CALLS.get("work", 0.0) + (u.size / 700) ** 2.1 * (2.4 if jacobian
                                                                           else 1.0)
        return collide(self, u, jacobian, energy_power, even)

    FEMDiscretisation._collide = counted  # type: ignore[method-assign]


def curves(repeat: int, full: bool, out: list[str]) -> None:
    """Section 1."""
    out.append("## 1. a2(alpha) curves over [0, 0.99], defaults: pointwise and by "
               "continuation\n")
    out.append(f"Best of {repeat}, the two ways alternately; units: the mean yardstick "
               "before and after the row (given).  Kernel "
               "calls: Jacobians / residuals / loss moments, and the work in residuals at "
               "700 nodes (size^2.1, a Jacobian 2.4).\n")
    out.append("| curve | pointwise s | units | continuation s | units | speed-up | "
               "CPU s pointwise / continuation | calls pointwise | calls continuation | "
               "work ratio | max abs dT/T | max abs da2 | yardstick s |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for alphas, label in ((CURVE, "25-point"), (CURVE100 if full else [], "100-point")):
        if not alphas:
            continue
        before = yardstick()
        best = [np.inf, np.inf]
        cpu = [np.inf, np.inf]
        calls: list[dict[str, float]] = [{}, {}]
        res: list[tuple[np.ndarray, np.ndarray]] = []
        for rep in range(repeat):
            for i in range(2):
                CALLS.clear()
                c0 = time.process_time()
                t0 = time.perf_counter()
                if i == 0:
                    dists = [kf.solve_heated(a) for a in alphas]
                    temp = np.array([d.temperature for d in dists])
                    a2 = np.array([d.a2 for d in dists])
                else:
                    curve = heated_curve(alphas)
                    temp, a2 = curve.temperature, curve.a2
                best[i] = min(best[i], time.perf_counter() - t0)
                cpu[i] = min(cpu[i], time.process_time() - c0)
                calls[i] = dict(CALLS)
                if rep == 0:
                    res.append((temp, a2))
        text = ["{:.0f} / {:.0f} / {:.0f}".format(c.get("J", 0), c.get("R", 0),
                                                   c.get("loss", 0)) for c in calls]
        unit = 0.5 * (before + yardstick())
        d_t = np.abs(res[1][0] / res[0][0] - 1).max()
        d_a2 = np.abs(res[1][1] - res[0][1]).max()
        out.append(f"| {label} | {best[0]:.2f} | {best[0] / unit:.1f} | {best[1]:.2f} | "
                   f"{best[1] / unit:.1f} | {best[0] / best[1]:.2f} | "
                   f"{cpu[0]:.2f} / {cpu[1]:.2f} = {cpu[0] / cpu[1]:.2f} | {text[0]} | {text[1]} | "
                   f"{calls[1]['work'] / calls[0]['work']:.3f} | {d_t:.1e} | {d_a2:.1e} | "
                   f"{unit:.3f} |")
        print(out[-1], flush=True)
    out.append("")


def per_state(points: int, out: list[str]) -> None:
    """Section 2."""
    alphas = [round(float(a), 6) for a in np.linspace(0.0, 0.99, points)]
    out.append("## 2. Mean time per heated state, `kf.solve_heated(alpha, kernel=gamma, "
               "friction=xi)` defaults\n")
    out.append(f"{points} alphas over [0, 0.99], best of two per state; units: the mean of "
               "the yardsticks measured before and after the row.  Target: 0.1 s = "
               f"{TARGET_SECONDS / ISSUE_YARDSTICK:.1f} units (at the issue's "
               f"{ISSUE_YARDSTICK} s yardstick).\n")
    out.append("| model | mean s | mean units | max units (alpha) | nodes | yardstick s | met? |")
    out.append("|---|---|---|---|---|---|---|")
    for label, gamma, friction in MODELS:
        before = yardstick()
        times, nodes, failed = [], [], []
        for alpha in alphas:
            best = np.inf
            for _ in range(2):
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        t0 = time.perf_counter()
                        dist = kf.solve_heated(alpha, kernel=gamma, friction=friction)
                        best = min(best, time.perf_counter() - t0)
                except Exception as err:  # noqa: BLE001 - reported in the table
                    failed.append(f"{alpha}: {type(err).__name__}")
                    break
            if np.isfinite(best):
                times.append(best)
                nodes.append(dist.c.size)
        unit = 0.5 * (before + yardstick())
        t = np.array(times)
        worst = int(np.argmax(t))
        mean_units = t.mean() / unit
        met = "yes" if mean_units <= TARGET_SECONDS / ISSUE_YARDSTICK else "no"
        out.append(f"| {label} | {t.mean():.3f} | {mean_units:.2f} | "
                   f"{t[worst] / unit:.2f} ({alphas[worst]}) | {min(nodes)}-{max(nodes)} | "
                   f"{unit:.3f} | "
                   f"{met}{'; failed ' + ', '.join(failed) if failed else ''} |")
        print(out[-1], flush=True)
    out.append("")


# ------------------------------------------------- before / after: one worker per tree
BEFORE = "39f99a9"
"""main before the third round of issue 16 (heated states of soft kernels)."""
F_GRID = 6000
"""Points of the c grid on which f(c) is compared."""


def _problem(model: int, alpha: float):
    _, gamma, friction = MODELS[model]
    return kf.HeatedProblem.from_parameters(alpha, kernel=gamma, friction=friction)


def _fields(state, c_top: float | None = None) -> dict:
    """T, a2, the mesh's c range and f(c) on the comparison grid of the state."""
    dist = state.disc.distribution(state.u)
    scale = float(np.sqrt(dist.temperature))
    top = state.disc.vertices[-1] / scale
    c = np.linspace(0.0, 0.999 * (top if c_top is None else min(top, c_top)), F_GRID)
    return {"T": float(dist.temperature), "a2": float(dist.a2), "c_top": float(top),
            "nodes": int(state.u.size), "order": int(state.disc.order),
            "f": (scale * state.disc.evaluate(state.u, c * scale)).tolist()}


def task_state(model: int, alpha: float, c_top: float | None) -> dict:
    """One default state (``kf.solve_heated``'s path), CPU and wall seconds, its fields."""
    from kinetic_fem.solvers import fem

    problem = _problem(model, alpha)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c0, t0 = time.process_time(), time.perf_counter()
        state = fem.steady_state(problem)
        fem.state_distribution(problem, state, state.disc.order)
        cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    return {"cpu": cpu, "wall": wall, **_fields(state, c_top)}


def task_reference(model: int, alpha: float) -> dict:
    """P2 at half the default spacing (the comparison of the table)."""
    from kinetic_fem.solvers import fem
    from kinetic_fem.solvers.fem_defaults import model_spacing, scaled_model

    problem = _problem(model, alpha)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        state = fem.steady_state(problem, order=2,
                                 spacing=0.5 * model_spacing(scaled_model(problem)))
    return _fields(state)


def serve() -> None:
    """Answer JSON requests on stdin, one a line, with one JSON line each."""
    import json

    kf.solve_heated(0.5)  # compile
    for line in sys.stdin:
        req = json.loads(line)
        kind = req.pop("task")
        out: object
        if kind == "yardstick":
            out = cpu_yardstick()
        elif kind == "reference":
            out = task_reference(**req)
        else:
            out = task_state(**req)
        print(json.dumps(out), flush=True)


class Worker(SpeedWorker):
    """A persistent worker process on one source tree: this script with ``--serve``
    (``ask`` and ``close`` as in ``bench_fem_speed``)."""

    def __init__(self, tree: Path) -> None:
        import subprocess

        env = dict(os.environ, PYTHONPATH=str(tree))
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()),
                                      "--serve"], env=env, cwd=tree, text=True,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE)


def _errors(out: dict, ref: dict) -> tuple[float, float, float]:
    """dT/T, da2 and the largest df/f where the reference's f > 1e-30."""
    f, fr = np.array(out["f"]), np.array(ref["f"])
    c = np.linspace(0.0, 0.999 * ref["c_top"], F_GRID)
    cs = np.linspace(0.0, 0.999 * min(out["c_top"], ref["c_top"]), F_GRID)
    fr_s = np.exp(np.interp(cs, c, np.log(np.maximum(fr, 1e-300))))
    keep = fr_s > 1e-30
    return (abs(out["T"] / ref["T"] - 1), abs(out["a2"] - ref["a2"]),
            float(np.abs(f[keep] / fr_s[keep] - 1).max()))


def compare(points: int, before: str, out: list[str]) -> None:
    """Before (commit ``before``) and after (this tree), per state alternately in two
    worker processes; errors against P2 at half the default spacing (of ``before``), the
    Maxwell model also against its exact T and a2."""
    import subprocess
    import tempfile

    from kinetic_fem.solvers import maxwell

    tree = Path(tempfile.mkdtemp(prefix="heated_before_"))
    subprocess.run(f"git -C {ROOT} archive {before} | tar -x -C {tree}", shell=True,
                   check=True)
    workers = (Worker(tree), Worker(ROOT))
    alphas = [round(float(a), 6) for a in np.linspace(0.0, 0.99, points)]
    out.append(f"## Third round (soft kernels): before = {before}, after = this tree\n")
    out.append(f"One core, load average at the start {os.getloadavg()[0]:.1f}.  "
               f"{points} alphas over [0, 0.99]; two worker processes (one per tree) "
               "asked alternately, best of two CPU times per state and tree; CPU units: "
               "CPU seconds of a state over the CPU seconds of the yardstick in the same "
               "worker (mean of before and after the row).  Errors: largest over the "
               "alphas against P2 at half the default spacing (before's code; f(c) where "
               "f > 1e-30); Maxwell also against the exact T and a2.\n")
    out.append("| model | before CPU s (units) | after CPU s (units) | CPU ratio | worst after "
               "(alpha), units | nodes before | nodes after | max dT/T before / after | "
               "max da2 before / after | max df/f before / after | largest df/f "
               "after/before (alpha) | exact dT/T, da2 before / after |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    means = np.zeros(2)
    for index, (label, gamma, _friction) in enumerate(MODELS):
        units = [np.array([w.ask("yardstick") for w in workers])]
        cpu = np.full((2, len(alphas)), np.inf)
        res: list[list[dict]] = [[], []]
        err = np.zeros((2, len(alphas), 3))
        exact = np.zeros((2, len(alphas), 2))
        for k, alpha in enumerate(alphas):
            ref = workers[0].ask("reference", model=index, alpha=alpha)
            for rep in range(2):
                for i, w in enumerate(workers):
                    r = w.ask("state", model=index, alpha=alpha, c_top=ref["c_top"])
                    cpu[i, k] = min(cpu[i, k], r["cpu"])
                    if rep == 0:
                        res[i].append(r)
                        err[i, k] = _errors(r, ref)
                        if gamma == 0.0 and MODELS[index][2] == 0.0:
                            m = maxwell.steady_state(alpha)
                            exact[i, k] = (abs(r["T"] / m.temperature - 1), abs(r["a2"] - m.a2))
        units.append(np.array([w.ask("yardstick") for w in workers]))
        unit = 0.5 * (units[0] + units[1])
        mean = cpu.mean(axis=1)
        means += mean / unit
        nodes = [[r["nodes"] for r in rs] for rs in res]
        worst = int(np.argmax(cpu[1]))
        ratio = err[1, :, 2] / err[0, :, 2]
        text = (f"{exact[0, :, 0].max():.1e}, {exact[0, :, 1].max():.1e} / "
                f"{exact[1, :, 0].max():.1e}, {exact[1, :, 1].max():.1e}"
                if exact.any() else "")
        out.append(f"| {label} | {mean[0]:.3f} ({mean[0] / unit[0]:.2f}) | {mean[1]:.3f} "
                   f"({mean[1] / unit[1]:.2f}) | {mean[0] / mean[1]:.2f} | "
                   f"{cpu[1, worst] / unit[1]:.2f} ({alphas[worst]}) | "
                   f"{min(nodes[0])}-{max(nodes[0])} | {min(nodes[1])}-{max(nodes[1])} | "
                   f"{err[0, :, 0].max():.1e} / {err[1, :, 0].max():.1e} | "
                   f"{err[0, :, 1].max():.1e} / {err[1, :, 1].max():.1e} | "
                   f"{err[0, :, 2].max():.1e} / {err[1, :, 2].max():.1e} | "
                   f"{ratio.max():.2f} ({alphas[int(np.argmax(ratio))]}) | {text} |")
        print(out[-1], flush=True)
        per_alpha = " ".join(f"{a}: {c0 / unit[0]:.2f}/{c1 / unit[1]:.2f} "
                             f"({n0}/{n1})" for a, c0, c1, n0, n1 in
                             zip(alphas, cpu[0], cpu[1], nodes[0], nodes[1], strict=True))
        out.append(f"|  | per alpha, units before/after (nodes): {per_alpha} "
                   "| | | | | | | | | | |")
    means /= len(MODELS)
    out.append(f"\nMean over the {len(MODELS)} kernels, CPU units: before {means[0]:.2f}, "
               f"after {means[1]:.2f} (target 0.4).\n")
    for w in workers:
        w.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="25-point curve only, 4 alphas")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many (curves)")
    parser.add_argument("--points", type=int, default=12, help="alphas per model")
    parser.add_argument("--compare", action="store_true",
                        help="only the before/after section, into fem_heated_speed_compare.md")
    parser.add_argument("--before", default=BEFORE, help="commit of the before tree")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve:
        serve()
        return
    if args.compare:
        out: list[str] = []
        compare(4 if args.quick else args.points, args.before, out)
        out.append(f"load average at the end {os.getloadavg()[0]:.1f}\n")
        name = "fem_heated_speed_compare_quick.md" if args.quick else \
            "fem_heated_speed_compare.md"
        path = ROOT / "benchmarks" / "archive" / "results" / name
        old = path.read_text() if path.exists() else "# Heated FEM states: before / after\n"
        marker = "## Third round (soft kernels)"
        keep = old.split(marker)[0].rstrip() + "\n\n" if marker in old else old + "\n"
        path.write_text(keep + "\n".join(out) + "\n")
        return
    _count_calls()
    kf.solve_heated(0.5)  # compile
    out = ["# Heated FEM states: curves by continuation, time per state by kernel (issue 16)\n",
           f"One core (single-threaded BLAS and numba), load average at the start "
           f"{os.getloadavg()[0]:.1f}; compare within a row.\n"]
    curves(args.repeat, not args.quick, out)
    per_state(4 if args.quick else args.points, out)
    out.append(f"load average at the end {os.getloadavg()[0]:.1f}\n")
    text = "\n".join(out)
    print(text)
    name = "fem_heated_speed_quick.md" if args.quick else "fem_heated_speed.md"
    (ROOT / "benchmarks" / "archive" / "results" / name).write_text(text + "\n")


if __name__ == "__main__":
    main()
