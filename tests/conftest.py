"""Shared test settings.

Hypothesis runs without per-example deadlines: the machine is shared and numba
compiles on first use, so wall-clock deadlines would make tests flaky.

The default profile ``kinetic_fem`` is derandomized: every run draws the same
examples, so the continuous integration cannot fail on an example nobody has seen
before.  New inputs are explored with ``HYPOTHESIS_PROFILE=explore`` (random
examples, more of them), which is how a new property test is tried before it is
committed (CONTRIBUTING.md).
"""

import os

from hypothesis import settings

settings.register_profile("kinetic_fem", deadline=None, max_examples=50, derandomize=True)
settings.register_profile("explore", deadline=None, max_examples=200)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "kinetic_fem"))
