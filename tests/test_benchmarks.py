"""The benchmark index (benchmarks/run.py) and the folder agree.

Every script of benchmarks/ is in the runner's table (or is the runner or a shared
helper), every entry exists and says in its docstring what it measures, and the
archive of past before/after studies stays out of the table.
"""

import ast
import importlib.util
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _runner():
    spec = importlib.util.spec_from_file_location("benchmarks_run", BENCH / "run.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_script_is_listed_and_every_entry_exists():
    runner = _runner()
    scripts = {p.stem for p in BENCH.glob("*.py")} - set(runner.NOT_BENCHMARKS)
    assert scripts == set(runner.BENCHMARKS), (
        f"not listed in benchmarks/run.py: {sorted(scripts - set(runner.BENCHMARKS))}; "
        f"listed but missing: {sorted(set(runner.BENCHMARKS) - scripts)}")
    assert {kind for kind, _ in runner.BENCHMARKS.values()} <= set(runner.KINDS)


def test_every_benchmark_says_what_it_measures():
    runner = _runner()
    for name in runner.BENCHMARKS:
        doc = ast.get_docstring(ast.parse((BENCH / f"{name}.py").read_text()))
        assert doc and doc.strip(), f"benchmarks/{name}.py needs a module docstring"
        assert runner.summary(name)


def test_the_listing_and_a_bad_name(capsys):
    runner = _runner()
    assert runner.main([]) == 0
    out = capsys.readouterr().out
    assert "speed:" in out and "bench_targets" in out
    assert runner.main(["no_such_benchmark"]) == 2
    assert "unknown benchmark" in capsys.readouterr().err
