"""The exceptions of platefield, raised from the Rust library's errors."""

import re

from . import _platefield


class Error(Exception):
    """An error of platefield.

    ``path`` is the JSON path (``target.field.strength``) or the keyword
    option (``budget``) the error is about, ``""`` when it is about no one
    value; ``message`` says what is wrong and what is allowed.
    """

    def __init__(self, path, message):
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}" if path else message)


class InvalidInput(Error, ValueError):
    """A value is missing, misspelt, of the wrong type or out of its range."""


class PhysicalError(Error, RuntimeError):
    """The computation is physically invalid (e.g. the part leaves the plate)."""


class NotConverged(Error, RuntimeError):
    """An iterative solver did not converge."""


def option_name(arg):
    """``--polish-plays <POLISH_PLAYS>`` -> ``polish_plays``; other paths as they are."""
    m = re.match(r"^--([A-Za-z0-9-]+)", arg)
    return m.group(1).replace("-", "_") if m else arg


def _strip(path, prefixes):
    for p in prefixes:
        if p and path.startswith(p + ": "):
            return path[len(p) + 2:]
    return path


def raised(err, function, temp_files=()):
    """The :class:`Error` (or ``TypeError``) for a native error of ``function``.

    ``temp_files`` are the files a dict input was written to: their names are
    taken off the paths, which then start at the JSON root (``target.``).
    """
    kind, path, message, suggestion = err.args
    if kind == "unknown":
        name = option_name(path)
        hint = f" (did you mean {option_name(suggestion)!r}?)" if suggestion else ""
        return TypeError(f"{function}() got an unexpected keyword argument {name!r}{hint}")
    path = option_name(_strip(path, [str(t) for t in temp_files]))
    if kind == "invalid":
        return InvalidInput(path, message)
    if kind == "physical":
        return PhysicalError(path, message)
    if kind == "not_converged":
        return NotConverged(path, message)
    return Error(path, message)


NativeError = _platefield.NativeError
