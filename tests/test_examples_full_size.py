"""Every docs example runs at full size without a warning (issue 30, item 7).

Slow: each docs/examples/*.py runs as the full docs build runs it (as ``__main__``,
``KINETIC_FEM_DOCS_QUICK`` unset, the Agg backend) in a process of its own under
``-W error``, so that any warning fails it; a logged warning fails it too.  Seconds to
tens of CPU minutes per example; the default run checks the same scripts at their
``TEST_KWARGS`` (tests/test_examples.py).
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).parents[1] / "docs" / "examples").glob("*.py"))

# ``plt.show()`` under Agg warns that the figure cannot be shown; sphinx-gallery
# replaces it, so does this runner.
_RUN = ("import runpy, sys\n"
        "import matplotlib\n"
        "matplotlib.use('Agg')\n"
        "import matplotlib.pyplot as plt\n"
        "plt.show = lambda *args, **kwargs: None\n"
        "runpy.run_path(sys.argv[1], run_name='__main__')\n")


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_at_full_size_without_a_warning(path, tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "KINETIC_FEM_DOCS_QUICK"}
    env["MPLBACKEND"] = "Agg"
    done = subprocess.run([sys.executable, "-W", "error", "-c", _RUN, str(path)],
                          cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=4 * 3600)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Warning" not in done.stderr and "WARNING" not in done.stderr, done.stderr[-3000:]
