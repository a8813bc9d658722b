"""Issue 16: heated FEM states, the a2(alpha) curves by continuation, and the mean time
per state for every kernel, in one process on one core.

1. The 25- and 100-point a2(alpha) curves over [0, 0.99] with the defaults: pointwise
   ``kf.solve_heated`` against :func:`kinetic_fem.solvers.fem_curve.heated_curve`
   (continuation from a linear prediction in alpha), alternately, best of ``--repeat``;
   seconds, yardstick units, the collision-kernel calls of each (Jacobians, residuals,
   loss moments, weighted by size^2.1 in residuals at 700 nodes), and the largest
   difference of T and a2 between the two.
2. The mean time per heated state over alpha in [0, 0.99] (``--points`` values) for
   gamma = 0, 0.5, 1, 2 with white noise and for hard rods in a Fokker-Planck bath
   (friction 1), defaults, best of two per state; against the issue's target of 0.1 s,
   about 0.4 units at the issue's 0.25 s yardstick.

Units: the yardstick (10 LU factorisations of 1000 x 1000, single-threaded BLAS) measured
in this process before each section.

    python benchmarks/bench_fem_heated_speed.py [--quick] [--repeat 2] [--points 12]

Writes ``benchmarks/results/fem_heated_speed.md`` (``_quick`` with ``--quick``).
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_fem_speed import CURVE, CURVE100, yardstick  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation  # noqa: E402
from kinetic_fem.solvers.fem import SEQUENCE_TOL  # noqa: E402
from kinetic_fem.solvers.fem_curve import heated_curve  # noqa: E402
from kinetic_fem.solvers.fem_defaults import _unstretched as UNSTRETCHED  # noqa: E402

MODELS = [("gamma 0 (Maxwell)", 0.0, 0.0), ("gamma 0.5", 0.5, 0.0),
          ("gamma 1 (hard rods, the paper)", 1.0, 0.0), ("gamma 2", 2.0, 0.0),
          ("gamma 1, bath (friction 1)", 1.0, 1.0)]
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


class _AssembledTransport:
    """The former thermostat terms of the heated Newton iteration: scikit-fem ``asm``
    at every call (the interface of :class:`TransportArrays`)."""

    def __init__(self, basis, friction: float = 0.0) -> None:
        self.basis, self.friction = basis, friction

    def transport(self, u, *, jacobian: bool = False):
        from skfem import asm

        from kinetic_fem.operators import fem_discretisation as fd

        field = self.basis.interpolate(u)
        res = -asm(fd.fokker_planck, self.basis, u=field)
        if self.friction > 0.0:
            res -= self.friction * asm(fd.bath_drift, self.basis, u=field)
        grad_mass = asm(fd.mass, self.basis, u=self.basis.interpolate(u))
        if not jacobian:
            return res, None, grad_mass
        jac = asm(fd.fokker_planck_jacobian, self.basis, u=field)
        if self.friction > 0.0:
            jac = jac + self.friction * asm(fd.bath_drift_jacobian, self.basis, u=field)
        return res, -jac.toarray(), grad_mass


def _unstretched_by_roots(s, h0, kappa, cb):
    """The former inverse of the graded mesh's stretching: a root per vertex."""
    from scipy.optimize import brentq

    from kinetic_fem.solvers.fem_defaults import _stretched

    top = cb + 10.0
    while _stretched(top, h0, kappa, cb) < s[-1]:
        top *= 2.0
    return np.array([brentq(lambda c, t=t: _stretched(c, h0, kappa, cb) - t, 0.0, top)
                     for t in s])


def _before(on: bool) -> None:
    """Switch the changes of issue 16's second round off (``on``) or back: P2 for every
    kernel but the paper's model (the former :func:`default_order`), the coarse-mesh
    tolerance 1e-6, the thermostat terms assembled by scikit-fem at every call, the graded
    mesh's vertices by root finding."""
    from kinetic_fem.operators.fem_transport import TransportArrays
    from kinetic_fem.solvers import fem, fem_defaults, fem_newton

    fem.default_order = ((lambda m: 3 if m.is_paper_model else 2) if on  # type: ignore
                         else fem_defaults.default_order)
    fem.SEQUENCE_TOL = 1e-6 if on else SEQUENCE_TOL
    fem_newton.TransportArrays = _AssembledTransport if on else TransportArrays  # type: ignore
    fem_defaults._unstretched = (_unstretched_by_roots if on  # type: ignore
                                 else UNSTRETCHED)


def cpu_yardstick() -> float:
    """CPU seconds (``time.process_time``) of the yardstick, best of 3: with CPU times per
    state, units that a loaded machine does not inflate."""
    import scipy.linalg

    a = np.random.default_rng(0).standard_normal((1000, 1000))
    best = np.inf
    for _ in range(3):
        t0 = time.process_time()
        for _ in range(10):
            scipy.linalg.lu_factor(a)
        best = min(best, time.process_time() - t0)
    return best


def _f_error(state, ref) -> float:
    """Largest relative difference of f(c) where the reference's f > 1e-30."""
    c_top = []
    for st in (state, ref):
        c_top.append(st.disc.vertices[-1] / np.sqrt(st.disc.distribution(st.u).temperature))
    c = np.linspace(0.0, 0.999 * min(c_top), 4000)
    f = []
    for st in (state, ref):
        scale = np.sqrt(st.disc.distribution(st.u).temperature)
        f.append(scale * st.disc.evaluate(st.u, c * scale))
    keep = f[1] > 1e-30
    return float(np.abs(f[0][keep] / f[1][keep] - 1).max())


def compare(points: int, out: list[str]) -> None:
    """Section 3: before (P2 for the other kernels, the C1 figures evaluated with the
    state) and after (P3 by :func:`default_order`, C1 on first read), per state
    alternately in this process; T and a2 against P2 at half the default spacing."""
    from kinetic_fem.solvers import fem
    from kinetic_fem.solvers.fem_defaults import model_spacing, scaled_model

    alphas = [round(float(a), 6) for a in np.linspace(0.0, 0.99, points)]
    out.append("## Before / after the second round (P3 for constant-alpha kernels, C1 "
               "figures on first read, coarse tolerance 1e-2, thermostat forms from cached "
               "element arrays, graded vertices in closed form), per state alternately\n")
    out.append(f"{points} alphas over [0, 0.99], best of two per state and variant; units: "
               "the mean yardstick before and after the row (CPU units: CPU seconds of the "
               "state over CPU seconds of the yardstick, robust to the load).  Errors: "
               "largest over the alphas against P2 at half the default spacing (f(c) where "
               "f > 1e-30).  The "
               "before time includes the C1 loss, evaluated with the state as it was.\n")
    out.append("| model | before s (units) | after s (units) | ratio | before CPU s (CPU units) "
               "| after CPU s (CPU units) | CPU ratio | worst after (alpha), CPU units | "
               "nodes before | nodes after | max dT/T before / after | max da2 before / after "
               "| max df/f before / after | largest df/f after/before | yardstick s wall / "
               "CPU |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, gamma, friction in MODELS:
        before = yardstick()
        cpu_before = cpu_yardstick()
        times = np.zeros((2, len(alphas)))
        cpu = np.zeros((2, len(alphas)))
        nodes: list[list[int]] = [[], []]
        err_t = np.zeros((2, len(alphas)))
        err_a2 = np.zeros((2, len(alphas)))
        err_f = np.zeros((2, len(alphas)))
        for k, alpha in enumerate(alphas):
            problem = kf.HeatedProblem.from_parameters(alpha, kernel=gamma, friction=friction)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                ref_state = fem.steady_state(problem, order=2, spacing=0.5 * model_spacing(
                    scaled_model(problem)))
                ref = ref_state.disc.distribution(ref_state.u)
                for i in (0, 1, 0, 1):
                    _before(i == 0)
                    c0 = time.process_time()
                    t0 = time.perf_counter()
                    dist = kf.solve_heated(alpha, kernel=gamma, friction=friction)
                    if i == 0:
                        dist.info.extra["c1_loss"]  # noqa: B018 - evaluated, as before
                    dt = time.perf_counter() - t0
                    dc = time.process_time() - c0
                    times[i, k] = dt if times[i, k] == 0 else min(times[i, k], dt)
                    cpu[i, k] = dc if cpu[i, k] == 0 else min(cpu[i, k], dc)
                    if len(nodes[i]) == k:
                        nodes[i].append(dist.c.size)
                        err_t[i, k] = abs(dist.temperature / ref.temperature - 1)
                        err_a2[i, k] = abs(dist.a2 - ref.a2)
                        err_f[i, k] = _f_error(fem.steady_state(problem), ref_state)
            _before(False)
        unit = 0.5 * (before + yardstick())
        cpu_unit = 0.5 * (cpu_before + cpu_yardstick())
        m = times.mean(axis=1)
        mc = cpu.mean(axis=1)
        out.append(f"| {label} | {m[0]:.3f} ({m[0] / unit:.2f}) | {m[1]:.3f} "
                   f"({m[1] / unit:.2f}) | {m[0] / m[1]:.2f} | "
                   f"{mc[0]:.3f} ({mc[0] / cpu_unit:.2f}) | "
                   f"{mc[1]:.3f} ({mc[1] / cpu_unit:.2f}) | {mc[0] / mc[1]:.2f} | "
                   f"{cpu[1].max() / cpu_unit:.2f} ({alphas[int(np.argmax(cpu[1]))]}) | "
                   f"{min(nodes[0])}-{max(nodes[0])} "
                   f"| {min(nodes[1])}-{max(nodes[1])} | {err_t[0].max():.1e} / "
                   f"{err_t[1].max():.1e} | {err_a2[0].max():.1e} / {err_a2[1].max():.1e} | "
                   f"{err_f[0].max():.1e} / {err_f[1].max():.1e} | "
                   f"{np.max(err_f[1] / err_f[0]):.2f} | {unit:.3f} / {cpu_unit:.3f} |")
        print(out[-1], flush=True)
    out.append("")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="25-point curve only, 4 alphas")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many (curves)")
    parser.add_argument("--points", type=int, default=12, help="alphas per model")
    parser.add_argument("--compare", action="store_true",
                        help="only section 3 (before/after), to fem_heated_speed_compare.md")
    args = parser.parse_args()
    if args.compare:
        kf.solve_heated(0.5)
        out = ["# Heated FEM states: before / after (issue 16, second round)\n",
               f"One core, load average at the start {os.getloadavg()[0]:.1f}.\n"]
        compare(4 if args.quick else args.points, out)
        out.append(f"load average at the end {os.getloadavg()[0]:.1f}\n")
        (ROOT / "benchmarks" / "results" / "fem_heated_speed_compare.md").write_text(
            "\n".join(out) + "\n")
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
    (ROOT / "benchmarks" / "results" / name).write_text(text + "\n")


if __name__ == "__main__":
    main()
