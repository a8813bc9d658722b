"""Argument parsing shared by the sub-commands of ``kinetic-fem``.

:class:`CommandParser` reports a mistyped option with the usage of the sub-command it
was typed in and the list of that sub-command's valid options (with the closest match);
the model options (kernel, friction, restitution law) and ``-o KEY=VALUE`` solver
options are parsed once here, and options a function does not take are named with the
list of valid names.
"""

from __future__ import annotations

import argparse
import ast
import difflib
import inspect
import logging
import os
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Sequence

from ..files import output_path
from ..options import option_names

if TYPE_CHECKING:
    from ..distribution import VelocityDistribution

__all__ = ["CommandParser", "api_default", "key_value", "split_keys", "float_list", "int_list",
           "setup_logging", "add_model_arguments", "restitution_of", "check_options",
           "check_out", "save", "PACKAGES"]

PACKAGES = ("kinetic_fem", "particles")


class CommandParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` whose errors name the valid options of its command.

    Parameters
    ----------
    *args, **kwargs
        As for ``argparse.ArgumentParser``.
    """

    def option_names(self) -> list[str]:
        """The long (or only) option string of every optional argument."""
        names = []
        for action in self._actions:
            if action.option_strings:
                longs = [s for s in action.option_strings if s.startswith("--")]
                names.append((longs or action.option_strings)[0])
        return names

    def reject_unknown(self, extra: Sequence[str]) -> None:
        """Exit with this command's usage, the unknown words and the valid options."""
        names = self.option_names()
        hints = []
        for word in extra:
            if word.startswith("-"):
                close = difflib.get_close_matches(word.split("=")[0],
                                                  [n for n in names if n != "--help"], n=1)
                if close:
                    hints.append(f"{word.split('=')[0]} -> did you mean {close[0]}?")
        hint = f" ({'; '.join(hints)})" if hints else ""
        self.error(f"unrecognized argument(s): {' '.join(extra)}{hint}\n"
                   f"valid options of '{self.prog}': {', '.join(names)}")


def key_value(text: str) -> tuple[str, object]:
    """``KEY=VALUE`` with VALUE a Python literal (number, bool, string, tuple ...).

    Parameters
    ----------
    text : str
        ``KEY=VALUE``.

    Returns
    -------
    tuple
        ``(key, value)``.

    Raises
    ------
    argparse.ArgumentTypeError
        Without ``=``.
    """
    key, sep, value = text.partition("=")
    if not sep or not key.strip().isidentifier():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        parsed: object = ast.literal_eval(value)
    except (ValueError, SyntaxError):
        parsed = value  # a plain string
    return key.strip(), parsed


def split_keys(text: str) -> list[str]:
    """Comma-separated keys (``--only F2,C5``), at least one.

    Parameters
    ----------
    text : str
        Comma-separated keys.

    Returns
    -------
    list of str

    Raises
    ------
    argparse.ArgumentTypeError
        If no key is given.
    """
    keys = [k.strip() for k in text.split(",") if k.strip()]
    if not keys:
        raise argparse.ArgumentTypeError(f"no item given in {text!r}; e.g. --only F2,C5")
    return keys


def _list_of(kind: Callable[[str], Any], what: str) -> Callable[[str], list[Any]]:
    def parse(text: str) -> list[Any]:
        """Comma-separated values of one kind (an argparse ``type``).

        Parameters
        ----------
        text : str
            The option's text, e.g. ``0.3,0.6,0.9``.

        Returns
        -------
        list

        Raises
        ------
        argparse.ArgumentTypeError
            For a value of another kind, or no value.
        """
        try:
            values = [kind(x) for x in text.split(",") if x.strip()]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected comma-separated {what}, e.g. 0.3,0.6,0.9; got {text!r}") from None
        if not values:
            raise argparse.ArgumentTypeError(f"no value in {text!r}")
        return values
    return parse


float_list = _list_of(float, "numbers")
int_list = _list_of(int, "integers")


def setup_logging(quiet: bool) -> None:
    """Log the packages to stderr at INFO (WARNING with ``--quiet``); command only.

    Parameters
    ----------
    quiet : bool
        Log warnings only.
    """
    for name in PACKAGES:
        log = logging.getLogger(name)
        for old in [h for h in log.handlers if getattr(h, "_kinetic_fem", False)]:
            log.removeHandler(old)  # a second call (tests) writes to the current stderr
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
        handler._kinetic_fem = True  # type: ignore[attr-defined]
        log.addHandler(handler)
        log.setLevel(logging.WARNING if quiet else logging.INFO)


def _law(text: str) -> tuple[str, float | None]:
    kind, _, value = text.partition(":")
    kind = kind.strip().lower()
    if kind == "constant" and not value:
        return kind, None
    if kind in ("threshold", "viscoelastic") and value:
        try:
            return kind, float(value)
        except ValueError:
            pass
    raise argparse.ArgumentTypeError(
        f"expected constant, threshold:SPEED or viscoelastic:DELTA, got {text!r}")


def api_default(function: Callable[..., Any], name: str) -> Any:
    """The default of keyword ``name`` of ``function``: the CLI takes the API's defaults.

    Parameters
    ----------
    function : callable
        A public function (``kf.solve_heated`` ...).
    name : str
        One of its keyword parameters.

    Returns
    -------
    object
        The default value.

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> api_default(kf.solve_cooling, "method")
    'fem'
    """
    return inspect.signature(function).parameters[name].default


def add_model_arguments(parser: argparse.ArgumentParser, *, heated: bool,
                        alpha: bool = True) -> None:
    """``alpha`` (positional), ``--restitution``, ``--kernel`` and (heated) ``--friction``.

    Their defaults are those of :func:`kinetic_fem.solve_heated` (heated) or
    :func:`kinetic_fem.solve_cooling`.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    heated : bool
        Add the heated gas's ``--diffusion`` and ``--friction``.
    alpha : bool
        Add the positional ``alpha``.
    """
    from ..solve import solve_cooling, solve_heated

    api = solve_heated if heated else solve_cooling
    if alpha:
        parser.add_argument("alpha", type=float, nargs="?", default=None,
                            help="restitution coefficient, 0 <= alpha < 1 (not with "
                                 "--restitution viscoelastic:DELTA)")
        parser.add_argument("--restitution", type=_law, default=("constant", None),
                            metavar="LAW",
                            help="constant (default: alpha), threshold:SPEED (elastic below "
                                 "the relative speed SPEED, alpha above) or viscoelastic:DELTA "
                                 "(Brilliantov-Poeschel law)")
    parser.add_argument("--kernel", type=float, default=api_default(api, "kernel"),
                        metavar="GAMMA",
                        help="collision kernel |g|^GAMMA, 0 <= GAMMA <= 2 (default "
                             "%(default)s; 1: hard rods, 0: Maxwell model)")
    parser.add_argument("--density", type=float, default=api_default(api, "density"),
                        metavar="N",
                        help="number density n > 0 (default: %(default)s)")
    if heated:
        parser.add_argument("--diffusion", type=float, default=api_default(api, "diffusion"),
                            metavar="D",
                            help="noise strength D > 0 (default: %(default)s)")
        parser.add_argument("--friction", type=float, default=api_default(api, "friction"),
                            metavar="XI",
                            help="friction xi >= 0 of a Fokker-Planck bath, bath temperature "
                                 "D/xi (default %(default)s; 0: white noise, the paper)")


def restitution_of(args: argparse.Namespace) -> Any:
    """``alpha`` as a float or a restitution law, from ``alpha`` and ``--restitution``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    float or RestitutionLaw
    """
    from ..model import ThresholdRestitution, ViscoelasticRestitution

    kind, value = args.restitution
    if kind == "viscoelastic":
        if args.alpha is not None:
            raise ValueError("give either alpha or --restitution viscoelastic:DELTA, not both "
                             "(the viscoelastic law sets alpha(g) itself)")
        return ViscoelasticRestitution(value)
    if args.alpha is None:
        raise ValueError("alpha is required (e.g. 0.9), unless --restitution "
                         "viscoelastic:DELTA is given")
    return args.alpha if kind == "constant" else ThresholdRestitution(args.alpha, value)


def check_options(function: Callable[..., Any], options: dict[str, Any], what: str,
                  exclude: Sequence[str] = ()) -> None:
    """Raise ValueError naming options ``function`` does not take, and the valid names.

    Parameters
    ----------
    function : callable
        The function the options are passed to.
    options : dict
        The ``-o KEY=VALUE`` options.
    what : str
        Name of the function in the message.
    exclude : sequence of str
        Names that are not options here (e.g. grid dimensions).

    Raises
    ------
    ValueError
        Naming the unknown options and the valid ones.
    """
    names = option_names(function)  # its parameters and its option objects' fields
    if names is None:
        return
    valid = sorted(n for n in names if n not in exclude)
    unknown = sorted(set(options) - set(valid))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown} for {what}; valid -o names: {valid}")


def check_out(out: Path | None, suffixes: Sequence[str] | None = None) -> None:
    """Check ``--out`` before any computation: its suffix, and that it can be written.

    Parameters
    ----------
    out : Path or None
        The ``--out`` file.
    suffixes : sequence of str, optional
        The allowed suffixes (default: ``.npz`` and :data:`kinetic_fem.io.FORMATS`).

    Raises
    ------
    ValueError
        For another suffix.
    OSError
        If the directory does not exist or is not writable
        (:func:`kinetic_fem.files.output_path`).
    """
    from .. import io

    suffixes = (".npz", *io.FORMATS) if suffixes is None else suffixes
    if out is not None and out.suffix not in suffixes:
        raise ValueError(f"--out must end in {', '.join(suffixes)}; got {str(out)!r}")
    if out is not None:
        output_path(out, name="--out")


def save(dist: VelocityDistribution, out: Path) -> Path:
    """Write ``dist`` as ``.npz`` (:meth:`VelocityDistribution.save`) or VTU/XDMF.

    Parameters
    ----------
    dist : VelocityDistribution
        The result.
    out : Path
        Destination: ``.npz``, ``.vtu`` or ``.xdmf``.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    OSError
        If ``out`` cannot be written; the result is then saved in the temporary
        directory and the message names that file.
    """
    from .. import io

    try:
        return dist.save(out) if out.suffix == ".npz" else io.write_distribution(dist, out)
    except OSError as err:  # the directory vanished, the disk is full: keep the result
        fallback = Path(tempfile.gettempdir()) / f"kinetic-fem-{os.getpid()}.npz"
        raise OSError(f"--out {str(out)!r} could not be written ({err}); the result is "
                      f"saved in {str(dist.save(fallback))!r}") from err
