"""Every docs example runs: ``main(**TEST_KWARGS)`` of each docs/examples/*.py.

Examples are imported from their file path (they are scripts, not a package).  An
example without ``TEST_KWARGS`` or ``main`` fails with a message saying what to add.
Plotting happens only under ``__main__``, so importing one is cheap.
"""

import importlib.util
import math
import sys
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

EXAMPLES = sorted((Path(__file__).parents[1] / "docs" / "examples").glob("*.py"))


def load_example(path: Path):
    """Import an example script as a module named ``example_<stem>``."""
    name = f"example_{path.stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses and pickling look the module up here
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def test_examples_exist():
    assert any(p.name == "plot_sonine_a2.py" for p in EXAMPLES)


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs(path):
    module = load_example(path)
    assert callable(getattr(module, "main", None)), (
        f"{path.name} must define main(...) returning its result")
    assert isinstance(getattr(module, "TEST_KWARGS", None), dict), (
        f"{path.name} must define TEST_KWARGS = {{...}}: cheap keyword arguments of main() "
        "with which the test suite runs the example")
    assert module.__doc__ and module.__doc__.strip().splitlines()[1].startswith("="), (
        f"{path.name} needs a module docstring starting with an RST title (sphinx-gallery)")
    result = module.main(**module.TEST_KWARGS)
    assert result is not None, f"{path.name}: main() must return its result"


def test_sonine_a2_example_numbers():
    """The first worked example recovers a2 and gives a Gaussian no Sonine corrections."""
    module = load_example(next(p for p in EXAMPLES if p.name == "plot_sonine_a2.py"))
    result = module.main(**module.TEST_KWARGS)
    assert result.alpha.shape == (module.TEST_KWARGS["n_alpha"],)
    assert result.a2_theory[0] == pytest.approx(16 / 129)
    assert result.a2_theory[-1] == pytest.approx(-16 / 159)
    assert result.sonine.a2 == pytest.approx(result.a2_check, rel=1e-8)
    assert result.gaussian.temperature == pytest.approx(2.0, rel=1e-10)
    for p in range(2, 7):
        assert abs(result.gaussian.sonine_coefficient(p)) < 1e-8
        if p > 2:
            assert abs(result.sonine.sonine_coefficient(p)) < 1e-8
    n = result.gaussian.effective_exponent([1.0, 2.0, 3.0])
    assert all(math.isclose(x, 2.0, abs_tol=1e-6) for x in n)


def test_readme_commands_match_ci():
    """The README's two set-up commands exist, and .ci/run runs the README's test command."""
    root = Path(__file__).parents[1]
    readme = (root / "README.md").read_text()
    ci = (root / ".ci" / "run").read_text()
    main_job = "pip install . && kinetic-fem reproduce --quick --out reproduce-out"
    test_command = 'pip install ".[test,docs]" && python -m pytest'
    assert main_job in readme
    assert test_command in readme
    assert test_command in ci
    assert "python -m sphinx -W" in ci


def test_getting_started_output():
    """The output printed on the getting-started page is what docs/first_solve.py prints.

    The page shows the script (literalinclude) and its output as text; the numbers must
    stay what the script computes.  T, a2 and f are compared to the digits printed
    (round-off of the last digit allowed); the node count is compared exactly.
    """
    root = Path(__file__).parents[1]
    page = (root / "docs" / "getting_started.rst").read_text()
    block = page.split(".. code-block:: text", 1)[1].split("\n\n", 2)[1]
    documented = [line.strip() for line in block.splitlines() if line.strip()]
    script = root / "docs" / "first_solve.py"
    import contextlib
    import io
    import re
    import runpy

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        runpy.run_path(str(script), run_name="first_solve")  # not __main__: no show()
    printed = [line.strip() for line in out.getvalue().splitlines() if line.strip()]
    assert len(printed) == len(documented), (printed, documented)
    number = re.compile(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?")
    for got, doc in zip(printed, documented, strict=True):
        assert number.sub("#", got) == number.sub("#", doc), (got, doc)
        for g, d in zip(number.findall(got), number.findall(doc), strict=True):
            digits = d.split("e")[0]
            ulp = 10.0 ** -(len(digits.split(".")[1]) if "." in digits else 0)
            scale = 10.0 ** int(d.split("e")[1]) if "e" in d else 1.0
            assert abs(float(g) - float(d)) <= 1.01 * ulp * scale, (got, doc)


def test_example_titles_have_no_maths():
    """Gallery titles appear in tiles, the sidebar and the browser title: no maths there."""
    for path in EXAMPLES:
        title = load_example_doc(path).strip().splitlines()[0]
        assert ":math:" not in title and "$" not in title, f"{path.name}: maths in {title!r}"


def load_example_doc(path: Path) -> str:
    """The module docstring of an example, without running it."""
    import ast

    return ast.get_docstring(ast.parse(path.read_text())) or ""
