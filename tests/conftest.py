"""Shared test settings.

Hypothesis runs without per-example deadlines: the machine is shared and numba
compiles on first use, so wall-clock deadlines would make tests flaky.
"""

from hypothesis import settings

settings.register_profile("kinetic_fem", deadline=None, max_examples=50)
settings.load_profile("kinetic_fem")
