"""The MD rows of issue 31 against the shared C yardstick, in the same run.

For each row: the public call with default options (collisions per CPU second of
the whole call), the event loop alone (:meth:`particles.md.MDEngine.advance` from the
same initial state to the same collision count, no stops), and the yardstick
``shared/yardstick/md_edmd.c`` built here with ``gcc -O3 -march=native`` (its own
printed figure: free cooling ``coll_per_s``, sampling excluded; heated ``without
bursts: coll_per_s_total``, kicks included), alternately, ``--repeat`` times each;
the median and the range are printed, with the ratios of the medians.  Also the
a2 error bar per CPU second (``a2_error * sqrt(CPU s)``) of the public call.

Rows (``--rows``): ``cool`` ``md.simulate_cooling(0.9, 5000, collisions_per_particle=1000,
threshold=1e-6, seed=1)`` vs ``md_edmd mode=cool N=5000 alpha=0.9 coll=2.5e6``;
``heat`` ``md.simulate_heated(0.9, 5000, collisions_per_particle=2000, seed=1)`` vs
``md_edmd mode=heat N=5000 alpha=0.9 coll=5e6``; ``large``
``md.simulate_cooling(0.99, 100000, collisions_per_particle=200, seed=1)`` vs
``md_edmd mode=cool N=100000 alpha=0.99 coll=1e7`` (the same 200 collisions per particle).

Run ``python benchmarks/bench_md_yardstick.py [--rows cool heat large] [--repeat 3]``
(from a worktree: ``PYTHONPATH=<worktree>``).  CPU time (``time.process_time``; the
yardstick's thread CPU time); ratios within one run are what count on a shared machine.
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from particles import _md_run as R
from particles import md

YARDSTICK = Path(__file__).resolve().parents[2] / "shared" / "yardstick" / "md_edmd.c"
if not YARDSTICK.exists():  # worktrees live one level deeper than the main checkout
    YARDSTICK = Path("/work/shared/yardstick/md_edmd.c")

ROWS: dict[str, tuple[str, Callable[[], Any], list[str], str]] = {
    "cool": ("md.simulate_cooling(0.9, 5000, collisions_per_particle=1000, threshold=1e-6)",
             lambda: md.simulate_cooling(0.9, 5000, collisions_per_particle=1000,
                                         threshold=1e-6, seed=1),
             ["mode=cool", "N=5000", "alpha=0.9", "coll=2.5e6"], r"coll_per_s=([0-9.e+]+)"),
    "heat": ("md.simulate_heated(0.9, 5000, collisions_per_particle=2000)",
             lambda: md.simulate_heated(0.9, 5000, collisions_per_particle=2000, seed=1),
             ["mode=heat", "N=5000", "alpha=0.9", "coll=5e6"],
             r"without bursts: coll_per_s_eventloop=[0-9.e+]+ coll_per_s_total=([0-9.e+]+)"),
    "large": ("md.simulate_cooling(0.99, 100000, collisions_per_particle=200)",
              lambda: md.simulate_cooling(0.99, 100000, collisions_per_particle=200, seed=1),
              ["mode=cool", "N=100000", "alpha=0.99", "coll=1e7"], r"coll_per_s=([0-9.e+]+)"),
}


def build(tmp: Path) -> Path:
    gcc = shutil.which("gcc")
    if gcc is None:
        raise RuntimeError("gcc not found")
    exe = tmp / "md_edmd"
    subprocess.run([gcc, "-O3", "-march=native", "-o", str(exe), str(YARDSTICK), "-lm"],
                   check=True)
    return exe


def run_c(exe: Path, args: list[str], pattern: str) -> float:
    out = subprocess.run([str(exe), *args, "verbose=0"], check=True, capture_output=True,
                         text=True).stdout
    m = re.search(pattern, out)
    if m is None:
        raise RuntimeError(f"no figure in the yardstick's output:\n{out}")
    return float(m.group(1))


def run_public(call: Callable[[], Any]) -> tuple[float, float, float]:
    """(collisions per CPU s, a2 error x sqrt(CPU s), a2) of one public call."""
    c0 = time.process_time()
    run = call()
    cpu = time.process_time() - c0
    return run.n_collisions / cpu, run.a2_error * cpu**0.5, run.a2


def run_kernel(name: str) -> float:
    """Collisions per CPU s of the event loop alone (same engine and initial state)."""
    captured: dict[str, Any] = {}
    real = R.run_md

    def grab(params, *, seed, y, v, rng, options, plan, checkpointing, progress):
        captured.update(y=y.copy(), v=v.copy(), rng=rng, options=options, total=plan.total)
        raise _Stop

    R.run_md = grab
    md.run_md = grab  # type: ignore[attr-defined]
    try:
        ROWS[name][1]()
    except _Stop:
        pass
    finally:
        R.run_md = real
        md.run_md = real  # type: ignore[attr-defined]
    eng = md.MDEngine(captured["y"], captured["v"], captured["options"], captured["rng"])
    c0 = time.process_time()
    eng.advance(captured["total"])
    return eng.n_collisions / (time.process_time() - c0)


class _Stop(Exception):
    pass


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rows", nargs="*", default=list(ROWS), choices=list(ROWS))
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--no-kernel", action="store_true", help="skip the event loop alone")
    a = p.parse_args()
    md.simulate_cooling(0.9, 200, collisions_per_particle=20, threshold=1e-6, seed=0)
    md.simulate_cooling(0.99, 200, collisions_per_particle=20, seed=0)
    md.simulate_heated(0.9, 200, collisions_per_particle=20, seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        exe = build(Path(tmp))
        print(f"{'row':6} {'public call':>22} {'kernel alone':>22} {'yardstick':>22} "
              f"{'public/C':>8} {'kernel/C':>8}  a2 err*sqrt(cpu s)")
        for name in a.rows:
            label, call, cargs, pattern = ROWS[name]
            pub, ker, cc, merit, a2 = [], [], [], [], []
            for _ in range(a.repeat):
                rate, m, av = run_public(call)
                pub.append(rate)
                merit.append(m)
                a2.append(av)
                if not a.no_kernel:
                    ker.append(run_kernel(name))
                cc.append(run_c(exe, cargs, pattern))

            def fmt(xs: list[float]) -> str:
                if not xs:
                    return "-"
                return f"{statistics.median(xs):.3e} ({min(xs):.2e}..{max(xs):.2e})"

            mp, mc = statistics.median(pub), statistics.median(cc)
            mk = statistics.median(ker) if ker else np.nan
            print(f"{name:6} {fmt(pub):>22} {fmt(ker):>22} {fmt(cc):>22} {mp / mc:8.3f} "
                  f"{mk / mc:8.3f}  {statistics.median(merit):.3e} (a2 {a2[0]:.5f})")
            print(f"       {label}; yardstick {' '.join(cargs)}", flush=True)


if __name__ == "__main__":
    main()
