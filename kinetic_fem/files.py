"""File safety: the one error for unreadable files, and output paths checked up front.

Every loader of the package reads through :func:`read_npz` (or wraps its library in
:func:`reading`), so a damaged, truncated, foreign or edited file raises
:class:`~kinetic_fem.exceptions.FileFormatError` naming the file and what was expected,
whatever fails underneath (``zipfile.BadZipFile``, ``EOFError``, numpy's pickle
refusal, a missing key, meshio's ``SystemExit``).  :func:`output_path` checks before a
computation that its result can be written, and :func:`npz_path` is the one rule for
``.npz`` names: the path given is the path written, ``.npz`` appended only when it is
not already the suffix (``"alpha0.6"`` writes ``alpha0.6.npz``, never ``alpha0.npz``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterable

import numpy as np
from numpy.typing import NDArray

from .exceptions import FileFormatError

__all__ = ["FileFormatError", "npz_path", "output_path", "read_npz", "reading", "read_toml",
           "json_entry", "check_loaded_values"]


def npz_path(path: str | Path) -> Path:
    """``path`` as given, with ``.npz`` appended unless it already ends in ``.npz``.

    Parameters
    ----------
    path : str or Path
        The path a user gave.

    Returns
    -------
    Path

    Examples
    --------
    >>> npz_path("ck_alpha0.6").name, npz_path("run.npz").name, npz_path("a.dsmc").name
    ('ck_alpha0.6.npz', 'run.npz', 'a.dsmc.npz')
    """
    path = Path(path)
    return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")


def output_path(path: str | Path, *, name: str = "path") -> Path:
    """Check, before any work, that a file can be written at ``path``.

    Parameters
    ----------
    path : str or Path
        The file to be written (it may exist: it will be replaced).
    name : str
        The parameter or option named in the error message.

    Returns
    -------
    Path

    Raises
    ------
    FileNotFoundError
        If the directory does not exist.
    PermissionError
        If the directory or the existing file is not writable.
    IsADirectoryError
        If ``path`` is a directory.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise IsADirectoryError(f"{name}={str(path)!r} is a directory; give a file name")
    if not folder.is_dir():
        raise FileNotFoundError(f"{name}={str(path)!r}: the directory {str(folder)!r} does not "
                                "exist; create it first or choose another path")
    if not os.access(folder, os.W_OK | os.X_OK) or (path.exists() and
                                                    not os.access(path, os.W_OK)):
        raise PermissionError(f"{name}={str(path)!r} cannot be written (no permission)")
    return path


def read_toml(path: str | Path, what: str) -> dict[str, Any]:
    """The tables of a TOML file (``tomllib``; ``tomli`` on Python 3.10).

    Parameters
    ----------
    path : str or Path
    what : str
        How messages name the file, e.g. ``"--config 'grid.toml'"``.

    Returns
    -------
    dict

    Raises
    ------
    ValueError
        If the file cannot be read or is not valid TOML (naming ``what``).
    """
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib  # type: ignore[no-redef]
        except ModuleNotFoundError:
            raise ValueError(f"reading {what} on Python 3.10 needs tomli (pip install "
                             "tomli)") from None
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read {what}: {exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{what} is not valid TOML: {exc}") from exc


@contextmanager
def reading(path: str | Path, what: str) -> Iterator[None]:
    """Turn any failure of a file library inside the block into :class:`FileFormatError`.

    ``SystemExit`` is caught too (meshio exits the process on some malformed files);
    ``FileNotFoundError``, ``KeyboardInterrupt`` and our own ``FileFormatError`` pass.

    Parameters
    ----------
    path : str or Path
        The file read inside the block (named in the message).
    what : str
        What it should be, e.g. ``"VTU line mesh of kinetic_fem.io"``.
    """
    try:
        yield
    except (FileNotFoundError, FileFormatError):
        raise
    except (Exception, SystemExit) as err:  # noqa: BLE001 - the point: one error type
        detail = f"{type(err).__name__}: {err}"
        if "pickle" in str(err):  # numpy's advice to allow pickles does not apply here
            detail = "not an archive of numeric arrays; pickled objects are never loaded"
        raise FileFormatError(f"{str(path)!r} is not a readable {what} ({detail})") from err


def read_npz(path: str | Path, *, what: str, required: Iterable[str]
             ) -> dict[str, NDArray[Any]]:
    """All arrays of an ``.npz`` file, refusing pickles, damage and missing entries.

    Parameters
    ----------
    path : str or Path
        The file.
    what : str
        What the file should be (for the message), e.g. ``"VelocityDistribution .npz"``.
    required : iterable of str
        Entries that must be present.

    Returns
    -------
    dict of str to ndarray

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    FileFormatError
        If it is not a readable ``.npz`` or lacks a required entry.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{str(path)!r} does not exist")
    with reading(path, what):
        with np.load(path, allow_pickle=False) as data:
            if not isinstance(data, np.lib.npyio.NpzFile):
                raise FileFormatError(f"{str(path)!r} is a single .npy array, not a {what}")
            arrays = {k: data[k] for k in data.files}
    missing = [k for k in required if k not in arrays]
    if missing:
        raise FileFormatError(f"{str(path)!r} is not a {what}: it lacks {missing} "
                              f"(it holds {sorted(arrays)})")
    return arrays


def json_entry(arrays: dict[str, NDArray[Any]], key: str, path: str | Path, what: str
               ) -> dict[str, Any]:
    """The JSON object stored as the string array ``arrays[key]``.

    Parameters
    ----------
    arrays : dict of str to ndarray
        What :func:`read_npz` returned.
    key : str
        The entry holding the JSON text.
    path : str or Path
        The file (for the message).
    what : str
        What the file should be (for the message).

    Returns
    -------
    dict
    """
    with reading(path, what):
        out = json.loads(str(arrays[key]))
    if not isinstance(out, dict):
        raise FileFormatError(f"{str(path)!r} is not a {what}: {key!r} is not a JSON object")
    return out


def check_loaded_values(path: str | Path, **arrays: Any) -> None:
    """Refuse NaN or infinite entries in arrays read from ``path`` (names in the message).

    Parameters
    ----------
    path : str or Path
        The file the arrays came from.
    **arrays : array_like or None
        The arrays by name (None is skipped).

    Raises
    ------
    FileFormatError
        For a non-finite or non-numeric entry.
    """
    for name, a in arrays.items():
        if a is None:
            continue
        a = np.asarray(a)
        if a.dtype.kind not in "fiu" or not np.all(np.isfinite(a)):
            raise FileFormatError(f"{str(path)!r}: {name!r} holds non-finite or non-numeric "
                                  "values; the file is damaged or edited")

