"""The first hour of a new user (issue 30, items 2-8), each figure in yardstick units.

Every figure is the CPU time of a child process (``getrusage(RUSAGE_CHILDREN)``), or of
a call in this process, divided by the machine yardstick measured in this process (CPU
seconds of 10 LU factorisations of a 1000 x 1000 matrix with single-threaded BLAS,
``yardstick.cpu_yardstick``; about 0.15 s on this machine when idle).  Children
run single-threaded (BLAS and numba), like the yardstick.

Figures:

``import``
    ``python -c "import kinetic_fem"`` and ``import kinetic_fem, particles`` (best of 3;
    a Python start-up alone is subtracted and printed separately).
``help``
    ``python -m kinetic_fem --help`` and ``python -m kinetic_fem solve-heated --help``.
``first-solve``
    ``kf.solve_heated(0.6); kf.solve_cooling(0.6)`` in a fresh process, with an empty
    numba cache (a copy of the sources in a temporary folder) and then with the cache
    that run left (warm).
``reproduce``
    ``kinetic-fem reproduce --quick`` (every item) with an empty numba cache and again
    warm; long (tens of CPU minutes on a loaded machine): run it niced, alone.
``reproduce-items``
    ``reproduce --quick`` item by item in one child process with an empty numba cache
    (``NUMBA_CACHE_DIR`` a new temporary folder): CPU seconds per item and the part
    spent compiling (numba's ``numba:compile`` events), to see which items dominate.
``features``
    The one-line results (``dist.plot()``, ``plot_f`` of a distribution / list /
    Dataset, ``to_xarray``, ``_repr_html_``), the CLI defaults against the API's, the
    sweep's validation of every value before the first point, and Ctrl-C on a CLI
    command (SIGINT to a child: exit status, traceback or not, last line of stderr):
    yes/no figures.

    python benchmarks/bench_first_hour.py [--source DIR] [--only import,help,...]

``--source DIR`` measures the ``kinetic_fem``/``particles`` of another tree (e.g. one
extracted with ``git archive``), for the before column.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import resource  # noqa: E402
import shutil  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from yardstick import cpu_yardstick  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ("import", "help", "first-solve", "features", "reproduce", "reproduce-items")


def child_cpu(cmd: list[str], source: Path, *, cwd: Path | None = None,
              env: dict[str, str] | None = None) -> tuple[float, float, int]:
    """CPU seconds (user + system) and wall seconds of a child process, and its status.

    Parameters
    ----------
    cmd : list of str
        The command.
    source : Path
        Folder put first on ``PYTHONPATH`` (holds ``kinetic_fem`` and ``particles``).
    cwd : Path, optional
        Working directory.
    env : dict, optional
        Extra environment variables.

    Returns
    -------
    tuple
        ``(cpu_seconds, wall_seconds, returncode)``.
    """
    full = {**os.environ, "PYTHONPATH": str(source), **(env or {})}
    cwd = cwd or Path(tempfile.gettempdir())  # not this tree: `python -c/-m` put cwd first
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=full, cwd=cwd, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode:
        print(f"  ! {' '.join(cmd[:6])}: status {proc.returncode}: "
              f"{proc.stderr.strip().splitlines()[-1:] }", file=sys.stderr)
    return cpu, wall, proc.returncode


def best_cpu(cmd: list[str], source: Path, repeat: int = 3) -> float:
    """Best CPU seconds of ``repeat`` runs of ``cmd``."""
    return min(child_cpu(cmd, source)[0] for _ in range(repeat))


def fresh_copy(source: Path, into: Path) -> Path:
    """Copy the two packages of ``source`` without any ``__pycache__`` (empty numba cache)."""
    for pkg in ("kinetic_fem", "particles"):
        shutil.copytree(source / pkg, into / pkg,
                        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    if (source / "pyproject.toml").exists():
        shutil.copy(source / "pyproject.toml", into / "pyproject.toml")
    return into


def measure_import(source: Path, unit: float) -> list[tuple[str, float]]:
    """Import and ``--help`` CPU seconds, in units (Python's own start-up subtracted)."""
    py = [sys.executable]
    bare = best_cpu([*py, "-c", "pass"], source)
    rows = [("python start-up alone (CPU s)", bare)]
    for label, code in [("import kinetic_fem", "import kinetic_fem"),
                        ("import kinetic_fem, particles", "import kinetic_fem, particles")]:
        cpu = best_cpu([*py, "-c", code], source)
        rows.append((f"`{label}` (CPU s, start-up included)", cpu))
        rows.append((f"`{label}` (units, start-up subtracted)", (cpu - bare) / unit))
    return rows


def measure_help(source: Path, unit: float) -> list[tuple[str, float]]:
    """``kinetic-fem --help`` and one sub-command's ``--help``."""
    rows = []
    for args in (["--help"], ["solve-heated", "--help"], ["reproduce", "--list"]):
        cpu = best_cpu([sys.executable, "-m", "kinetic_fem", *args], source)
        rows.append((f"`kinetic-fem {' '.join(args)}` (CPU s)", cpu))
        rows.append((f"`kinetic-fem {' '.join(args)}` (units)", cpu / unit))
    return rows


FIRST_SOLVE = "import kinetic_fem as kf; kf.solve_heated(0.6); kf.solve_cooling(0.6)"


def measure_first_solve(source: Path, unit: float) -> list[tuple[str, float]]:
    """The first solve with an empty numba cache, then warm (the cache it left)."""
    with tempfile.TemporaryDirectory() as tmp:
        copy = fresh_copy(source, Path(tmp))
        cold, _, _ = child_cpu([sys.executable, "-c", FIRST_SOLVE], copy)
        warm = best_cpu([sys.executable, "-c", FIRST_SOLVE], copy, repeat=2)
    return [("first `solve_heated(0.6); solve_cooling(0.6)`, empty cache (units)", cold / unit),
            ("the same, warm cache (units)", warm / unit)]


def measure_reproduce(source: Path, unit: float) -> list[tuple[str, float]]:
    """``kinetic-fem reproduce --quick``: empty numba cache, then warm."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        copy = fresh_copy(source, Path(tmp) / "src")
        for label in ("empty cache", "warm cache"):
            out = Path(tmp) / f"out-{label.split()[0]}"
            cpu, wall, status = child_cpu(
                [sys.executable, "-m", "kinetic_fem", "reproduce", "--quick", "--quiet",
                 "--out", str(out)], copy)
            print(f"  reproduce --quick, {label}: {cpu:.1f} CPU s, {wall:.0f} s wall, "
                  f"status {status}", file=sys.stderr, flush=True)
            claims = out / "claims.md"
            if claims.is_file():  # the closing summary (verdicts) of that run
                summary = claims.read_text().split("claim row(s):")[-1]
                print(f"  summary: claim row(s):{summary}", file=sys.stderr, flush=True)
            rows.append((f"`reproduce --quick`, {label} (CPU s)", cpu))
            rows.append((f"`reproduce --quick`, {label} (units)", cpu / unit))
    return rows


ITEMS = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from numba.core import event
    from kinetic_fem import reproduce
    reproduce.load_plugins()
    class Compiling(event.Listener):
        depth, t0, total = 0, 0.0, 0.0
        def on_start(self, ev):
            if self.depth == 0:
                self.t0 = time.process_time()
            self.depth += 1
        def on_end(self, ev):
            self.depth -= 1
            if self.depth == 0:
                self.total += time.process_time() - self.t0
    comp = Compiling()
    event.register("numba:compile", comp)
    ctx = reproduce.Context(out=Path(sys.argv[1]), quick=True)
    for key in sorted(reproduce.ITEMS, key=reproduce.item_order):
        c0, k0 = time.process_time(), comp.total
        rows = reproduce.run_items(ctx, [key], progress=False)
        print(key, time.process_time() - c0, comp.total - k0, len(rows), flush=True)
""")


def measure_reproduce_items(source: Path, unit: float) -> list[tuple[str, float]]:
    """Per-item CPU seconds (and compiling seconds) of ``reproduce --quick``, empty cache."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        env = {**os.environ, "PYTHONPATH": str(source), "NUMBA_CACHE_DIR": str(Path(tmp) / "nb")}
        proc = subprocess.run([sys.executable, "-c", ITEMS, str(Path(tmp) / "out")], env=env,
                              capture_output=True, text=True, check=False,
                              cwd=tempfile.gettempdir())
    total = compiling = 0.0
    for line in proc.stdout.splitlines():
        key, cpu, comp, n = line.split()
        total, compiling = total + float(cpu), compiling + float(comp)
        rows.append((f"item {key} ({n} rows): CPU s, of which compiling {float(comp):.1f}",
                     float(cpu)))
    rows.append(("all items, empty cache (units)", total / unit))
    rows.append(("all items, compiling excluded (units)", (total - compiling) / unit))
    return rows


FEATURES = textwrap.dedent("""
    import warnings
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import kinetic_fem as kf
    from kinetic_fem import plot
    d = kf.solve_heated(0.6)
    def ok(label, call):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                call()
            print(label, "yes")
        except Exception as err:
            print(label, "no:", type(err).__name__, str(err)[:60])
    ok("plot_f(dist)", lambda: plot.plot_f(d))
    ok("plot_f([dist])", lambda: plot.plot_f([d]))
    ok("dist.plot()", lambda: d.plot())
    ok("dist.to_xarray()", lambda: d.to_xarray())
    ok("plot_f(Dataset)", lambda: plot.plot_f(d.to_xarray()))
    ok("dist._repr_html_()", lambda: d._repr_html_())
    from kinetic_fem.evolution import Evolution
    w = np.gradient(d.v)
    ev = Evolution([0.0, 1.0], np.stack([d.v, d.v]), np.stack([d.values, d.values]),
                   np.stack([w, w]), method="fem")  # two states, as an evolve call returns
    ok("ev.to_xarray()", lambda: ev.to_xarray())
    ok("ev._repr_html_()", lambda: ev._repr_html_())
    print("dir(kinetic_fem) has logging/sys", "yes" if {"logging", "sys"} & set(dir(kf)) else "no")
""")


def measure_features(source: Path) -> list[tuple[str, str]]:
    """Yes/no figures: one-line results, CLI defaults, sweep validation, Ctrl-C."""
    env = {**os.environ, "PYTHONPATH": str(source)}
    rows: list[tuple[str, str]] = []
    tmp_cwd = tempfile.gettempdir()  # not this tree: `python -c/-m` put cwd first
    proc = subprocess.run([sys.executable, "-c", FEATURES], env=env, capture_output=True,
                          text=True, check=False, cwd=tmp_cwd)
    for line in proc.stdout.splitlines():
        label, _, value = line.partition(" yes") if " yes" in line else line.partition(" no")
        rows.append((label.strip(), "yes" if " yes" in line else "no" + value))
    # CLI solve-cooling method default against the API's
    code = ("import inspect, kinetic_fem as kf; from kinetic_fem.cli import build_parser; "
            "p = build_parser().commands['solve-cooling']; "
            "print(p.get_default('method'), "
            "inspect.signature(kf.solve_cooling).parameters['method'].default)")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=False, cwd=tmp_cwd)
    cli, _, api = proc.stdout.strip().partition(" ")
    rows.append(("`solve-cooling` method: CLI / API default", f"{cli} / {api}"))
    # sweep: a bad value after a good one is refused before any point runs
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "kinetic_fem", "sweep", "--alpha",
                               "0.3,1.5", "--store", str(Path(tmp) / "s"), "--quiet"],
                              env=env, capture_output=True, text=True, check=False,
                              cwd=tmp_cwd)
        points = list((Path(tmp) / "s").glob("point-*.nc"))
        rows.append(("`sweep --alpha 0.3,1.5`: points computed before the refusal",
                     f"{len(points)} (status {proc.returncode}, "
                     f"{time.perf_counter() - t0:.1f} s wall)"))
    # Ctrl-C on a CLI command: SIGINT to the process group (as a terminal sends it)
    # once the first point is stored
    with tempfile.TemporaryDirectory() as tmp:
        store = Path(tmp) / "s"
        cmd = [sys.executable, "-m", "kinetic_fem", "sweep", "--alpha",
               ",".join(f"{a:.2f}" for a in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)),
               "--method", "spectral", "--store", str(store), "--workers", "2"]
        child = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True, start_new_session=True, cwd=tmp_cwd)
        deadline = time.monotonic() + 300
        while (not list(store.glob("point-*.nc")) and time.monotonic() < deadline
               and child.poll() is None):
            time.sleep(0.2)
        t0 = time.perf_counter()
        os.killpg(child.pid, signal.SIGINT)
        out, err = child.communicate(timeout=300)
        lines = err.strip().splitlines()
        rows.append(("Ctrl-C on `sweep`: exit status, seconds to exit",
                     f"{child.returncode}, {time.perf_counter() - t0:.1f}"))
        rows.append(("Ctrl-C on `sweep`: tracebacks printed (command and workers)",
                     str(err.count("Traceback"))))
        rows.append(("Ctrl-C on `sweep`: last line of stderr",
                     (lines[-1] if lines else "").replace("|", "/")[:120]))
    return rows


def main() -> None:
    """Measure the selected figures and print them as a markdown table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", type=Path, default=ROOT,
                        help="tree holding kinetic_fem/ and particles/ (default: this one)")
    parser.add_argument("--only", default=",".join(f for f in FIGURES
                                                   if not f.startswith("reproduce")),
                        help=f"comma-separated figures among {', '.join(FIGURES)} "
                             "(default: all but the reproduce ones)")
    args = parser.parse_args()
    source = args.source.resolve()
    only = [s.strip() for s in args.only.split(",") if s.strip()]
    unit = cpu_yardstick()
    load = os.getloadavg()[0]
    print(f"source {source}; yardstick {unit:.3f} CPU s; load {load:.1f}\n")
    print("| figure | value |\n|---|---|")
    rows: list[tuple[str, object]] = []
    if "import" in only:
        rows += measure_import(source, unit)
    if "help" in only:
        rows += measure_help(source, unit)
    if "first-solve" in only:
        rows += measure_first_solve(source, unit)
    if "reproduce" in only:
        rows += measure_reproduce(source, unit)
    if "reproduce-items" in only:
        rows += measure_reproduce_items(source, unit)
    if "features" in only:
        rows += measure_features(source)
    for label, value in rows:
        print(f"| {label} | {value:.2f} |" if isinstance(value, float) else
              f"| {label} | {value} |")
    unit2 = cpu_yardstick()
    print(f"\nyardstick after: {unit2:.3f} CPU s; load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
