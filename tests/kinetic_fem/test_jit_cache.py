"""numba's cache: dropped when any kernel source of the package changes, kept across a
reinstall of the same sources, in a user folder when the package folder is read-only."""

from __future__ import annotations

import subprocess
import sys

import pytest

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


# A child of a virtual environment: which kinetic_fem kernels numba compiles (its
# ``numba:compile`` event fires only when a kernel is not found in the cache) while one
# kernel runs; with an argument, the installed package folder counts as read-only
# (``os.access`` says so, as for a system-wide installation; root could write anyway).
_PROBE = """\
import json, os, sys
from numba.core import event

compiled = []


class Compiled(event.Listener):
    def on_start(self, ev):
        func = getattr(ev.data.get("dispatcher"), "py_func", None)
        if str(getattr(func, "__module__", "")).split(".")[0] == "kinetic_fem":
            compiled.append(func.__module__ + "." + func.__name__)

    def on_end(self, ev):
        pass


event.register("numba:compile", Compiled())
if len(sys.argv) > 1:
    access = os.access
    os.access = lambda path, mode, *a, **k: (
        False if mode & os.W_OK and str(path).startswith(sys.argv[1]) else
        access(path, mode, *a, **k))
import kinetic_fem
from kinetic_fem.model.restitution import restitution_value

restitution_value(0, 0.5, 0.0, 1.0)
print(json.dumps({"file": kinetic_fem.__file__, "compiled": compiled,
                  "cache_dir": os.environ.get("NUMBA_CACHE_DIR")}))
"""


@pytest.mark.slow
def test_the_cache_survives_reinstalling_the_same_version(tmp_path):
    """A real ``pip install`` (non-editable) into a virtual environment, twice: a kernel
    compiled after the first install is loaded from numba's cache after the second (pip
    rewrites the sources with new time stamps and keeps the cache files it did not
    install), both with the cache beside the sources and, for a read-only package folder,
    in the user cache folder.  About a minute (three wheel builds)."""
    import json
    import os
    import shutil
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    src = tmp_path / "src"  # a clean copy: pip builds in the tree it is given
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(root / name, src / name)
    for pkg in ("kinetic_fem", "particles"):
        shutil.copytree(root / pkg, src / pkg,
                        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
                   check=True, timeout=300)
    python = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR", "NUMBA_DISABLE_JIT")}
    env["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    user_folder = tmp_path / "xdg" / "kinetic-fem" / "numba"

    def install():
        # --no-deps: the dependencies come from the system site; the build backend is
        # fetched as for any user (--no-build-isolation needs the `wheel` package)
        done = subprocess.run([python, "-m", "pip", "install", "--no-deps", "--quiet",
                               str(src)], env=env, capture_output=True, text=True,
                              timeout=900, cwd=tmp_path)
        assert done.returncode == 0, done.stdout + done.stderr

    def run(*read_only):
        done = subprocess.run([python, "-c", _PROBE, *map(str, read_only)], env=env,
                              capture_output=True, text=True, timeout=900, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout.splitlines()[-1])

    install()
    first = run()
    package = Path(first["file"]).parent
    assert package.is_relative_to(venv)  # the installed copy, not a source tree
    source = package / "model" / "restitution.py"
    assert "kinetic_fem.model.restitution.restitution_value" in first["compiled"]
    index = sorted(package.rglob("*.nbi"))
    assert index and first["cache_dir"] is None
    stamps = {p: p.stat().st_mtime_ns for p in index}
    installed = source.stat().st_mtime_ns
    install()  # the same version again
    assert source.stat().st_mtime_ns != installed  # the sources were rewritten
    second = run()
    assert second["compiled"] == []
    assert {p: p.stat().st_mtime_ns for p in index} == stamps  # loaded, not rewritten

    # read-only package folder: the kernels go to the user cache folder and stay there
    shutil.rmtree(user_folder, ignore_errors=True)
    for path in index:  # nothing to load beside the sources
        path.unlink()
    for path in package.rglob("*.nbc"):
        path.unlink()
    third = run(package)
    assert third["cache_dir"] == str(user_folder)
    assert "kinetic_fem.model.restitution.restitution_value" in third["compiled"]
    assert not list(package.rglob("*.nbi"))
    user_index = sorted(user_folder.rglob("*.nbi"))
    assert user_index
    install()
    fourth = run(package)
    assert fourth["cache_dir"] == str(user_folder) and fourth["compiled"] == []
    assert sorted(user_folder.rglob("*.nbi")) == user_index
