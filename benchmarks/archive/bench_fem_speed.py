"""Speed of the FEM heated steady state (issue 16), before and after, in one run.

Two persistent worker processes, one on the code of commit ``BEFORE`` (exported with
``git archive``) and one on the working tree, both with single-threaded BLAS, are driven
alternately call by call, so that both see the same machine load; every time is also
given in units of the yardstick (10 LU factorisations of a 1000 x 1000 matrix, measured
in the same worker), which makes the figures comparable across noisy machines.

1. Cost of one collision-operator call (residual; with the Jacobian) against the number
   of nodes (250 ... 4000), before (P2) and after (P2 and P3), the even (mirrored) sums
   the steady Newton uses; fitted exponents and one dense LU of the same size beside.
2. ``kf.solve_heated(alpha)`` with the defaults on the 25-point curve alpha = 0 ... 0.99:
   nodes, time, units; the 25- and 100-point curves (pointwise and warm started).
3. Accuracy of the defaults before (P2) and after (P3) against a finer P3 reference.
4. The levers one at a time (after): each switched off alone.
5. The other kernels (gamma = 0, 0.5, 2) and the Fokker-Planck bath, and the cooling
   state (not changed here; it shares the pair kernel).

    python benchmarks/bench_fem_speed.py [--quick] [--before COMMIT]

Writes ``benchmarks/archive/results/fem_speed.md`` (``fem_speed_quick.md`` with ``--quick``).
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/: the yardstick
from yardstick import cpu_yardstick, yardstick  # noqa: E402,F401

ROOT = Path(__file__).resolve().parents[2]
BEFORE = "aa5003c"
"""main before this round's issue-16 work (P2, the previous round's kernel)."""
CURVE = [round(float(a), 6) for a in np.linspace(0.0, 0.99, 25)]
CURVE100 = [round(float(a), 6) for a in np.linspace(0.0, 0.99, 100)]
LEVER_ALPHAS = [0.0, 0.5, 0.9, 0.95, 0.99]
SIZES = [251, 501, 1001, 2001, 4001]
OTHERS = [(0.0, 0.0, 0.0), (0.0, 0.5, 0.0), (0.5, 0.0, 0.0), (0.5, 0.5, 0.0), (0.5, 0.9, 0.0),
          (2.0, 0.0, 0.0), (2.0, 0.5, 0.0), (2.0, 0.9, 0.0), (2.0, 0.99, 0.0),
          (1.0, 0.0, 1.0), (1.0, 0.5, 1.0), (1.0, 0.9, 1.0), (1.0, 0.99, 1.0)]
"""(gamma, alpha, friction) of section 5 (Maxwell at alpha >= 0.88 and gamma = 0.5 at
0.99 fail before and after: issue 9)."""
COOLING = [0.5, 0.9, 0.99, 0.999]


# ------------------------------------------------------------------ worker (subprocess)
def _timed(func) -> tuple[float, object]:
    t0 = time.perf_counter()
    out = func()
    return time.perf_counter() - t0, out


def _solve(alpha: float, gamma: float = 1.0, friction: float = 0.0, **kw) -> dict:
    import warnings

    from kinetic_fem.gas import HeatedProblem
    from kinetic_fem.solvers import fem

    problem = HeatedProblem.from_parameters(alpha, friction=friction, kernel=gamma)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            wall, st = _timed(lambda: fem.steady_state(problem, **kw))
    except Exception as err:  # noqa: BLE001 - reported in the table
        return {"error": f"{type(err).__name__}: {str(err)[:80]}"}
    d = st.disc.distribution(st.u)
    return {"time": wall, "nodes": int(st.u.size), "order": int(st.disc.order),
            "newton": int(st.info.iterations), "T": float(d.temperature), "a2": float(d.a2)}


def _old_kernel(tree: str):
    """The ``collision_operator`` of the archived tree, compiled beside the new one."""
    import importlib.util

    src = (Path(tree) / "kinetic_fem" / "operators" / "fem_kernels.py").read_text()
    for mod in ("_jit", "model.restitution"):
        src = src.replace(f"from ..{mod}", f"from kinetic_fem.{mod}")
    src = src.replace("from .fem_pair_breaks", "from kinetic_fem.operators.fem_pair_breaks")
    path = Path(tempfile.mkdtemp()) / "fem_kernels_before.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("fem_kernels_before", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.collision_operator


def task_kernel(sizes: list[int], old_tree: str) -> list[dict]:
    """Old (P2) and new (P2, P3) kernels timed alternately in this process."""
    import scipy.linalg

    from kinetic_fem.model.restitution import CONSTANT
    from kinetic_fem.operators.fem_discretisation import FEMDiscretisation

    old_kernel = _old_kernel(old_tree)
    rows = []
    for n_nodes in sizes:
        funcs = {}
        for order in (2, 3):
            n_el = (n_nodes - 1) // order
            n_el += n_el % 2
            disc = FEMDiscretisation(0.6, np.linspace(-20.0, 20.0, n_el + 1), order,
                                     2 * order + 1)
            u = disc.gaussian(2.0)
            for jac in (False, True):
                name = ("jac" if jac else "res") + f"_p{order}"
                funcs[name] = (lambda d=disc, u=u, j=jac:
                               d.collision(u, jacobian=j, energy_power=None, even=True))
            if order == 2:
                verts, dofs = disc.mesh_arrays
                xq, wq, eq = disc.points
                rx, rw = disc.basis.quadrature
                head = (verts, dofs, 2, u, xq, wq, eq, np.ascontiguousarray(rx[0]), rw, 0.6,
                        1.0)
                tail = (3, False, 1.0, CONSTANT, 0.6, 0.0, 1.0, 0.8, disc.mirror)
                for jac in (False, True):
                    funcs["jac_before" if jac else "res_before"] = (
                        lambda h=head, t=tail, j=jac: old_kernel(*h, j, *t))
                new = disc.collision(u, even=True)[0]
                old = old_kernel(*head, False, *tail)[0]
                np.testing.assert_allclose(new, old, rtol=0, atol=1e-12 * np.abs(old).max())
                nodes = int(u.size)
        for f in funcs.values():
            f()  # compile
        row: dict = {"nodes": nodes}
        rounds = 5 if n_nodes <= 1100 else 3 if n_nodes <= 2100 else 2
        for _ in range(rounds):
            for name, f in funcs.items():
                row[name] = min(row.get(name, np.inf), _timed(f)[0])
        mat = np.random.default_rng(1).standard_normal((nodes, nodes))
        row["lu"] = min(_timed(lambda m=mat: scipy.linalg.lu_factor(m))[0]
                        for _ in range(rounds))
        rows.append(row)
    return rows


def task_curve(alphas: list[float], warm: bool | None) -> dict:
    """A curve pointwise (``warm=None``) or by ``heated_curve``."""
    import kinetic_fem as kf

    if warm is None:
        wall, _ = _timed(lambda: [kf.solve_heated(a) for a in alphas])
        return {"time": wall}
    from kinetic_fem.solvers.fem_curve import heated_curve

    curve = heated_curve(alphas, warm_start=warm)
    return {"time": curve.wall_time, "newton": curve.newton_iterations.tolist()}


def task_accuracy(alpha: float) -> dict:
    """Errors of the P2 and the P3 default against P3 at 0.8 times the P2 spacing."""
    import math

    from kinetic_fem import sonine
    from kinetic_fem.solvers import fem
    from kinetic_fem.solvers.fem_defaults import default_spacing

    p2 = fem.steady_state(alpha, order=2)
    p3 = fem.steady_state(alpha)
    cut = p2.disc.vertices[-1] / math.sqrt(sonine.steady_temperature(alpha))
    ref = fem.steady_state(alpha, order=3, spacing=0.8 * default_spacing(alpha), cutoff=cut)
    dr = ref.disc.distribution(ref.u)
    out: dict = {"alpha": alpha, "ref_nodes": int(ref.u.size)}
    for name, st in (("p2", p2), ("p3", p3)):
        d = st.disc.distribution(st.u)
        s = math.sqrt(d.temperature)
        c_max = min(st.disc.vertices[-1] / s, cut)
        keep = (dr.f_values > 1e-30) & (np.abs(dr.c) < 0.999 * c_max)
        f = s * st.disc.evaluate(st.u, dr.c[keep] * s)
        out[name] = {"nodes": int(st.u.size), "dT": abs(d.temperature / dr.temperature - 1),
                     "da2": abs(d.a2 / dr.a2 - 1),
                     "df": float(np.max(np.abs(f / dr.f_values[keep] - 1)))}
    return out


def task_lever(name: str, alpha: float) -> dict:
    """One solve with one lever switched off."""
    from functools import partial

    from kinetic_fem.solvers import fem, fem_newton

    saved = (fem.SEQUENCE_MAX_SPACING, fem_newton.PREDICT_MARGIN, fem.newton_steady)
    kw: dict = {}
    if name == "sequencing off":
        fem.SEQUENCE_MAX_SPACING = 0.0
    elif name == "P3 off (P2)":
        kw["order"] = 2
    elif name == "chord-predicted stop off":
        fem_newton.PREDICT_MARGIN = 0.0
    elif name == "chord off":
        fem.newton_steady = partial(fem_newton.newton_steady, chord=False)
    try:
        return _solve(alpha, **kw)
    finally:
        fem.SEQUENCE_MAX_SPACING, fem_newton.PREDICT_MARGIN, fem.newton_steady = saved


def task_cooling(alpha: float) -> dict:
    import warnings

    import kinetic_fem as kf
    from kinetic_fem.solvers import fem_cooling

    fem_cooling.hump_start.cache_clear()  # a cold call: the state at eps = 0.1 included
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            wall, d = _timed(lambda: kf.solve_cooling(alpha, method="fem"))
    except Exception as err:  # noqa: BLE001 - reported in the table
        return {"error": f"{type(err).__name__}: {str(err)[:80]}"}
    extra = d.info.extra
    return {"time": wall, "a2": float(d.a2), "zeta": float(extra["zeta"]),
            "nodes": int(extra["n_dofs"]), "order": int(extra.get("order", 2))}


def serve() -> None:
    """Answer JSON requests on stdin, one a line, with one JSON line each."""
    import kinetic_fem as kf

    kf.solve_heated(0.5, spacing=0.3)  # compile
    for line in sys.stdin:
        req = json.loads(line)
        kind = req.pop("task")
        if kind == "yardstick":
            out: object = yardstick()
        elif kind == "kernel":
            out = task_kernel(req["sizes"], req["old_tree"])
        elif kind == "solve":
            out = _solve(**req)
        elif kind == "curve":
            out = task_curve(req["alphas"], req["warm"])
        elif kind == "accuracy":
            out = task_accuracy(req["alpha"])
        elif kind == "lever":
            out = task_lever(req["name"], req["alpha"])
        else:
            out = task_cooling(req["alpha"])
        print(json.dumps(out), flush=True)


# ------------------------------------------------------------------ driver
class Worker:
    """A persistent worker process on one source tree."""

    def __init__(self, tree: Path) -> None:
        env = dict(os.environ, PYTHONPATH=str(tree))
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve()),
                                      "--serve"], env=env, cwd=tree, text=True,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE)

    def ask(self, task: str, **req) -> object:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(json.dumps({"task": task, **req}) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"worker died on {task} {req}")
        return json.loads(line)

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        self.proc.wait()


def fit(nodes: list[int], times: list[float]) -> float:
    """Exponent p of time ~ nodes^p over sizes >= 501."""
    return float(np.polyfit(np.log(nodes[1:]), np.log(times[1:]), 1)[0])


def report_kernel(rows: list[dict], unit: float, out: list[str]) -> None:
    out.append("## 1. Collision operator cost against the number of nodes (alpha = 0.6)\n")
    out.append("Even (mirrored) sums as the steady Newton uses them; the old kernel compiled "
               "beside the new one and timed alternately (best of 2-5); P3 on a mesh with the "
               f"same number of nodes.  Yardstick unit {unit:.3f} s.\n")
    out.append("| nodes | res before | res P2 | res P3 | jac before | jac P2 | jac P3 | "
               "dense LU | jac P3 / LU |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        out.append(f"| {r['nodes']} | " + " | ".join(
            f"{1e3 * r[k]:.1f} ms" for k in ("res_before", "res_p2", "res_p3", "jac_before",
                                             "jac_p2", "jac_p3", "lu"))
            + f" | {r['jac_p3'] / r['lu']:.1f} |")
    nodes = [r["nodes"] for r in rows]
    keys = ["res_before", "res_p2", "res_p3", "jac_before", "jac_p2", "jac_p3", "lu"]
    out.append("\nfitted exponents (time ~ nodes^p, sizes >= 501): "
               + ", ".join(f"{k} {fit(nodes, [r[k] for r in rows]):.2f}" for k in keys))
    mid = min(rows, key=lambda r: abs(r["nodes"] - 1001))
    out.append(f"\nspeed-up at {mid['nodes']} nodes: residual P2 "
               f"{mid['res_before'] / mid['res_p2']:.2f}x, Jacobian P2 "
               f"{mid['jac_before'] / mid['jac_p2']:.2f}x\n")


def report_solves(rows: list[tuple[dict, dict]], units: tuple[float, float],
                  out: list[str]) -> tuple[float, float]:
    ub, ua = units
    out.append("## 2. kf.solve_heated(alpha), defaults (hard rods, white noise)\n")
    out.append("Best of two, before and after alternately.  'units': the time over the "
               "yardstick of the same worker.\n")
    out.append("| alpha | nodes before | nodes after (P3) | newton before | newton after | "
               "before / s | after / s | before / units | after / units | speed-up | "
               "rel dT | rel da2 |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for b, a in rows:
        out.append(f"| {a['alpha']:.4f} | {b['nodes']} | {a['nodes']} | {b['newton']} | "
                   f"{a['newton']} | {b['time']:.3f} | {a['time']:.3f} | {b['time'] / ub:.2f} | "
                   f"{a['time'] / ua:.2f} | {b['time'] / a['time']:.2f} | "
                   f"{abs(a['T'] / b['T'] - 1):.1e} | {abs(a['a2'] / b['a2'] - 1):.1e} |")
    tb = sum(b["time"] for b, _ in rows)
    ta = sum(a["time"] for _, a in rows)
    n = len(rows)
    out.append(f"\n{n} states: before {tb:.2f} s = {tb / ub:.1f} units (mean {tb / n:.3f} s "
               f"per state), after {ta:.2f} s = {ta / ua:.1f} units (mean {ta / n:.3f} s); "
               f"speed-up {tb / ta:.2f}.  (rel dT, da2: the P2 and P3 discretisation errors, "
               "see section 3.)\n")
    return ta / n, tb / n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, few alphas")
    parser.add_argument("--before", default=BEFORE, help="commit to compare against")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve:
        serve()
        return
    curve = LEVER_ALPHAS if args.quick else CURVE
    out = [f"# FEM heated steady state: speed before ({args.before}) and after (issue 16)\n",
           "Single-threaded BLAS on a shared 2-core machine: compare within a row; "
           "'units' are yardsticks (10 LU of 1000 x 1000) of the same worker.\n"]
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp)
        archive = subprocess.run(["git", "archive", args.before, "kinetic_fem"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        before, after = Worker(old), Worker(ROOT)
        ub = float(before.ask("yardstick"))  # type: ignore[arg-type]
        ua = float(after.ask("yardstick"))  # type: ignore[arg-type]
        kernel = after.ask("kernel", sizes=SIZES[:3] if args.quick else SIZES,
                           old_tree=str(old))
        report_kernel(kernel, ua, out)  # type: ignore[arg-type]
        print("kernel done", flush=True)
        rows = []
        for alpha in curve:
            best: list[dict] = [{}, {}]
            for _ in range(2):
                for i, w in enumerate((before, after)):
                    r = w.ask("solve", alpha=alpha)
                    assert isinstance(r, dict)
                    if not best[i] or r["time"] < best[i]["time"]:
                        best[i] = dict(r, alpha=alpha)
            rows.append((best[0], best[1]))
        ub = min(ub, float(before.ask("yardstick")))  # type: ignore[arg-type]
        ua = min(ua, float(after.ask("yardstick")))  # type: ignore[arg-type]
        mean_after, mean_before = report_solves(rows, (ub, ua), out)
        print("solves done", flush=True)
        lines = []
        for alphas, label in ((curve, f"{len(curve)}-point"),
                              ([] if args.quick else CURVE100, "100-point")):
            if not alphas:
                continue
            for warm in (None, True):
                tb = before.ask("curve", alphas=alphas, warm=warm)
                ta = after.ask("curve", alphas=alphas, warm=warm)
                assert isinstance(tb, dict) and isinstance(ta, dict)
                how = "pointwise kf.solve_heated" if warm is None else "heated_curve(warm)"
                lines.append(f"| {label} | {how} | {tb['time']:.2f} s = {tb['time'] / ub:.1f} "
                             f"| {ta['time']:.2f} s = {ta['time'] / ua:.1f} | "
                             f"{tb['time'] / ta['time']:.2f} |")
        out.append("Curves (seconds = yardstick units):\n")
        out.append("| curve | how | before | after | speed-up |")
        out.append("|---|---|---|---|---|")
        out += lines + [""]
        print("curves done", flush=True)
        out.append("## 3. Accuracy of the defaults against P3 at 0.8 times the P2 spacing\n")
        out.append("Relative errors of T and a2 and max |df/f| where f > 1e-30; before: the "
                   "P2 default (equal to the old code's to 1e-14), after: the P3 default.\n")
        out.append("| alpha | ref nodes | nodes P2 | nodes P3 | dT P2 | dT P3 | da2 P2 | "
                   "da2 P3 | df P2 | df P3 | P3 <= P2 |")
        out.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for alpha in curve:
            r = after.ask("accuracy", alpha=alpha)
            assert isinstance(r, dict)
            p2, p3 = r["p2"], r["p3"]
            ok = all(p3[k] <= p2[k] for k in ("dT", "da2", "df"))
            out.append(f"| {alpha:.4f} | {r['ref_nodes']} | {p2['nodes']} | {p3['nodes']} | "
                       f"{p2['dT']:.1e} | {p3['dT']:.1e} | {p2['da2']:.1e} | {p3['da2']:.1e} | "
                       f"{p2['df']:.1e} | {p3['df']:.1e} | {'yes' if ok else 'NO'} |")
        out.append("")
        print("accuracy done", flush=True)
        names = ["all on", "P3 off (P2)", "sequencing off", "chord-predicted stop off",
                 "chord off"]
        out.append("## 4. Levers one at a time (after; seconds, best of two, Newton steps)\n")
        out.append("| alpha | " + " | ".join(names) + " |")
        out.append("|---|" + "---|" * len(names))
        for alpha in LEVER_ALPHAS:
            cells = []
            for name in names:
                rs = [after.ask("lever", name=name, alpha=alpha) for _ in range(2)]
                r = min(rs, key=lambda x: x.get("time", np.inf))  # type: ignore[union-attr]
                assert isinstance(r, dict)
                cells.append(f"{r['time']:.3f} ({r['newton']})" if "time" in r else r["error"])
            out.append(f"| {alpha} | " + " | ".join(cells) + " |")
        out.append("")
        print("levers done", flush=True)
        out.append("## 5. Other kernels, the bath, and the cooling state\n")
        out.append("| gamma | alpha | friction | nodes | before / s | after / s | speed-up | "
                   "rel dT | rel da2 |")
        out.append("|---|---|---|---|---|---|---|---|---|")
        means = []
        for gamma, alpha, xi in OTHERS[:4] if args.quick else OTHERS:
            rb = before.ask("solve", alpha=alpha, gamma=gamma, friction=xi)
            ra = after.ask("solve", alpha=alpha, gamma=gamma, friction=xi)
            assert isinstance(rb, dict) and isinstance(ra, dict)
            if "error" in ra or "error" in rb:
                out.append(f"| {gamma} | {alpha} | {xi} | | {rb.get('error', rb.get('time'))} "
                           f"| {ra.get('error', ra.get('time'))} | | | |")
                continue
            means.append((rb["time"], ra["time"]))
            out.append(f"| {gamma} | {alpha} | {xi} | {ra['nodes']} | {rb['time']:.3f} | "
                       f"{ra['time']:.3f} | {rb['time'] / ra['time']:.2f} | "
                       f"{abs(ra['T'] / rb['T'] - 1):.1e} | "
                       f"{abs(ra['a2'] / rb['a2'] - 1):.1e} |")
        mb = float(np.mean([m[0] for m in means]))
        ma = float(np.mean([m[1] for m in means]))
        out.append(f"\nmean over these: before {mb:.3f} s, after {ma:.3f} s; over them and the "
                   f"hard-rod curve: before {(mb + mean_before) / 2:.3f} s = "
                   f"{(mb + mean_before) / 2 / ub:.2f} units, after {(ma + mean_after) / 2:.3f}"
                   f" s = {(ma + mean_after) / 2 / ua:.2f} units\n")
        out.append("Cooling state `kf.solve_cooling(alpha, method='fem')` (solver files "
                   "unchanged; it shares the pair kernel):\n")
        out.append("| alpha | before / s | after / s | speed-up | rel da2 |")
        out.append("|---|---|---|---|---|")
        for alpha in COOLING[:2] if args.quick else COOLING:
            rb = before.ask("cooling", alpha=alpha)
            ra = after.ask("cooling", alpha=alpha)
            assert isinstance(rb, dict) and isinstance(ra, dict)
            if "error" in ra or "error" in rb:
                out.append(f"| {alpha} | {rb.get('error', rb.get('time'))} | "
                           f"{ra.get('error', ra.get('time'))} | | |")
                continue
            out.append(f"| {alpha} | {rb['time']:.3f} | {ra['time']:.3f} | "
                       f"{rb['time'] / ra['time']:.2f} | {abs(ra['a2'] / rb['a2'] - 1):.1e} |")
        out.append(f"\nyardstick: before worker {ub:.3f} s, after worker {ua:.3f} s\n")
        before.close()
        after.close()
    text = "\n".join(out)
    print(text)
    results = ROOT / "benchmarks" / "archive" / "results"
    results.mkdir(exist_ok=True)
    (results / ("fem_speed_quick.md" if args.quick else "fem_speed.md")).write_text(text + "\n")


if __name__ == "__main__":
    main()
