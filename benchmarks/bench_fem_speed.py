"""Speed of the FEM heated steady state, before and after issue 16, in one run.

Every figure is measured twice in this run: on the code of commit ``BEFORE`` (exported
with ``git archive`` into a temporary directory) and on the working tree, each in its own
subprocess with single-threaded BLAS.  Times are also given in units of the yardstick
(10 LU factorisations of a 1000 x 1000 matrix, measured in the same subprocess), so the
figures compare across noisy machines.

1. Cost of one collision-operator call (residual, with Jacobian) against the number of
   P2 nodes (250 ... 4000), fitted exponents, beside one dense LU of the same size; after:
   the full sum and the even (mirrored) sum the steady Newton uses.
2. Per-solve time of ``kf.solve_heated(alpha)`` (defaults) on the 25-point curve
   alpha = 0 ... 0.99, nodes, Newton steps, T and a2 (before/after agree to round-off);
   the curve by :func:`kinetic_fem.solvers.fem_curve.heated_curve` with warm starts.
3. The levers one at a time (after): chord steps off, the even sum off, warm starts off.
4. With ``--graded``: fewer nodes from meshes graded in the tail (the model's scales),
   errors of T, a2 and f against a fine reference (not adopted: f loses accuracy).

    python benchmarks/bench_fem_speed.py [--quick] [--graded] [--before COMMIT]

Writes ``benchmarks/results/fem_speed.md``.  The machine is shared: read ratios.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BEFORE = "01feeb1"
"""The last commit before issue 16's changes to the FEM kernel and Newton."""
CURVE = [round(float(a), 6) for a in np.linspace(0.0, 0.99, 25)]
LEVER_ALPHAS = [0.0, 0.6, 0.9, 0.99]
SIZES = [251, 501, 1001, 2001, 4001]


# ------------------------------------------------------------------ worker (subprocess)
def yardstick() -> float:
    """Seconds for 10 LU factorisations of a 1000 x 1000 matrix (best of 3)."""
    import scipy.linalg

    a = np.random.default_rng(0).standard_normal((1000, 1000))
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        for _ in range(10):
            scipy.linalg.lu_factor(a)
        best = min(best, time.perf_counter() - t0)
    return best


def _best(func, repeat: int) -> float:
    out = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        out = min(out, time.perf_counter() - t0)
    return out


def _old_kernel(tree: str):
    """The ``collision_operator`` of the archived tree, compiled beside the new one."""
    import importlib.util

    src = (Path(tree) / "kinetic_fem" / "operators" / "fem_kernels.py").read_text()
    src = src.replace("from .._jit import jit", "from kinetic_fem._jit import jit")
    src = src.replace("from ..model.restitution", "from kinetic_fem.model.restitution")
    path = Path(tempfile.mkdtemp()) / "fem_kernels_before.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("fem_kernels_before", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.collision_operator


def worker_kernel(sizes: list[int], old_tree: str) -> list[dict]:
    """Old and new kernels timed alternately in this process (best of the rounds)."""
    import scipy.linalg

    from kinetic_fem.model.restitution import CONSTANT
    from kinetic_fem.solvers import fem

    old_kernel = _old_kernel(old_tree)
    rows = []
    for n_nodes in sizes:
        n_el = (n_nodes - 1) // 2
        n_el += n_el % 2
        disc = fem.FEMDiscretisation(0.6, np.linspace(-20.0, 20.0, n_el + 1), 2, 5)
        u = disc.gaussian(2.0)
        verts, dofs = disc.mesh_arrays
        xq, wq, eq = disc.points
        ref_x, ref_w = disc.basis.quadrature

        rx = np.ascontiguousarray(ref_x[0])
        head = (verts, dofs, 2, u, xq, wq, eq, rx, ref_w, 0.6, 1.0)
        tail = (3, False, 1.0, CONSTANT, 0.6, 0.0, 1.0, 0.8)

        def old(jac: bool, head=head, tail=tail) -> None:
            old_kernel(*head, jac, *tail)

        funcs = {"res_before": lambda: old(False), "jac_before": lambda: old(True),
                 "res": lambda d=disc, u=u: d.collision(u),
                 "jac": lambda d=disc, u=u: d.collision(u, jacobian=True),
                 "res_even": lambda d=disc, u=u: d.collision(u, even=True),
                 "jac_even": lambda d=disc, u=u: d.collision(u, jacobian=True, even=True)}
        for f in funcs.values():
            f()  # compile
        new_res = disc.collision(u)[0]
        np.testing.assert_allclose(new_res, old_kernel(*head, False, *tail)[0], rtol=0,
                                   atol=1e-12 * np.abs(new_res).max())
        row: dict = {"nodes": int(u.size)}
        rounds = 3 if n_nodes <= 1100 else 2
        for _ in range(rounds):
            for name, f in funcs.items():
                row[name] = min(row.get(name, np.inf), _best(f, 1))
        mat = np.random.default_rng(1).standard_normal((u.size, u.size))
        row["lu"] = _best(lambda m=mat: scipy.linalg.lu_factor(m), rounds)
        rows.append(row)
        print(json.dumps({"progress": row}), file=sys.stderr, flush=True)
    return rows


def _solve_rows(alphas: list[float]) -> list[dict]:
    import kinetic_fem as kf

    rows = []
    for alpha in alphas:
        t0 = time.perf_counter()
        d = kf.solve_heated(alpha)
        rows.append({"alpha": alpha, "time": time.perf_counter() - t0,
                     "nodes": int(d.info.extra["n_dofs"]), "newton": int(d.info.iterations),
                     "T": float(d.temperature), "a2": float(d.a2)})
    return rows


def worker_solves(after: bool, quick: bool) -> dict:
    import kinetic_fem as kf

    kf.solve_heated(0.5, spacing=0.3)  # compile
    alphas = LEVER_ALPHAS if quick else CURVE
    out: dict = {"solves": _solve_rows(alphas)}
    if not after:
        return out
    from functools import partial

    from kinetic_fem.operators.fem_discretisation import FEMDiscretisation
    from kinetic_fem.solvers import fem
    from kinetic_fem.solvers.fem_curve import heated_curve

    for warm in (True, False):
        curve = heated_curve(alphas, warm_start=warm)
        out[f"curve_warm_{warm}"] = {"time": curve.wall_time,
                                     "newton": curve.newton_iterations.tolist(),
                                     "a2": curve.a2.tolist()}
    levers = {}
    orig_newton = fem.newton_steady
    orig_residual = FEMDiscretisation.residual
    fem.newton_steady = partial(orig_newton, chord=False)
    levers["chord off"] = _solve_rows(LEVER_ALPHAS)
    fem.newton_steady = orig_newton

    def full_residual(self, u, *, jacobian=False, even=False):
        return orig_residual(self, u, jacobian=jacobian, even=False)

    FEMDiscretisation.residual = full_residual  # type: ignore[method-assign]
    levers["even sum off"] = _solve_rows(LEVER_ALPHAS)
    FEMDiscretisation.residual = orig_residual  # type: ignore[method-assign]
    levers["all on"] = _solve_rows(LEVER_ALPHAS)
    out["levers"] = levers
    return out


def worker_graded() -> list[dict]:
    import math

    from kinetic_fem import sonine
    from kinetic_fem.solvers import fem
    from kinetic_fem.solvers.fem_defaults import default_cutoff, default_spacing, graded_vertices

    rows = []
    for alpha in (0.0, 0.9):
        ref = fem.steady_state(alpha, spacing=0.04)
        dr = ref.disc.distribution(ref.u)
        temp = sonine.steady_temperature(alpha)
        cands = [("default (uniform)", None)]
        for kappa in (0.5, 0.75):
            for cb in (3.0, 4.0):
                v = math.sqrt(temp) * graded_vertices(default_cutoff(alpha),
                                                      default_spacing(alpha),
                                                      grading=kappa, bulk=cb)
                cands.append((f"kappa={kappa}, c_b={cb}", v))
        for name, verts in cands:
            t0 = time.perf_counter()
            st = fem.steady_state(alpha, vertices=verts)
            wall = time.perf_counter() - t0
            d = st.disc.distribution(st.u)
            s = math.sqrt(d.temperature)
            keep = (dr.f_values > 1e-30) & (np.abs(dr.c) < 0.999 * st.disc.vertices[-1] / s)
            f = s * st.disc.evaluate(st.u, dr.c[keep] * s)
            rows.append({"alpha": alpha, "mesh": name, "nodes": int(st.u.size), "time": wall,
                         "dT": abs(d.temperature / dr.temperature - 1),
                         "da2": abs(d.a2 - dr.a2),
                         "df": float(np.max(np.abs(f / dr.f_values[keep] - 1)))})
    return rows


def worker(task: str, after: bool, quick: bool) -> None:
    unit = yardstick()
    sizes = SIZES[:3] if quick else SIZES
    if task == "kernel":
        data: object = worker_kernel(sizes, os.environ["BENCH_OLD_TREE"])
    elif task == "solves":
        data = worker_solves(after, quick)
    else:
        data = worker_graded()
    print(json.dumps({"unit": min(unit, yardstick()), "data": data}))


# ------------------------------------------------------------------ driver
def run(task: str, tree: Path, after: bool, quick: bool, old_tree: Path | None = None) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), BENCH_OLD_TREE=str(old_tree or ""))
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", task]
    if after:
        cmd.append("--after")
    if quick:
        cmd.append("--quick")
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tree,
                          check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"worker {task} ({'after' if after else 'before'}) failed:\n"
                           f"{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def fit(nodes: list[int], times: list[float]) -> float:
    return float(np.polyfit(np.log(nodes[1:]), np.log(times[1:]), 1)[0])


def report_kernel(after: dict, out: list[str]) -> None:
    out.append("## 1. Collision operator cost against P2 nodes (alpha = 0.6, uniform mesh)\n")
    out.append("Old (archived) and new kernels compiled and timed alternately in one process "
               f"(best of 2-3 rounds); yardstick unit {after['unit']:.3f} s.  'even': the "
               "mirrored half sum the steady Newton uses.\n")
    out.append("| nodes | res before / ms | res after / ms | res even / ms | jac before / ms | "
               "jac after / ms | jac even / ms | dense LU / ms | jac even / LU |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    rows = after["data"]
    for r in rows:
        out.append(f"| {r['nodes']} | {1e3 * r['res_before']:.1f} | {1e3 * r['res']:.1f} | "
                   f"{1e3 * r['res_even']:.1f} | {1e3 * r['jac_before']:.1f} | "
                   f"{1e3 * r['jac']:.1f} | {1e3 * r['jac_even']:.1f} | {1e3 * r['lu']:.1f} | "
                   f"{r['jac_even'] / r['lu']:.1f} |")
    nodes = [r["nodes"] for r in rows]
    names = ["res_before", "res", "res_even", "jac_before", "jac", "jac_even", "lu"]
    fits = {k: fit(nodes, [r[k] for r in rows]) for k in names}
    out.append("\nfitted exponents (time ~ nodes^p, sizes >= 501): "
               + ", ".join(f"{k} {v:.2f}" for k, v in fits.items()) + "\n")


def report_solves(before: dict, after: dict, out: list[str]) -> None:
    ub, ua = before["unit"], after["unit"]
    bs, as_ = before["data"]["solves"], after["data"]["solves"]
    out.append("## 2. kf.solve_heated(alpha), defaults (hard rods, white noise)\n")
    out.append("| alpha | nodes | newton before | newton after | before / s | after / s | "
               "before / units | after / units | speed-up | rel dT | rel da2 |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for b, a in zip(bs, as_, strict=True):
        out.append(f"| {a['alpha']:.4f} | {a['nodes']} | {b['newton']} | {a['newton']} | "
                   f"{b['time']:.3f} | {a['time']:.3f} | {b['time'] / ub:.2f} | "
                   f"{a['time'] / ua:.2f} | {b['time'] / a['time']:.2f} | "
                   f"{abs(a['T'] / b['T'] - 1):.1e} | {abs(a['a2'] / b['a2'] - 1):.1e} |")
    tb = sum(r["time"] for r in bs)
    ta = sum(r["time"] for r in as_)
    n = len(bs)
    out.append(f"\ncurve of {n} points, pointwise: before {tb:.2f} s = {tb / ub:.1f} units "
               f"(mean {tb / n:.3f} s per state), after {ta:.2f} s = {ta / ua:.1f} units "
               f"(mean {ta / n:.3f} s); speed-up {tb / ta:.2f}")
    for warm in (True, False):
        c = after["data"][f"curve_warm_{warm}"]
        out.append(f"heated_curve(warm_start={warm}): {c['time']:.2f} s = "
                   f"{c['time'] / ua:.1f} units, Newton steps {c['newton']}")
    out.append("")
    out.append("## 3. Levers one at a time (after; per-solve seconds)\n")
    levers = after["data"]["levers"]
    names = list(levers)
    out.append("| alpha | " + " | ".join(names) + " |")
    out.append("|---|" + "---|" * len(names))
    for i, alpha in enumerate(LEVER_ALPHAS):
        out.append(f"| {alpha} | " + " | ".join(f"{levers[k][i]['time']:.3f} "
                                                f"({levers[k][i]['newton']} steps)"
                                                for k in names) + " |")
    out.append("")


def report_graded(after: dict, out: list[str]) -> None:
    out.append("## 4. Graded meshes (h ~ c^kappa beyond c_b), errors against spacing 0.04\n")
    out.append("| alpha | mesh | nodes | time / s | dT/T | da2 | max df/f (f > 1e-30) |")
    out.append("|---|---|---|---|---|---|---|")
    for r in after["data"]:
        out.append(f"| {r['alpha']} | {r['mesh']} | {r['nodes']} | {r['time']:.2f} | "
                   f"{r['dT']:.1e} | {r['da2']:.1e} | {r['df']:.1e} |")
    out.append("")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, four alphas")
    parser.add_argument("--graded", action="store_true", help="also the graded-mesh lever")
    parser.add_argument("--before", default=BEFORE, help="commit to compare against")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--after", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args.worker, args.after, args.quick)
        return
    out = [f"# FEM heated steady state: speed before ({args.before}) and after\n",
           "Single-threaded BLAS; shared 2-core machine, so compare within a row.\n"]
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp)
        archive = subprocess.run(["git", "archive", args.before, "kinetic_fem"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        report_kernel(run("kernel", ROOT, True, args.quick, old), out)
        print("kernel: done", flush=True)
        before = run("solves", old, False, args.quick)
        after = run("solves", ROOT, True, args.quick)
        report_solves(before, after, out)
        print("solves: done", flush=True)
    if args.graded:
        report_graded(run("graded", ROOT, True, args.quick), out)
    text = "\n".join(out)
    print(text)
    results = ROOT / "benchmarks" / "results"
    results.mkdir(exist_ok=True)
    (results / ("fem_speed_quick.md" if args.quick else "fem_speed.md")).write_text(text + "\n")


if __name__ == "__main__":
    main()
