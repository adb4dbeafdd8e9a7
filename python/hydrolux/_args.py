"""The argument checks every call of the package shares, and the declared options' machinery.

Private: the public names are hydrolux's (``import hydrolux``). Every argument is checked by type here
(numbers, strings, flags, pairs, paths) or in _core (whole numbers with their ranges, arrays); the
options of the frame jobs come from the library's one table of declared parameters (``_declared``) and
reach each function's signature and docstring through ``_with_options``.
"""
from __future__ import annotations

import functools
import inspect
import math
import os
import warnings
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np

from hydrolux import _core, _xarray

ArrayLike = Union[float, Sequence[float], np.ndarray]


# ---- arguments ------------------------------------------------------------------------------------
# Every argument is checked by type here (numbers, strings, flags, pairs) or in _core (whole numbers
# with their ranges, arrays), never laundered through int() / float() / bool() / str(): a bad one is a
# one-line TypeError or ValueError naming it, its value (short, never an array's contents) and what
# is valid.

# A value as an error message shows it: short, and never an array's or a container's contents (the
# same words as the bindings' own messages).
_describe = _core.describe


_REALS = (int, float, np.integer, np.floating)


def _real(value: Any, name: str) -> float:
    """One real number (not a bool); +-inf past a float's range, for the range check that follows."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]
    if isinstance(value, _REALS) and not isinstance(value, (bool, np.bool_)):
        try:
            return float(value)
        except OverflowError:
            return math.inf if value > 0 else -math.inf
    raise TypeError(f"{name}: expected a number, got {_describe(value)}")


def _opt_real(value: Any, name: str) -> Optional[float]:
    return None if value is None else _real(value, name)


def _complex(value: Any, name: str) -> complex:
    """One complex number (a real one too)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iufc":
        value = value[()]
    if isinstance(value, _REALS + (complex, np.complexfloating)) and not isinstance(value, (bool, np.bool_)):
        try:
            return complex(value)
        except OverflowError:
            raise ValueError(f"{name}: {_describe(value)} is beyond what a double holds (about 1e308)") from None
    raise TypeError(f"{name}: expected one complex number such as 1.333+1e-8j, got {_describe(value)}")


def _reals(value: Any, name: str) -> np.ndarray:
    """Numbers of any shape: an ndarray as it is (_core checks its dtype and copies it, MemoryError
    when the copy cannot be made), anything else through numpy as float64. Text is never a number
    here (``["10"]`` is a TypeError, as ``"10"`` is)."""
    if isinstance(value, np.ndarray):
        return value
    expected = f"{name}: expected a number or an array of numbers, got {_describe(value)}"
    if value is None or isinstance(value, (str, bytes, complex, np.complexfloating)):
        raise TypeError(expected)
    try:
        a = np.asarray(value)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(expected) from None
    if a.dtype.kind in "USO" and any(isinstance(v, (str, bytes, np.str_, np.bytes_)) for v in a.flat):
        raise TypeError(f"{expected} holding text")
    if a.dtype.kind not in "biufO":
        raise TypeError(f"{expected} of {a.dtype}")
    try:
        return np.asarray(value, dtype=np.float64)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(expected) from None


def _rgb(value: Any, name: str) -> list:
    """Three finite non-negative real numbers (linear R, G, B): a list, a tuple or a 1-D array of 3.
    Text, a set, a bool or a number is a TypeError; a sequence or array of numbers of another length
    or shape ((3, 1)), or a negative or non-finite value, a ValueError: each naming the argument."""
    what = "three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85)"
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "iuf":
            raise TypeError(f"{name}: expected {what}, got {_describe(value)}")
        if value.shape != (3,):  # numbers, but not three of them
            raise ValueError(f"{name}: expected {what}, got {_describe(value)}")
        items = list(value)
    elif isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise ValueError(f"{name}: expected {what}, got a {type(value).__name__} of {len(value)}")
        items = list(value)
    else:
        raise TypeError(f"{name}: expected {what}, got {_describe(value)}")
    out = []
    for k, v in enumerate(items):
        x = _real(v, f"{name}[{k}]")
        if not (math.isfinite(x) and x >= 0):
            raise ValueError(f"{name}[{k}] = {x:g} is not a finite value >= 0 (linear light); expected {what}")
        out.append(x)
    return out


def _text(value: Any, name: str, valid: str) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected a string ({valid}), got {_describe(value)}")
    return value


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, got {_describe(value)}")
    return bool(value)


def _pair(value: Any, name: str, what: str) -> tuple:
    """Two values, (A, B) or [A, B] or a 1-D array of two; their own checks follow."""
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return (value[0], value[1])
    if isinstance(value, np.ndarray) and value.shape == (2,):
        return (value[0], value[1])
    raise TypeError(f"{name}: expected {what}, got {_describe(value)}")


def _history(function: Any, arguments: dict) -> str:
    """A CF history line for a call of ``function`` (``hydrolux.<its name>``) with these arguments
    (those that differ from the signature's defaults), as a labelled form's ``history`` attribute
    states it."""
    defaults = {name: p.default for name, p in inspect.signature(function).parameters.items()
                if p.default is not inspect.Parameter.empty}
    return _xarray.history(_xarray.call_text(function.__name__, arguments, defaults))


def _path(value: Any, name: str) -> bytes:
    """A file path as the file system's bytes: str, bytes or os.PathLike, so that a name that is not
    UTF-8 (os.listdir gives it as surrogate escapes, os.fsencode back) reaches the file as the CLI's
    would."""
    if isinstance(value, (str, bytes)) or isinstance(value, os.PathLike):
        path = os.fspath(value)
        if isinstance(path, (str, bytes)):
            return os.fsencode(path)
    raise TypeError(f"{name}: expected a file path (str, bytes or pathlib.Path), got {_describe(value)}")


def _array_arg(value: Any, name: str) -> np.ndarray:
    """An image argument as an ndarray (_core checks its shape and dtype, naming it)."""
    if isinstance(value, np.ndarray):
        return value
    try:
        return np.asarray(value)
    except OverflowError:
        raise ValueError(f"{name}: holds a number beyond what a double holds (about 1e308)") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected an array (height, width[, channels]), got {_describe(value)}") from None


_MEDIUM = "a name from media() or 'const:1.49'"


# ---- declared options ----------------------------------------------------------------------------

def _declared(job: str, *groups: str) -> list:
    """A job's declared parameters (the library's one table, hydrolux/jobs.hpp) of the given groups."""
    return [p for p in _core.params(job) if p["group"] in groups]


def _options_doc(params: list) -> str:
    """The options' reference for a docstring, from the declared table: name, range, default, help."""
    lines = []
    for p in params:
        valid = "True or False" if p["kind"] == "flag" else p["form"]
        default = f"; default {p['default']!r}" if p["default"] is not None else ""
        # A switch's help is its CLI flag's, which turns the default around (--no-unresolved).
        what = f"{not p['default']}: {p['help']}" if p["kind"] == "flag" else p["help"]
        old = f" (``{p['deprecated']}`` before: deprecated)" if p.get("deprecated") else ""
        lines.append(f"    ``{p['name']}`` ({valid}{default}): {what}{old}")
    return "\n".join(lines)


def _deprecated_keyword(kw: dict, old: str, now: str, unit: str, stacklevel: int = 2) -> dict:
    """``kw`` with the keyword ``old``, a parameter's name before it was renamed ``now`` (kept for one
    release), given as ``now``, with one DeprecationWarning naming ``now`` (the library's words, as the
    CLI says it for the old flag); both given is a TypeError naming both. ``stacklevel`` as
    warnings.warn counts it from the caller of this function."""
    if old not in kw:
        return kw
    if kw.get(now) is not None:
        raise TypeError(f"{old}: give {now} or {old} ({now}'s deprecated name), not both")
    kw = dict(kw)
    kw.pop(now, None)
    kw[now] = kw.pop(old)
    warnings.warn(_core.deprecation_warning(old, now, unit), DeprecationWarning, stacklevel=stacklevel + 1)
    return kw


def _renamed(params: list, kw: dict, stacklevel: int = 2) -> dict:
    """The options ``kw`` of a function taking ``**options`` with each declared parameter's deprecated
    name (``p["deprecated"]``) given as its name, each with its warning (:func:`_deprecated_keyword`;
    ``stacklevel`` 2: at the line that called the function calling this one)."""
    for p in params:
        if p.get("deprecated"):
            kw = _deprecated_keyword(kw, p["deprecated"], p["name"], p["unit"], stacklevel + 1)
    return kw


# The Python type of each kind of declared parameter (hydrolux/core/params.hpp's ParamKind).
_ANNOTATIONS = {"real": float, "integer": int, "flag": bool, "choice": str, "size": Tuple[int, int],
                "span": Tuple[float, float], "colour": Tuple[float, float, float]}


def _with_options(params: list, keep: int, positional: bool = False):
    """Gives a function taking ``**options`` the declared options as parameters in its signature
    (help(), IDEs and inspect show them) and their reference at the end of its docstring. The
    options are keyword-only, or with ``positional`` may also be given by position after the first
    ``keep`` parameters (for functions whose options always could be); either way the function
    receives only the options given, and the library fills in the rest from the same table."""
    def wrap(fn):
        sig = inspect.signature(fn)
        head = [q for q in sig.parameters.values() if q.kind != q.VAR_KEYWORD][:keep]
        # A parameter another replaces (focal_mm by fov_deg) shows None: either may be given.
        replaced = {p["excludes"] for p in params if p["excludes"]}
        kind = inspect.Parameter.POSITIONAL_OR_KEYWORD if positional else inspect.Parameter.KEYWORD_ONLY
        opts = [inspect.Parameter(p["name"], kind, default=None if p["name"] in replaced else p["default"],
                                  annotation=_ANNOTATIONS[p["kind"]])
                for p in params]
        full = sig.replace(parameters=head + opts)
        doc = (fn.__doc__ or "").rstrip() + "\n\n    Options (the CLI's flags of the same names):\n\n" + \
            _options_doc(params) + "\n"
        if not positional:
            fn.__signature__, fn.__doc__ = full, doc
            return fn
        names = [q.name for q in head]

        @functools.wraps(fn)
        def call(*args, **kw):
            bound = full.bind(*args, **kw)
            given = bound.arguments
            return fn(**{n: given[n] for n in names if n in given}, **{k: v for k, v in given.items() if k not in names})

        call.__signature__, call.__doc__ = full, doc
        return call
    return wrap

