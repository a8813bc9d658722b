"""Options that travel together: typed objects, and the keywords that name their fields.

A solver takes the options that belong together (a mesh's degree, spacing and cut-off;
Newton's tolerance and iteration limit) as one frozen dataclass, and still takes each of
them by keyword, as users pass them (``kf.solve_heated(0.5, spacing=0.2)``).  One rule
turns the keywords into the object and refuses the names it does not know
(:func:`gather`); :func:`option_names` lists every name a function takes, its own
parameters and the fields of its option objects, for the command line's check of
``-o KEY=VALUE``.
"""

from __future__ import annotations

import dataclasses
import inspect
import typing
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

__all__ = ["gather", "option_names"]

T = TypeVar("T")


def gather(cls: type[T], given: T | None, keywords: Mapping[str, Any], where: str) -> T:
    """``given`` (or the defaults of ``cls``) with the fields that ``keywords`` name.

    Parameters
    ----------
    cls : dataclass type
        The options' class.
    given : cls, optional
        The options passed as one object.
    keywords : mapping
        Fields of ``cls`` passed by keyword (they override ``given``).
    where : str
        The function's name, for the message.

    Returns
    -------
    cls

    Raises
    ------
    TypeError
        For a keyword that is not a field of ``cls``, naming the allowed ones.

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Mesh:
    ...     order: int = 2
    ...     spacing: float | None = None
    >>> gather(Mesh, None, {"spacing": 0.1}, "solve")
    Mesh(order=2, spacing=0.1)
    >>> gather(Mesh, Mesh(order=3), {"spacing": 0.1}, "solve")
    Mesh(order=3, spacing=0.1)
    >>> gather(Mesh, None, {"spacnig": 0.1}, "solve")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    TypeError: solve() got an unexpected keyword argument 'spacnig'; its Mesh options ...
    """
    names = [f.name for f in dataclasses.fields(cls)]  # type: ignore[arg-type]
    unknown = sorted(set(keywords) - set(names))
    if unknown:
        raise TypeError(f"{where}() got an unexpected keyword argument {unknown[0]!r}; its "
                        f"{cls.__name__} options are {names}")
    if given is None:
        return cls(**keywords)
    if not isinstance(given, cls):
        raise TypeError(f"{where}() takes its options as a {cls.__name__}, got "
                        f"{type(given).__name__}")
    return dataclasses.replace(given, **keywords)  # type: ignore[type-var]


def option_names(function: Callable[..., Any]) -> list[str] | None:
    """The keywords ``function`` takes: its named parameters, and for a ``**keywords``
    parameter the fields of its dataclass-typed parameters.

    Parameters
    ----------
    function : callable

    Returns
    -------
    list of str or None
        Sorted names; None if ``function`` takes any keyword (a ``**keywords`` parameter
        with no option object to name them) or has no signature.
    """
    try:
        params = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return None
    names = {n for n, p in params.items()
             if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}
    if not any(p.kind is p.VAR_KEYWORD for p in params.values()):
        return sorted(names)
    try:
        hints = typing.get_type_hints(function)
    except Exception:  # noqa: BLE001 (unresolvable annotations: no names to add)
        return None
    groups = [arg for name in names for arg in typing.get_args(hints.get(name)) or
              (hints.get(name),) if dataclasses.is_dataclass(arg) and isinstance(arg, type)]
    if not groups:
        return None
    for group in groups:
        names |= {f.name for f in dataclasses.fields(group)}
    return sorted(names)
