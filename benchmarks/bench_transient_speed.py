"""Cost of the FEM transients against steady solves of the same model (issue 30, item 1).

The two calls of the issue, at their default tolerance, as a user pays them:

* ``kf.evolve_heated(0.6, times=np.linspace(0, 5, 11), initial_temperature=0.5)``
  (hard rods, white noise), against ``kf.solve_heated(0.6)``;
* ``kf.evolve_heated(0.5, kernel=0.0, friction=0.5, initial_temperature=1.0,
  times=[0.25, 0.5, 1, 2, 5])`` (the Maxwell model in a bath), against
  ``kf.solve_heated(0.5, kernel=0.0, friction=0.5)``, with the global error of T
  (relative) and a2 (absolute) against the exact moment equations
  (:func:`kinetic_fem.solvers.maxwell.evolve_moments`).

For each: CPU seconds (``time.process_time``), accepted steps, Jacobian assemblies and
LU factorisations of the step Newton, nodes, the ratio to a steady solve measured in
the same process (best of 3), and yardstick units (10 LU of 1000 x 1000,
single-threaded BLAS, ``yardstick.cpu_yardstick``).  Target: ratio <= 20.

* free cooling of the Maxwell model, ``kf.evolve_cooling(0.5, kernel=0.0,
  initial_temperature=1.0, times=[0.1, 0.3, 0.6], spacing=0.5, cutoff=10.0)`` (the
  registry test's call, default rtol 1e-6), against ``kf.solve_cooling(0.5, kernel=0.0)``,
  with the same errors.

    python benchmarks/bench_transient_speed.py [--rtol R ...]
        [--only heated maxwell cooling cooling_rods]
        [--scheme bdf2 bdf3 bdf4] [--compare TREE]

* free cooling of hard rods, the same call with the default kernel (no exact moments).

``--scheme`` runs the cases with these time schemes (default: the driver's default,
``bdf4`` for ``evolve_heated`` and ``bdf2`` for ``evolve_cooling``, and ``bdf2``, the
integrator before issue 30; before/after in one run).

``--rtol`` runs the calls at these tolerances as well (the table of global error
against CPU time).  ``--compare TREE`` first runs the same table in a subprocess with
``PYTHONPATH`` at another tree (before/after in one run); or run it with ``PYTHONPATH``
at another tree to measure that tree.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import scipy.linalg  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from yardstick import cpu_yardstick  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.solvers.maxwell import evolve_moments  # noqa: E402

CASES = {
    "heated": (dict(alpha=0.6), dict(times=np.linspace(0.0, 5.0, 11), initial_temperature=0.5)),
    "maxwell": (dict(alpha=0.5, kernel=0.0, friction=0.5),
                dict(times=[0.25, 0.5, 1.0, 2.0, 5.0], initial_temperature=1.0)),
    "cooling": (dict(alpha=0.5, kernel=0.0),
                dict(times=[0.1, 0.3, 0.6], initial_temperature=1.0, spacing=0.5,
                     cutoff=10.0)),
    "cooling_rods": (dict(alpha=0.5),
                     dict(times=[0.1, 0.3, 0.6], initial_temperature=1.0, spacing=0.5,
                          cutoff=10.0)),
}
COOLING = {"cooling", "cooling_rods"}
TARGET = 20.0

_FACTORS = [0]
_lu_factor = scipy.linalg.lu_factor


def _counting_lu_factor(*args, **kwargs):
    _FACTORS[0] += 1
    return _lu_factor(*args, **kwargs)


scipy.linalg.lu_factor = _counting_lu_factor   # counts every dense LU of the step Newton


def steady_cpu(name: str) -> float:
    """Best of three CPU seconds of the steady solve of case ``name``'s model."""
    model = CASES[name][0]
    solve = kf.solve_cooling if name in COOLING else kf.solve_heated
    best = np.inf
    for _ in range(3):
        t0 = time.process_time()
        solve(model["alpha"], **{k: v for k, v in model.items() if k != "alpha"})
        best = min(best, time.process_time() - t0)
    return best


def maxwell_errors(model: dict, call: dict, ev) -> tuple[float, float]:
    """Largest relative error of T and absolute error of a2 against the exact moments."""
    times = np.concatenate([[0.0], np.asarray(call["times"], dtype=float)])
    bath = {"friction": model["friction"]} if "friction" in model else {"diffusion": 0.0}
    exact = evolve_moments(model["alpha"], times, **bath,
                           initial_temperature=call["initial_temperature"], order=4)
    err_t = np.max(np.abs(np.asarray(ev.temperature) / exact.temperature[1:] - 1.0))
    err_a2 = np.max(np.abs(np.asarray(ev.a2) - exact.a2[1:]))
    return float(err_t), float(err_a2)


def run(name: str, rtol: float | None, unit: float, scheme: str | None = None) -> dict:
    """One evolve call of case ``name`` (default rtol if None; default scheme if None)
    and its figures."""
    model, call = CASES[name]
    options = {} if rtol is None else {"rtol": rtol}
    if scheme is not None:
        options["scheme"] = scheme
    kwargs = {k: v for k, v in model.items() if k != "alpha"}
    _FACTORS[0] = 0
    t0 = time.process_time()
    evolve = kf.evolve_cooling if name in COOLING else kf.evolve_heated
    ev = evolve(model["alpha"], **kwargs, **call, **options)
    cpu = time.process_time() - t0
    extra = ev.info.extra
    row = {"case": name, "scheme": scheme or "default", "rtol": extra.get("rtol", rtol), "cpu": cpu,
           "steps": extra.get("accepted"), "rejected": extra.get("rejected"),
           "jacobians": extra.get("jacobians"), "factorisations": _FACTORS[0],
           "nodes": extra.get("n_dofs"), "units": cpu / unit,
           "T_end": float(ev.temperature[-1]), "a2_end": float(ev.a2[-1])}
    if model.get("kernel") == 0.0:
        row["err_T"], row["err_a2"] = maxwell_errors(model, call, ev)
    return row


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rtol", type=float, nargs="*", default=[])
    parser.add_argument("--only", nargs="*", choices=sorted(CASES), default=None)
    parser.add_argument("--scheme", nargs="*", default=[None, "bdf2"],
                        help="time schemes, old and new in one run (default: the "
                             "driver's default)")
    parser.add_argument("--compare", default=None, metavar="TREE",
                        help="first run the same table with PYTHONPATH at TREE")
    args = parser.parse_args(argv)
    if args.compare:
        rest = list(argv if argv is not None else sys.argv[1:])
        i = rest.index("--compare")
        del rest[i:i + 2]
        env = {**os.environ, "PYTHONPATH": args.compare}
        subprocess.run([sys.executable, __file__, *rest], env=env, check=True)
    kf.solve_heated(0.6)    # compile outside the timings (steady and transient kernels)
    kf.evolve_heated(0.6, times=[0.01], initial_temperature=0.5, spacing=0.5, rtol=1e-2)
    kf.solve_cooling(0.5, kernel=0.0)
    kf.evolve_cooling(0.5, kernel=0.0, times=[0.01], spacing=0.5, cutoff=10.0, rtol=1e-2)
    names = args.only or list(CASES)
    print(f"tree: {Path(kf.__file__).resolve().parents[1]}")
    header = ("| case | scheme | rtol | CPU s | steps (rej.) | Jacobians | LU | nodes | "
              "steady CPU s | "
              "ratio | units | err T | err a2 |")
    print(header)
    print("|" + "---|" * 13)
    for name in names:
        schemes = args.scheme
        for rtol, scheme in [(r, sc) for r in [None, *args.rtol] for sc in schemes]:
            unit = cpu_yardstick()
            steady = steady_cpu(name)
            row = run(name, rtol, unit, scheme)
            unit = 0.5 * (unit + cpu_yardstick())
            errs = (f"{row['err_T']:.2e} | {row['err_a2']:.2e}" if "err_T" in row
                    else f"(T_end {row['T_end']:.8f}) | (a2_end {row['a2_end']:.8f})")
            print(f"| {name} | {row['scheme']} | {row['rtol']:g} | {row['cpu']:.2f} | "
                  f"{row['steps']} "
                  f"({row['rejected']}) | {row['jacobians']} | {row['factorisations']} | "
                  f"{row['nodes']} | {steady:.3f} | {row['cpu'] / steady:.1f} | "
                  f"{row['cpu'] / unit:.1f} | {errs} |", flush=True)
    print(f"yardstick CPU s (last): {unit:.3f}; target ratio <= {TARGET:g}")


if __name__ == "__main__":
    main()
