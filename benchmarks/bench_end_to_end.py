"""End-to-end particle speed against a careful C program doing the same work (issue 13).

Run: ``python benchmarks/bench_end_to_end.py [--repeat K] [--only NAMES] [--quick]``.

For each call of the issue's table the whole public call with default options is timed
(numba compiled beforehand by a small call), collisions divided by the time, beside a C
program under ``benchmarks/c/`` built here with ``gcc -O3 -march=native`` (the binaries go
to a temporary directory, never into the tree) that does the same work: the same number
of collisions with the same algorithm (DSMC: the same candidate/acceptance scheme, the
rescaling or the ziggurat kicks, and the measurements of the default call: central
moments, histogram and power sums at every collision per particle; MD: event-driven hard
rods on a ring with a binary-heap event calendar, see ``benchmarks/c/md.c``).  The Python
and C runs are interleaved and repeated ``K`` times; the best of each is printed, as wall
time and as CPU time (``time.process_time`` / ``getrusage`` of the child): on a shared
machine the CPU time is closer to the cost on an idle core; the load average is printed.

``--growth``: collisions per CPU second and the peak memory per particle (tracemalloc)
of the DSMC (N = 1e3 .. 1e7) and MD (1e3 .. 1e6) cooling calls at 20 collisions per
particle.

Then the figure of merit of a user (issue 13, item 3): the standard error of the heated
``a2`` times the square root of the CPU seconds of the call (the error bar one CPU second
would give, as the error falls like one over the square root of the length), at
alpha = 0.6 and 0.9.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# measure the working tree (the installed copy may be older)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

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


def build(tmp: Path) -> dict[str, Path]:
    """Compile the C programs into ``tmp``; returns name -> executable."""
    gcc = shutil.which("gcc")
    if gcc is None:
        raise RuntimeError("gcc not found: the C side of the comparison needs it")
    out = {}
    for src in sorted(HERE.glob("*.c")):
        exe = tmp / src.stem
        subprocess.run([gcc, "-O3", "-march=native", "-o", str(exe), str(src), "-lm"],
                       check=True)
        out[src.stem] = exe
    return out


def c_args(name: str, run) -> list[str]:
    """Arguments of the C program doing the work of ``run`` (row ``name``)."""
    n, coll = SIZES[name], run.n_collisions
    if name == "dsmc_cooling":
        return ["dsmc", "cooling", str(n), "0.9", str(coll), "1"]
    if name == "dsmc_heated":
        t_ref = HeatedProblem.from_parameters(0.6).temperature_estimate()
        return ["dsmc", "heated", str(n), "0.6", str(coll), "1", repr(t_ref)]
    alpha = {"md_cooling": 0.9, "md_heated": 0.9, "md_large": 0.99}[name]
    kind = "heated" if name == "md_heated" else "cooling"
    if kind == "cooling":
        return ["md", kind, str(n), repr(alpha), str(coll), "1",
                "1e-6" if name == "md_cooling" else "0"]
    # md.simulate_heated's scales: the model at the reduced ring's density n/(1 - n sigma)
    t_est = HeatedProblem(InelasticGas(alpha, 2.0), WhiteNoise(1.0)).temperature_estimate()
    return ["md", kind, str(n), repr(alpha), str(coll), "1",
            repr(md.HEATED_THRESHOLD * math.sqrt(t_est)), repr(t_est)]


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


def table(names: list[str], repeat: int, exes: dict[str, Path]) -> None:
    best: dict[str, dict[str, float]] = {k: {} for k in names}
    for rep in range(repeat):
        for name in names:  # interleaved: Python, then C, row by row
            wall, cpu, run = time_py(ROWS[name][1])
            coll = run.n_collisions
            b = best[name]
            b["coll"] = coll
            b["py_wall"] = min(b.get("py_wall", math.inf), wall)
            b["py_cpu"] = min(b.get("py_cpu", math.inf), cpu)
            if c_args(name, run)[0] in exes:
                cw, cc, ccoll = time_c(exes, c_args(name, run))
                b["c_coll"] = ccoll
                b["c_wall"] = min(b.get("c_wall", math.inf), cw)
                b["c_cpu"] = min(b.get("c_cpu", math.inf), cc)
            print(f"  [{rep + 1}/{repeat}] {name}: {coll} collisions, python {wall:.2f} s "
                  f"wall / {cpu:.2f} s cpu" + (f", C {cw:.2f} / {cc:.2f}" if "c_cpu" in b
                                               else ""), flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; "
          f"best of {repeat}; collisions per second (wall | CPU)")
    print(f"{'call':<78} {'python':>17} {'C':>17} {'py/C (cpu)':>10}")
    for name in names:
        b = best[name]
        py = f"{b['coll'] / b['py_wall']:.2e}|{b['coll'] / b['py_cpu']:.2e}"
        if "c_cpu" in b:
            c = f"{b['c_coll'] / b['c_wall']:.2e}|{b['c_coll'] / b['c_cpu']:.2e}"
            ratio = (b["coll"] / b["py_cpu"]) / (b["c_coll"] / b["c_cpu"])
            print(f"{ROWS[name][0]:<78} {py:>17} {c:>17} {ratio:>10.2f}")
        else:
            print(f"{ROWS[name][0]:<78} {py:>17} {'-':>17} {'-':>10}")


def error_per_cpu_second(cpp: float) -> None:
    """Standard error of the heated a2 scaled to one CPU second, alpha = 0.6 and 0.9."""
    print(f"\nheated DSMC, N = 25000, {cpp:g} collisions per particle, default options")
    print(f"{'alpha':>6} {'a2':>10} {'se(a2)':>10} {'cpu s':>7} {'se*sqrt(cpu)':>13}")
    for alpha in (0.6, 0.9):
        c0 = time.process_time()
        run = dsmc.simulate_heated(alpha, 25000, collisions_per_particle=cpp, seed=2)
        cpu = time.process_time() - c0
        print(f"{alpha:>6} {run.a2:>10.5f} {run.a2_error:>10.2e} {cpu:>7.2f} "
              f"{run.a2_error * math.sqrt(cpu):>13.2e}")


def growth(kind: str, sizes: list[int], cpp: float) -> None:
    """Collisions per CPU second against N, and the peak traced memory per particle.

    The memory is the peak of ``tracemalloc`` (numpy's arrays are traced) over the whole
    call, divided by N; the rate is from a second, untraced call.
    """
    import tracemalloc
    call = {"dsmc": lambda n: dsmc.simulate_cooling(0.9, n, collisions_per_particle=cpp,
                                                      seed=3),
            "md": lambda n: md.simulate_cooling(0.9, n, collisions_per_particle=cpp,
                                                threshold=1e-6, seed=3)}[kind]
    print(f"\n{kind} cooling alpha = 0.9, {cpp:g} collisions per particle, default options")
    print(f"{'N':>9} {'coll/s (cpu)':>13} {'ns/coll':>8} {'peak B/particle':>16}")
    for n in sizes:
        tracemalloc.start()
        call(n)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        wall, cpu, run = time_py(lambda n=n: call(n))
        rate = run.n_collisions / cpu
        print(f"{n:>9} {rate:>13.3e} {1e9 / rate:>8.1f} {peak / n:>16.1f}", flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("--only", nargs="*", default=list(ROWS), choices=list(ROWS))
    p.add_argument("--error-cpp", type=float, default=1000.0)
    p.add_argument("--growth", action="store_true",
                   help="also collisions/s and memory per particle against N")
    p.add_argument("--growth-max", type=float, default=1e7,
                   help="largest N of the growth table (DSMC; MD stops at a tenth)")
    args = p.parse_args()
    warm_up()
    if args.growth:
        top = int(args.growth_max)
        growth("dsmc", [n for n in (10**3, 10**4, 10**5, 10**6, 10**7) if n <= top], 20.0)
        growth("md", [n for n in (10**3, 10**4, 10**5, 10**6) if n <= top // 10], 20.0)
    with tempfile.TemporaryDirectory() as tmp:
        exes = build(Path(tmp))
        table(args.only, args.repeat, exes)
    if args.error_cpp > 0:
        error_per_cpu_second(args.error_cpp)


if __name__ == "__main__":
    main()
