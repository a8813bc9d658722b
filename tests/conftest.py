"""Shared test settings.

Hypothesis runs without per-example deadlines: the machine is shared and numba
compiles on first use, so wall-clock deadlines would make tests flaky.

The default profile ``kinetic_fem`` is derandomized: every run draws the same
examples, so the continuous integration cannot fail on an example nobody has seen
before.  New inputs are explored with ``HYPOTHESIS_PROFILE=explore`` (random
examples, more of them), which is how a new property test is tried before it is
committed (CONTRIBUTING.md).
"""

import logging
import os

import pytest
from hypothesis import settings

settings.register_profile("kinetic_fem", deadline=None, max_examples=50, derandomize=True)
settings.register_profile("explore", deadline=None, max_examples=200)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "kinetic_fem"))


@pytest.fixture(autouse=True)
def _command_logging_removed():
    """Remove what the command's ``setup_logging`` installs, after each test.

    A CLI test leaves a handler on the package loggers bound to that test's captured
    stderr; a later test of the same process (an xdist worker runs many files) would log
    into the closed stream and print a logging error into its own captured output.
    """
    yield
    for name in ("kinetic_fem", "particles"):
        log = logging.getLogger(name)
        for handler in [h for h in log.handlers if getattr(h, "_kinetic_fem", False)]:
            log.removeHandler(handler)
        log.setLevel(logging.NOTSET)
