"""Fixtures of the particle tests."""

import os
import subprocess
import sys

import pytest


@pytest.fixture
def jit_and_plain():
    """``run(code) -> (compiled stdout, plain-Python stdout)``: ``code`` run in two fresh
    interpreters, with ``NUMBA_DISABLE_JIT`` 0 and 1 (warnings ignored)."""
    def run(code: str) -> tuple[str, str]:
        out = []
        for jit_off in ("0", "1"):
            env = dict(os.environ, NUMBA_DISABLE_JIT=jit_off)
            out.append(subprocess.run([sys.executable, "-W", "ignore", "-c", code],
                                      check=True, env=env, timeout=300, capture_output=True,
                                      text=True).stdout)
        return out[0], out[1]
    return run
