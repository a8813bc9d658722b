"""Every speed target of issue 16 measured on the current tree, in one process.

The status page of the deterministic core's speed: each target of the issue, the public
call with default options as a user pays it, in CPU seconds and in units of the machine
yardstick (CPU seconds of 10 LU factorisations of a 1000 x 1000 matrix with
single-threaded BLAS, ``bench_fem_speed.cpu_yardstick``, measured before and after each
group in this process; the issue's yardstick is 0.25 s, so 0.1 s is 0.4 units and 0.5 s
2 units).  Single-threaded BLAS and numba.  Before/after comparisons of each lever are in
the benchmarks named in ``benchmarks/results/README.md``; this script only says where the
current code stands.

1. Heated steady state, ``kf.solve_heated(alpha, kernel=...)``: 12 alphas over
   [0, 0.99] per model (gamma 0, 0.5, 1, 2, hard rods in a bath, the saturating kernel),
   best of two calls per state; target: mean <= 0.4 units per model.
2. a2(alpha) curves over [0, 0.99]: 25 and 100 points, a loop over ``kf.solve_heated``
   (as a user writes it) and ``fem_curve.heated_curve``; targets: 25 points <= 10 units,
   100 points <= 10 CPU s.
3. Cooling state, ``kf.solve_cooling(alpha, kernel=...)``: cold calls (every solver cache
   cleared before each), hard rods over eps = 1 - alpha in [1e-3, 1], the Maxwell model
   and gamma = 2 over alpha in [0, 0.999]; target: <= 2 units for eps >= 1e-3.

    python benchmarks/bench_targets.py [--quick] [--out FILE]

Writes ``benchmarks/results/targets.md`` (``--quick``: fewer points, printed only).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import functools  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from yardstick import cpu_yardstick  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem import solvers  # noqa: E402
from kinetic_fem.solvers.fem import curve as fem_curve  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HEATED_MODELS = {"gamma 0 (Maxwell)": dict(kernel=0.0), "gamma 0.5": dict(kernel=0.5),
                 "gamma 1 (hard rods)": dict(kernel=1.0), "gamma 2": dict(kernel=2.0),
                 "gamma 1, bath (friction 1)": dict(kernel=1.0, friction=1.0),
                 "saturating, g0 = 1": dict(kernel=kf.SaturatingKernel(1.0))}
HEATED_UNITS = 0.4
CURVE25_UNITS = 10.0
CURVE100_CPU = 10.0
COOLING_UNITS = 2.0
ROD_EPS = [1.0, 0.75, 0.5, 0.3, 0.2, 0.1, 0.07, 0.05, 0.04, 0.03, 0.02, 0.01, 5e-3, 3e-3, 1e-3]
MAXWELL_ALPHAS = [0.0, 0.5, 0.9, 0.99, 0.999]
GAMMA2_ALPHAS = [0.0, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99, 0.995, 0.999]


def clear_caches() -> None:
    """Clear every ``functools`` cache of the solver modules (cold calls)."""
    for name, module in list(sys.modules.items()):
        if not name.startswith(solvers.__name__):
            continue
        for value in vars(module).values():
            if isinstance(value, functools._lru_cache_wrapper):  # noqa: SLF001
                value.cache_clear()


def cpu(call) -> tuple[float, object]:
    """CPU seconds of ``call()`` and its result (an exception is returned, not raised)."""
    t0 = time.process_time()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = call()
    except Exception as err:  # noqa: BLE001 - reported in the table
        out = err
    return time.process_time() - t0, out


def heated(alphas: list[float], repeat: int) -> tuple[list[str], dict]:
    lines = ["| model | mean CPU s | mean units | max units (alpha) | dofs | yardstick CPU s | "
             "target <= 0.4 units |", "|---|---|---|---|---|---|---|"]
    means = {}
    for model, kw in HEATED_MODELS.items():
        kf.solve_heated(0.31, **kw)  # compile and warm the imports
        unit = cpu_yardstick()
        times, nodes = [], []
        for alpha in alphas:
            call = functools.partial(kf.solve_heated, alpha, **kw)
            times.append(min(cpu(call)[0] for _ in range(repeat)))
            nodes.append(call().info.extra["n_dofs"])
        unit = 0.5 * (unit + cpu_yardstick())
        units = np.array(times) / unit
        worst = int(np.argmax(units))
        means[model] = float(units.mean())
        lines.append(f"| {model} | {np.mean(times):.3f} | {units.mean():.2f} | "
                     f"{units[worst]:.2f} ({alphas[worst]:g}) | {min(nodes)}-{max(nodes)} | "
                     f"{unit:.3f} | {'met' if units.mean() <= HEATED_UNITS else 'not met'} |")
    overall = float(np.mean(list(means.values())))
    lines.append(f"\nMean over the {len(means)} models: {overall:.2f} units.")
    return lines, means


def curves(points: list[int]) -> list[str]:
    lines = ["| points | way | CPU s | units | target |", "|---|---|---|---|---|"]
    for n in points:
        alphas = np.linspace(0.0, 0.99, n)
        unit = cpu_yardstick()
        loop, _ = cpu(lambda a=alphas: [kf.solve_heated(x) for x in a])
        warm, _ = cpu(lambda a=alphas: fem_curve.heated_curve(a))
        unit = 0.5 * (unit + cpu_yardstick())
        for way, t in (("loop over kf.solve_heated", loop), ("heated_curve", warm)):
            verdict = ""
            if n == 25:
                met = t / unit <= CURVE25_UNITS
                verdict = f"<= {CURVE25_UNITS:g} units: {'met' if met else 'not met'}"
            elif n == 100:
                met = t <= CURVE100_CPU
                verdict = f"<= {CURVE100_CPU:g} CPU s: {'met' if met else 'not met'}"
            lines.append(f"| {n} | {way} | {t:.2f} | {t / unit:.1f} | {verdict} |")
    return lines


def cooling(cases: list[tuple[str, float, float]]) -> list[str]:
    lines = ["| model | alpha | eps | dofs | CPU s | units | zeta | target <= 2 units |",
             "|---|---|---|---|---|---|---|---|"]
    kf.solve_cooling(0.5)  # compile
    unit = cpu_yardstick()
    for label, kernel, alpha in cases:
        clear_caches()
        t, out = cpu(functools.partial(kf.solve_cooling, alpha, kernel=kernel))
        if isinstance(out, Exception):
            lines.append(f"| {label} | {alpha:g} | {1 - alpha:.3g} | - | {t:.2f} | "
                         f"{t / unit:.2f} | {type(out).__name__} | not met |")
            continue
        extra = out.info.extra
        dofs = extra["n_dofs"]
        lines.append(f"| {label} | {alpha:g} | {1 - alpha:.3g} | {dofs} | {t:.2f} | "
                     f"{t / unit:.2f} | {extra.get('zeta', float('nan')):.10g} | "
                     f"{'met' if t / unit <= COOLING_UNITS else 'not met'} |")
        unit = 0.5 * (unit + cpu_yardstick())
    return lines


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer points, not written")
    parser.add_argument("--out", default=str(ROOT / "benchmarks/results/targets.md"))
    args = parser.parse_args(argv)
    load0 = os.getloadavg()
    alphas = [0.0, 0.5, 0.9, 0.99] if args.quick else [
        round(float(a), 6) for a in np.linspace(0.0, 0.99, 12)]
    cases = ([("hard rods", 1.0, 1 - e) for e in ([0.5, 0.05, 1e-3] if args.quick else ROD_EPS)]
             + [("Maxwell", 0.0, a) for a in ([0.9] if args.quick else MAXWELL_ALPHAS)]
             + [("gamma 2", 2.0, a) for a in ([0.9] if args.quick else GAMMA2_ALPHAS)])
    out = ["# Issue 16 targets on the current tree (`python benchmarks/bench_targets.py`)", "",
           f"Load average at the start {load0[0]:.1f}; one core (single-threaded BLAS and "
           "numba); units = CPU s / CPU s of the yardstick in this process.", "",
           f"## 1. Heated steady state, defaults ({len(alphas)} alphas over [0, 0.99], "
           "best of two)", ""]
    lines, _ = heated(alphas, repeat=2)
    out += lines + ["", "## 2. a2(alpha) curves over [0, 0.99], hard rods, defaults", ""]
    out += curves([25] if args.quick else [25, 100])
    out += ["", "## 3. Cooling state, defaults, cold calls (solver caches cleared)", ""]
    out += cooling(cases)
    out += ["", f"Load average at the end {os.getloadavg()[0]:.1f}."]
    text = "\n".join(out) + "\n"
    print(text)
    if not args.quick:
        Path(args.out).write_text(text)
    return text


if __name__ == "__main__":
    main()
