"""The numba cache is dropped when any kernel source of the package changes."""

from __future__ import annotations

import subprocess
import sys

from kinetic_fem.jit_cache import STAMP, ensure_fresh_cache, kernel_sources_digest


def _package(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    (pkg / "__pycache__").mkdir()
    (pkg / "kernels.py").write_text("from ._jit import jit\n")
    (pkg / "sub" / "callee.py").write_text("@jit\ndef f(x):\n    return x\n")
    (pkg / "plain.py").write_text("x = 1\n")
    return pkg


def _cached(pkg):
    files = [pkg / "__pycache__" / "kernels.f-1.py311.nbi",
             pkg / "sub" / "__pycache__" / "callee.f-1.py311.1.nbc"]
    for f in files:
        f.write_bytes(b"machine code")
    return files


def test_stale_kernels_are_removed_once_and_the_digest_stored(tmp_path):
    pkg = _package(tmp_path)
    files = _cached(pkg)
    assert ensure_fresh_cache(pkg) is True  # no stamp yet: the cache's origin is unknown
    assert not any(f.exists() for f in files)
    assert (pkg / "__pycache__" / STAMP).read_text() == kernel_sources_digest(pkg)
    files = _cached(pkg)
    assert ensure_fresh_cache(pkg, recheck=True) is False  # same sources: cache kept
    assert all(f.exists() for f in files)


def test_a_changed_callee_invalidates_every_cached_kernel(tmp_path):
    pkg = _package(tmp_path)
    ensure_fresh_cache(pkg)
    files = _cached(pkg)
    (pkg / "plain.py").write_text("x = 2\n")  # no kernel in it: cache kept
    assert ensure_fresh_cache(pkg, recheck=True) is False
    (pkg / "sub" / "callee.py").write_text("@jit\ndef f(x):\n    return 2 * x\n")
    assert ensure_fresh_cache(pkg, recheck=True) is True
    assert not any(f.exists() for f in files)


def test_the_installed_packages_stamp_matches_their_sources():
    """Importing the packages leaves their stamps equal to the current sources."""
    code = ("import pathlib, kinetic_fem, particles, particles.dsmc\n"
            "from kinetic_fem.jit_cache import STAMP, kernel_sources_digest\n"
            "for m in (kinetic_fem, particles):\n"
            "    root = pathlib.Path(m.__file__).parent\n"
            "    stamp = root / '__pycache__' / STAMP\n"
            "    assert stamp.read_text() == kernel_sources_digest(root), root\n")
    subprocess.run([sys.executable, "-c", code], check=True)
