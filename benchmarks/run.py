"""The one entry point of the maintained benchmarks: list them, run one, or run a kind.

    python benchmarks/run.py                    # the table: name, kind, what it measures
    python benchmarks/run.py speed [--quick]    # every benchmark of a kind, one after another
    python benchmarks/run.py NAME [ARGS ...]    # one benchmark with its own arguments

Kinds: ``speed`` (CPU time of the public calls and kernels, in yardstick units or against
the C yardstick), ``convergence`` (observed orders under refinement, one per solver),
``validation`` (methods against each other, exact results and the paper) and ``study``
(physics tables and figures the docs cite).  ``--quick`` is passed to the scripts that
take it; the others run at their own sizes.  Each script writes or prints its own table
(``benchmarks/results/README.md`` says which file each one writes).

The before/after studies of past rounds live in ``benchmarks/archive/`` beside their
results: they are kept for the record, not maintained, linted or listed here.
``tests/test_benchmarks.py`` checks that this table and the folder agree.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

KINDS = ("speed", "convergence", "validation", "study")

#: name -> (kind, takes --quick)
BENCHMARKS: dict[str, tuple[str, bool]] = {
    # speed
    "bench_targets": ("speed", True),
    "bench_end_to_end": ("speed", False),
    "bench_dsmc": ("speed", True),
    "bench_md": ("speed", True),
    "bench_sweep": ("speed", True),
    "bench_md_yardstick": ("speed", False),
    "bench_md_mixture": ("speed", False),
    "bench_dsmc_mixture": ("speed", False),
    "bench_fem_mixture": ("speed", False),
    "bench_fem_mixture_accuracy": ("speed", False),
    "bench_mixture_transient": ("speed", True),
    "bench_transient_speed": ("speed", False),
    "bench_first_hour": ("speed", True),
    "error_estimate_cost": ("speed", False),
    # convergence: one per solver
    "convergence_heated": ("convergence", True),
    "convergence_fem_cooling": ("convergence", True),
    "convergence_fem_cooling_band": ("convergence", False),
    "convergence_gamma2_cooling": ("convergence", False),
    "convergence_maxwell_hcs": ("convergence", False),
    "convergence_cooling": ("convergence", False),
    "convergence_fd": ("convergence", False),
    "convergence_spectral": ("convergence", False),
    "convergence_scaling": ("convergence", False),
    "convergence_transient": ("convergence", True),
    "convergence_dsmc": ("convergence", True),
    "convergence_fem_mixture": ("convergence", False),
    "convergence_fem_mixture_cooling": ("convergence", False),
    "convergence_fem_mixture_laws": ("convergence", False),
    "convergence_mixture_spectral": ("convergence", False),
    # validation
    "cross_validation": ("validation", True),
    "validate_dsmc": ("validation", True),
    "fem_model_table": ("validation", True),
    "dsmc_model_table": ("validation", True),
    "saturating_kernel": ("validation", False),
    "quasi_elastic_cooling": ("validation", False),
    "heated_near_elastic": ("validation", False),
    "relaxation_spectrum": ("validation", False),
    "relaxation_dsmc": ("validation", False),
    "cooling_transient": ("validation", False),
    "calibrate_error_estimates": ("validation", True),
    "calibrate_mixture_errors": ("validation", False),
    "regime_bitwise": ("validation", False),
    "fem_mixture_dsmc": ("validation", False),
    # studies
    "effective_exponent_peak": ("study", False),
    "memory_effects": ("study", False),
    "cooling_protocol": ("study", False),
    "mixture_temperature_ratio": ("study", False),
}

#: scripts of this folder that are not benchmarks (this runner, shared helpers, the
#: command that regenerates the package's stored gamma = 2 states)
NOT_BENCHMARKS = ("run", "yardstick", "gamma2_anchors")


def summary(name: str) -> str:
    """The first line of a benchmark's docstring."""
    doc = ast.get_docstring(ast.parse((HERE / f"{name}.py").read_text())) or ""
    return doc.strip().splitlines()[0] if doc.strip() else ""


def table() -> str:
    """The maintained benchmarks, by kind."""
    lines = []
    for kind in KINDS:
        lines.append(f"{kind}:")
        for name, (k, quick) in BENCHMARKS.items():
            if k == kind:
                flag = " [--quick]" if quick else ""
                lines.append(f"  {name:30s}{flag:10s} {summary(name)}")
    return "\n".join(lines)


def run(name: str, args: list[str]) -> int:
    """Run one benchmark as a script; its exit status."""
    return subprocess.call([sys.executable, str(HERE / f"{name}.py"), *args])


def main(argv: list[str] | None = None) -> int:
    """The command line (module docstring)."""
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("-h", "--help", "list"):
        print(__doc__ if argv[:1] in (["-h"], ["--help"]) else table())
        return 0
    target, rest = argv[0], argv[1:]
    if target in KINDS:
        quick = "--quick" in rest
        status = 0
        for name, (kind, takes_quick) in BENCHMARKS.items():
            if kind == target:
                print(f"== {name}", flush=True)
                status = max(status, run(name, ["--quick"] if quick and takes_quick else []))
        return status
    if target not in BENCHMARKS:
        print(f"unknown benchmark or kind {target!r}; one of {', '.join(KINDS)} or a name of "
              "`python benchmarks/run.py list`", file=sys.stderr)
        return 2
    return run(target, rest)


if __name__ == "__main__":
    sys.exit(main())
