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


def test_a_read_only_package_caches_in_the_user_folder(tmp_path, monkeypatch):
    import numba.core.config

    from kinetic_fem import jit_cache

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(numba.core.config, "CACHE_DIR", numba.core.config.CACHE_DIR)
    pkg = _package(tmp_path)
    assert jit_cache.configure_cache_dir(pkg) is None  # writable: numba's own __pycache__
    monkeypatch.setattr(jit_cache.os, "access", lambda path, mode: False)
    folder = jit_cache.configure_cache_dir(pkg)
    assert folder == tmp_path / "cache" / "kinetic-fem" / "numba"
    assert jit_cache.os.environ["NUMBA_CACHE_DIR"] == str(folder)
    assert numba.core.config.CACHE_DIR == str(folder)
    assert jit_cache.configure_cache_dir(pkg) is None  # set now: kept


def test_the_users_numba_cache_dir_wins_and_is_kept_fresh(tmp_path, monkeypatch):
    from numba.core.caching import _CacheLocator

    from kinetic_fem import jit_cache

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "mine"))
    monkeypatch.setattr(jit_cache.os, "access", lambda path, mode: False)
    pkg = _package(tmp_path)
    assert jit_cache.configure_cache_dir(pkg) is None
    sub = _CacheLocator.get_suitable_cache_subpath(str(pkg / "sub" / "callee.py"))
    assert tmp_path / "mine" / sub in jit_cache.cache_folders(pkg)
    (tmp_path / "mine" / sub).mkdir(parents=True)
    stale = tmp_path / "mine" / sub / "callee.f-1.py311.nbi"
    stale.write_bytes(b"machine code")
    assert ensure_fresh_cache(pkg) is True and not stale.exists()
    stale.write_bytes(b"machine code")
    assert ensure_fresh_cache(pkg, recheck=True) is False and stale.exists()


def _first_and_second_run(tmp_path, code, *flags):
    env = {**__import__("os").environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    return [subprocess.run([sys.executable, *flags, "-c", code], env=env, capture_output=True,
                           text=True, check=True, timeout=300) for _ in range(2)]


_KERNEL = ("from kinetic_fem.model.restitution import restitution_value\n"
           "restitution_value(0, 0.5, 0.0, 1.0); restitution_value(0, 0.5, 0.0, 2.0)\n")
_NOTICE = "kinetic-fem: compiling kernels, once per install, about"


def test_the_first_compilation_is_announced_once_and_is_no_warning(tmp_path):
    """With progress shown: one line on stderr when a kernel is compiled, none when it is
    cached; not a warning (a run under ``-W error`` passes)."""
    code = "from kinetic_fem.progress import resolve_progress; resolve_progress(True)\n" + _KERNEL
    runs = _first_and_second_run(tmp_path, code, "-W", "error")
    assert runs[0].stderr.count(_NOTICE) == 1, runs[0].stderr
    assert "Warning" not in runs[0].stderr
    assert _NOTICE not in runs[1].stderr


def test_the_compilation_notice_is_quiet_without_progress_but_logged(tmp_path):
    """progress=False: no line on stderr; the INFO record is there for a logging setup,
    once (not also as a line)."""
    quiet = "from kinetic_fem.progress import resolve_progress; resolve_progress(False)\n"
    logged = ("import logging; logging.basicConfig(level=logging.INFO, format='LOG %(message)s')\n"
              "from kinetic_fem.progress import resolve_progress; resolve_progress(True)\n")
    assert _NOTICE not in _first_and_second_run(tmp_path / "q", quiet + _KERNEL)[0].stderr
    err = _first_and_second_run(tmp_path / "l", logged + _KERNEL)[0].stderr
    assert err.count(_NOTICE) == 1 and err.count("LOG " + _NOTICE) == 1, err
