"""End-to-end particle speed against a careful C program doing the same work (issue 13).

Run: ``python benchmarks/bench_end_to_end.py [--repeat K] [--only NAMES] [--quick]``.

For each call of the issue's table the whole public call with default options is timed
(numba compiled beforehand by a small call), collisions divided by the time, beside a C
program under ``benchmarks/c/`` built here with ``gcc -O3 -march=native`` (the binaries go
to a temporary directory, never into the tree) that does the same work: the same number
of collisions with the same algorithm (DSMC: the same candidate/acceptance scheme, the
rescaling or the ziggurat kicks, and the measurements of the default call: central
moments, histogram and power sums at every collision per particle, or at the averaging
cadence the call chose from its measured correlation time for the whole C run (the
Python call measures every collision per particle until relaxation and through its first
batch: the C side measures less); MD: event-driven hard
rods on a ring with a binary-heap event calendar, see ``benchmarks/c/md.c``).

The heated DSMC row has two C columns.  "C" is the issue's program (``dsmc heated``: the
kicks' normals and two draws per candidate from xoshiro256**, a measurement in three
passes); "C same" (``dsmc heated-wy``) is the scheme the Python call runs since issue
13 (normals and one-draw candidates from wyrand, a measurement in two passes), written
in C.  Both simulate the same physics with the same statistics (the same Strang
splitting, time step, collision process and exact Gaussian kicks); they differ in the
random-number generator and in how many passes a measurement takes.  For the other rows
"C same" is "C".  The Python
and C runs are interleaved and repeated ``K`` times; the best of each is printed, as wall
time and as CPU time (``time.process_time`` / ``getrusage`` of the child): on a shared
machine the CPU time is closer to the cost on an idle core; the load average is printed.

``--growth``: collisions per CPU second and the peak memory per particle (tracemalloc)
of the DSMC (N = 1e3 .. 1e7) and MD (1e3 .. 1e6) cooling calls, at least 2e7 collisions
a call (20 collisions per particle from N = 2e6 on); ``--growth-kinds dsmc-heated`` the
same for the heated DSMC at alpha = 0.6; ``--no-table`` skips the table.

Then the figure of merit of a user (issue 13, item 3): the standard error of the heated
``a2`` times the square root of the CPU seconds of the call (the error bar one CPU second
would give, as the error falls like one over the square root of the length), at
alpha = 0.6 and 0.9, DSMC and MD.

``--before REV``: the same rows and figure of merit with the code of git revision
``REV`` (``kinetic_fem`` and ``particles`` extracted by ``git archive`` into a temporary
directory, run in a subprocess), interleaved with this tree's and the C runs.

The shared yardstick (issue 31): the careful C programs of ``shared/yardstick/``
(``dsmc.c``, ``md_edmd.c``; found in a ``shared/yardstick`` beside the checkout or one
of its parents, or given by ``--yardstick DIR``) are built here too (``gcc -O3
-march=native``, into the temporary directory) and run in the same repetitions with the
issue's commands (:data:`YARDSTICK`); their own printed rate is the comparable figure
("incl. rescaling", "incl. heating", the whole run, "without bursts": the yardstick
splits its CPU time between phases itself).  The column "yardstick" and the ratio
"py/yard" are printed beside the C columns.  Without gcc, or without the yardstick's
sources, the C columns are skipped with a message and the Python calls still run.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# measure the working tree (the installed copy may be older), or the tree of another
# revision extracted by --before (its worker process gets BENCH_SOURCE)
sys.path.insert(0, os.environ.get("BENCH_SOURCE", str(Path(__file__).resolve().parents[1])))

from kinetic_fem.model import HeatedProblem, InelasticGas, WhiteNoise
from particles import dsmc, md

HERE = Path(__file__).resolve().parent / "c"

ROWS = {
    "dsmc_cooling": ("dsmc.simulate_cooling(0.9, 25000, collisions_per_particle=4000)",
                     lambda: dsmc.simulate_cooling(0.9, 25000, collisions_per_particle=4000,
                                                   seed=1)),
    "dsmc_heated": ("dsmc.simulate_heated(0.6, 25000, collisions_per_particle=2000)",
                    lambda: dsmc.simulate_heated(0.6, 25000, collisions_per_particle=2000,
                                                 seed=1)),
    "md_cooling": ("md.simulate_cooling(0.9, 5000, collisions_per_particle=1000, "
                   "threshold=1e-6)",
                   lambda: md.simulate_cooling(0.9, 5000, collisions_per_particle=1000,
                                               threshold=1e-6, seed=1)),
    "md_heated": ("md.simulate_heated(0.9, 5000, collisions_per_particle=2000)",
                  lambda: md.simulate_heated(0.9, 5000, collisions_per_particle=2000, seed=1)),
    "md_large": ("md.simulate_cooling(0.99, 100000, collisions_per_particle=200)",
                 lambda: md.simulate_cooling(0.99, 100000, collisions_per_particle=200,
                                             seed=1)),
}


SIZES = {"dsmc_cooling": 25000, "dsmc_heated": 25000, "md_cooling": 5000, "md_heated": 5000,
         "md_large": 100000}


# the shared yardstick's command for each row (issue 31) and the figure of its RESULT line
# that is comparable with a whole public call
YARDSTICK = {
    "dsmc_cooling": (["dsmc", "mode=cool", "N=25000", "alpha=0.9", "steps=20000"],
                     r"incl\. rescaling:.*?coll_per_s=(\S+)"),
    "dsmc_heated": (["dsmc", "mode=heat", "N=25000", "alpha=0.6", "steps=20000"],
                    r"incl\. heating:.*?coll_per_s=(\S+)"),
    "md_cooling": (["md_edmd", "mode=cool", "N=5000", "alpha=0.9", "coll=2.5e6"],
                   r"coll_per_s=(\S+)"),
    "md_heated": (["md_edmd", "mode=heat", "N=5000", "alpha=0.9", "coll=5e6"],
                  r"without bursts:.*?coll_per_s_total=(\S+)"),
    "md_large": (["md_edmd", "mode=cool", "N=100000", "alpha=0.99", "coll=1e7"],
                 r"coll_per_s=(\S+)"),
}


def find_yardstick(given: str | None) -> Path | None:
    """The directory of the shared yardstick's sources, or None (with a message)."""
    if given:
        cands = [Path(given)]
    else:
        root = Path(__file__).resolve().parents[1]
        cands = [p / "shared" / "yardstick" for p in (root, *root.parents)]
    for d in cands:
        if (d / "dsmc.c").is_file() and (d / "md_edmd.c").is_file():
            return d
    print("shared yardstick not found (dsmc.c, md_edmd.c in shared/yardstick beside the "
          "checkout or above it; --yardstick DIR): its columns are skipped")
    return None


def build(tmp: Path, yardstick: Path | None = None) -> dict[str, Path]:
    """Compile the C programs (and the yardstick's) into ``tmp``; name -> executable.

    Without gcc nothing is built (a message says so) and the C columns stay empty.
    """
    gcc = shutil.which("gcc")
    if gcc is None:
        print("gcc not found: the C programs and the yardstick are skipped, only the "
              "Python calls are timed")
        return {}
    srcs = sorted(HERE.glob("*.c"))
    if yardstick is not None:
        srcs += [yardstick / "dsmc.c", yardstick / "md_edmd.c"]
    out = {}
    for src in srcs:
        name = ("yard_" if src.parent != HERE else "") + src.stem
        exe = tmp / name
        subprocess.run([gcc, "-O3", "-march=native", "-o", str(exe), str(src), "-lm"],
                       check=True)
        out[name] = exe
    return out


def time_yardstick(exes: dict[str, Path], name: str) -> float:
    """Collisions per CPU second the yardstick prints for row ``name`` (NaN if not built)."""
    args, pattern = YARDSTICK[name]
    exe = exes.get("yard_" + args[0])
    if exe is None:
        return math.nan
    out = subprocess.run([str(exe), *args[1:]], check=True, capture_output=True,
                         text=True).stdout
    line = next(x for x in out.splitlines() if x.startswith("RESULT"))
    found = re.search(pattern, line)
    if found is None:
        raise RuntimeError(f"no rate {pattern!r} in the yardstick's line {line!r}")
    return float(found.group(1))


def c_args(name: str, run) -> list[str]:
    """Arguments of the C program doing the work of ``run`` (row ``name``)."""
    n, coll = SIZES[name], run.n_collisions
    # the averaging cadence the call chose (collisions per particle, sample_every = 1)
    every = str(int(round(run.info.extra.get("average_every", 1.0))))
    if name == "dsmc_cooling":
        return ["dsmc", "cooling", str(n), "0.9", str(coll), "1", every]
    if name == "dsmc_heated":
        t_ref = HeatedProblem.from_parameters(0.6).temperature_estimate()
        return ["dsmc", "heated", str(n), "0.6", str(coll), "1", repr(t_ref), every]
    alpha = {"md_cooling": 0.9, "md_heated": 0.9, "md_large": 0.99}[name]
    kind = "heated" if name == "md_heated" else "cooling"
    if kind == "cooling":
        return ["md", kind, str(n), repr(alpha), str(coll), "1",
                "1e-6" if name == "md_cooling" else "0"]
    # md.simulate_heated's scales: the model at the reduced ring's density n/(1 - n sigma)
    t_est = HeatedProblem(InelasticGas(alpha, 2.0), WhiteNoise(1.0)).temperature_estimate()
    return ["md", kind, str(n), repr(alpha), str(coll), "1",
            repr(md.HEATED_THRESHOLD * math.sqrt(t_est)), repr(t_est)]


def c_args_same(name: str, run) -> list[str]:
    """Arguments of the C program running the Python call's own scheme (see the module
    docstring): ``dsmc heated-wy`` for the heated DSMC row, else as :func:`c_args`."""
    args = c_args(name, run)
    if name == "dsmc_heated":
        args[1] = "heated-wy"
    return args


def time_c(exes: dict[str, Path], args: list[str]) -> tuple[float, float, int]:
    """(wall, cpu, collisions) of one C run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run([str(exes[args[0]]), *args[1:]], check=True, capture_output=True,
                         text=True).stdout.split()
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, int(out[0])


def time_py(call) -> tuple[float, float, object]:
    """(wall, cpu, run) of one public call."""
    t0, c0 = time.perf_counter(), time.process_time()
    run = call()
    return time.perf_counter() - t0, time.process_time() - c0, run


def warm_up() -> None:
    """Compile every kernel the rows use (small calls, not timed)."""
    dsmc.simulate_cooling(0.9, 500, collisions_per_particle=20, seed=0)
    dsmc.simulate_heated(0.6, 500, collisions_per_particle=20, seed=0)
    md.simulate_cooling(0.9, 200, collisions_per_particle=20, threshold=1e-6, seed=0)
    md.simulate_cooling(0.99, 200, collisions_per_particle=20, seed=0)
    md.simulate_heated(0.9, 200, collisions_per_particle=20, seed=0)


def measure_rows(names: list[str]) -> dict[str, list[float]]:
    """name -> [collisions, wall, cpu] of one call of each row (this process's code)."""
    out = {}
    for name in names:
        wall, cpu, run = time_py(ROWS[name][1])
        out[name] = [run.n_collisions, wall, cpu]
        out[name + ":c_args"] = c_args(name, run)  # type: ignore[assignment]
        out[name + ":c_same"] = c_args_same(name, run)  # type: ignore[assignment]
    return out


MERIT = {
    "dsmc 0.6": lambda cpp, seed: dsmc.simulate_heated(0.6, 25000, collisions_per_particle=cpp,
                                                       seed=seed),
    "dsmc 0.9": lambda cpp, seed: dsmc.simulate_heated(0.9, 25000, collisions_per_particle=cpp,
                                                       seed=seed),
    "dsmc cool": lambda cpp, seed: dsmc.simulate_cooling(0.9, 25000,
                                                         collisions_per_particle=4 * cpp,
                                                         seed=seed),
    "md 0.6": lambda cpp, seed: md.simulate_heated(0.6, 5000, collisions_per_particle=2 * cpp,
                                                   seed=seed),
    "md 0.9": lambda cpp, seed: md.simulate_heated(0.9, 5000, collisions_per_particle=2 * cpp,
                                                   seed=seed),
}


def measure_merit(cpp: float, seeds: int = 1) -> dict[str, list[float]]:
    """label -> [a2, se(a2), cpu, se * sqrt(cpu), its standard error] of the runs of the
    figure of merit, averaged over seeds 2 .. 1 + ``seeds`` (the batch error of one run
    scatters by about 16 %)."""
    out = {}
    for label, call in MERIT.items():
        rows = []
        for seed in range(2, 2 + seeds):
            c0 = time.process_time()
            run = call(cpp, seed)
            cpu = time.process_time() - c0
            rows.append([run.a2, run.a2_error, cpu, run.a2_error * math.sqrt(cpu)])
        mean = [sum(r[k] for r in rows) / len(rows) for k in range(4)]
        spread = (math.sqrt(sum((r[3] - mean[3]) ** 2 for r in rows) / (len(rows) - 1)
                            / len(rows)) if len(rows) > 1 else math.nan)
        out[label] = mean + [spread]
    return out


def before_worker(ref: str, tmp: Path) -> Path:
    """Extract ``kinetic_fem`` and ``particles`` of git revision ``ref`` into ``tmp``."""
    root = Path(__file__).resolve().parents[1]
    archive = subprocess.run(["git", "-C", str(root), "archive", ref, "kinetic_fem",
                              "particles"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tmp)], input=archive, check=True)
    return tmp


def run_before(src: Path, names: list[str], merit_cpp: float, seeds: int = 1) -> dict:
    """The rows (and the figure of merit) with the code under ``src``, in a subprocess."""
    env = {**os.environ, "BENCH_SOURCE": str(src)}
    out = subprocess.run([sys.executable, __file__, "--json", "--only", *names,
                          "--error-cpp", str(merit_cpp), "--merit-seeds", str(seeds)],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.splitlines()[-1])


def table(names: list[str], repeat: int, exes: dict[str, Path], before: Path | None,
          merit_cpp: float, seeds: int = 1) -> None:
    """Interleaved repetitions: before (subprocess), this tree, C; best of each."""
    best: dict[str, dict[str, float]] = {k: {} for k in names}
    merit: dict[str, dict[str, list[float]]] = {"before": {}, "after": {}}

    def keep(b: dict[str, float], key: str, coll: float, wall: float, cpu: float) -> None:
        b[key + "_coll"] = coll
        b[key + "_wall"] = min(b.get(key + "_wall", math.inf), wall)
        b[key + "_cpu"] = min(b.get(key + "_cpu", math.inf), cpu)

    def keep_merit(which: str, res: dict[str, list[float]]) -> None:
        for label, row in res.items():
            old = merit[which].get(label)
            if old is None or row[2] < old[2]:
                merit[which][label] = row

    for rep in range(repeat):
        if before is not None:
            res = run_before(before, names, merit_cpp if rep == 0 else 0.0, seeds)
            for name in names:
                keep(best[name], "before", *res["rows"][name])
            keep_merit("before", res["merit"])
        rows = measure_rows(names)
        if merit_cpp > 0 and rep == 0:
            keep_merit("after", measure_merit(merit_cpp, seeds))
        for name in names:
            coll, wall, cpu = rows[name]
            keep(best[name], "py", coll, wall, cpu)
            args = rows[name + ":c_args"]
            line = f"  [{rep + 1}/{repeat}] {name}: {coll} collisions, python {cpu:.2f} s cpu"
            if args[0] in exes:
                cw, cc, ccoll = time_c(exes, args)
                keep(best[name], "c", ccoll, cw, cc)
                line += f", C {cc:.2f}"
                same = rows[name + ":c_same"]
                if same != args:
                    cw, cc, ccoll = time_c(exes, same)
                    line += f", C same {cc:.2f}"
                keep(best[name], "cs", ccoll, cw, cc)
            yard = time_yardstick(exes, name)
            best[name]["yard"] = max(best[name].get("yard", 0.0), yard)
            line += f", yardstick {yard:.3g} coll/s"
            if before is not None:
                line += f", before {best[name]['before_cpu']:.2f}"
            print(line, flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; "
          f"best of {repeat}; collisions per CPU second")
    head = (f"{'call':<78} {'before':>9} {'python':>9} {'C':>9} {'C same':>9} "
            f"{'yardstick':>9} {'before/C':>8} {'py/C':>6} {'py/C same':>9} "
            f"{'before/yard':>11} {'py/yard':>7}")
    print(head)
    for name in names:
        r = {key: best[name][key + "_coll"] / best[name][key + "_cpu"]
             if key + "_cpu" in best[name] else math.nan for key in ("before", "py", "c", "cs")}
        yard = best[name].get("yard", math.nan)
        print(f"{ROWS[name][0]:<78} {r['before']:>9.3g} {r['py']:>9.3g} {r['c']:>9.3g} "
              f"{r['cs']:>9.3g} {yard:>9.3g} {r['before'] / r['c']:>8.2f} "
              f"{r['py'] / r['c']:>6.2f} {r['py'] / r['cs']:>9.2f} "
              f"{r['before'] / yard:>11.2f} {r['py'] / yard:>7.2f}")
    print("yardstick: shared/yardstick (gcc -O3 -march=native), the issue's commands "
          "(YARDSTICK), its own printed rate; best of the repetitions")
    if merit_cpp > 0:
        print(f"\nfigure of merit: standard error of the heated a2 after one CPU second "
              f"(se * sqrt(cpu s)); DSMC N = 25000, {merit_cpp:g} collisions per particle "
              f"(dsmc cool: the cooling a2 at alpha = 0.9, {4 * merit_cpp:g}); MD N = 5000, "
              f"{2 * merit_cpp:g}; default options; mean over seeds 2..{1 + seeds}")
        print(f"{'run':>9} {'a2':>9} {'se before':>10} {'cpu before':>10} {'se after':>9} "
              f"{'cpu after':>9} {'se*sqrt(s) before':>17} {'after':>17} {'gain':>6}")
        for label in MERIT:
            af = merit["after"][label]
            bf = merit["before"].get(label, [math.nan] * 5)
            print(f"{label:>9} {af[0]:>9.5f} {bf[1]:>10.2e} {bf[2]:>10.2f} {af[1]:>9.2e} "
                  f"{af[2]:>9.2f} {bf[3]:>9.2e}+-{bf[4]:<7.1e} {af[3]:>9.2e}+-{af[4]:<7.1e} "
                  f"{bf[3] / af[3]:>6.2f}")


def growth(kind: str, sizes: list[int], cpp: float, total: float = 2e7) -> None:
    """Collisions per CPU second against N, and the peak traced memory per particle.

    The rate is from a call of ``max(cpp, 2 total / N)`` collisions per particle (at
    least ``total`` collisions, so that the fixed cost of a call does not dominate at
    small N); the memory is the peak of ``tracemalloc`` (numpy's arrays are traced) over
    a call of ``cpp`` collisions per particle, divided by N.
    """
    import tracemalloc

    def call(n: int, c: float):
        if kind == "dsmc":
            return dsmc.simulate_cooling(0.9, n, collisions_per_particle=c, seed=3)
        if kind == "dsmc-heated":
            return dsmc.simulate_heated(0.6, n, collisions_per_particle=c, seed=3)
        return md.simulate_cooling(0.9, n, collisions_per_particle=c, threshold=1e-6, seed=3)

    what = "heated alpha = 0.6" if kind == "dsmc-heated" else "cooling alpha = 0.9"
    print(f"\n{kind} {what}, default options, max({cpp:g}, 2 x {total:g} / N) "
          f"collisions per particle (memory: {cpp:g})")
    print(f"{'N':>9} {'coll/particle':>13} {'coll/s (cpu)':>13} {'ns/coll':>8} "
          f"{'peak B/particle':>16}")
    for n in sizes:
        tracemalloc.start()
        call(n, cpp)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        c = max(cpp, 2.0 * total / n)
        wall, cpu, run = time_py(lambda n=n, c=c: call(n, c))
        rate = run.n_collisions / cpu
        print(f"{n:>9} {c:>13.4g} {rate:>13.3e} {1e9 / rate:>8.1f} {peak / n:>16.1f}",
              flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("--only", nargs="*", default=list(ROWS), choices=list(ROWS))
    p.add_argument("--error-cpp", type=float, default=1000.0,
                   help="collisions per particle of the figure-of-merit runs (0: skip)")
    p.add_argument("--merit-seeds", type=int, default=1,
                   help="seeds of each figure-of-merit run (mean and its standard error)")
    p.add_argument("--before", metavar="REV",
                   help="also time the code of git revision REV (same run, interleaved)")
    p.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # --before worker
    p.add_argument("--growth", action="store_true",
                   help="also collisions/s and memory per particle against N")
    p.add_argument("--growth-max", type=float, default=1e7,
                   help="largest N of the growth table (DSMC; MD stops at a tenth)")
    p.add_argument("--growth-kinds", nargs="*", default=["dsmc", "md"],
                   choices=["dsmc", "dsmc-heated", "md"], help="which growth tables")
    p.add_argument("--no-table", action="store_true", help="only the growth tables")
    p.add_argument("--yardstick", metavar="DIR",
                   help="directory of the shared yardstick's dsmc.c and md_edmd.c "
                        "(default: shared/yardstick beside the checkout or above it)")
    args = p.parse_args()
    warm_up()
    if args.json:
        rows = measure_rows(args.only)
        out = {"rows": {k: v for k, v in rows.items() if ":" not in k},
               "merit": (measure_merit(args.error_cpp, args.merit_seeds)
                         if args.error_cpp > 0 else {})}
        print(json.dumps(out))
        return
    if args.growth:
        top = int(args.growth_max)
        for kind in args.growth_kinds:
            if kind == "md":
                growth("md", [n for n in (10**3, 10**4, 10**5, 10**6) if n <= top // 10], 20.0)
            else:
                growth(kind, [n for n in (10**3, 10**4, 10**5, 10**6, 10**7) if n <= top],
                       20.0)
    if args.no_table:
        return
    with tempfile.TemporaryDirectory() as tmp:
        exes = build(Path(tmp), find_yardstick(args.yardstick))
        before = None
        if args.before:
            before = before_worker(args.before, Path(tmp))
        table(args.only, args.repeat, exes, before, args.error_cpp, args.merit_seeds)


if __name__ == "__main__":
    main()
