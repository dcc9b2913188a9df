"""The exceptions of platefield, raised from the Rust library's errors."""

import re

from . import _platefield


class Error(Exception):
    """An error of platefield.

    ``path`` is the JSON path (``target.field.strength``) or the keyword
    option (``budget``) the error is about, ``""`` when it is about no one
    value; ``message`` says what is wrong and what is allowed; ``file`` is
    the input file the JSON path is in (``None`` for a dict or an option).
    """

    def __init__(self, path, message, file=None):
        self.path = path
        self.message = message
        self.file = file
        where = f"{file}: {path}" if file and path else path
        super().__init__(f"{where}: {message}" if where else message)


class InvalidInput(Error, ValueError):
    """A value is missing, misspelt, of the wrong type or out of its range."""


class PhysicalError(Error, RuntimeError):
    """The computation is physically invalid: :class:`ContactLost` or :class:`Unreachable`."""


class ContactLost(PhysicalError):
    """A part leaves the plate, or finds no steady state, where the computation needs contact."""


class Unreachable(PhysicalError):
    """No motion the method can make meets the request (no usable basis, no stable pose, ...)."""


class InternalError(Error, RuntimeError):
    """A step had nothing to work on or an internal invariant broke: a defect to report."""


class NotConverged(Error, RuntimeError):
    """An iterative solver did not converge."""


def option_name(arg):
    """``--polish-plays <POLISH_PLAYS>`` -> ``polish_plays``; other paths as they are."""
    m = re.match(r"^--([A-Za-z0-9-]+)", arg)
    return m.group(1).replace("-", "_") if m else arg


def _split(path, files):
    """(the file of ``files`` that ``path`` starts with, the rest: the JSON path)."""
    for f in files:
        if f and path.startswith(f + ": "):
            return f, path[len(f) + 2:]
    return None, path


def raised(err, function, input_file=None, temp_file=None):
    """The :class:`Error` (or ``TypeError``) for a native error of ``function``.

    The library names the input file before the JSON path; the file is taken
    off ``path`` (it starts at the JSON root, ``target.``) and kept as
    ``file``, unless it is ``temp_file``, where a dict input was written.
    """
    kind, path, message, suggestion = err.args
    if kind == "unknown":
        name = option_name(path)
        hint = f" (did you mean {option_name(suggestion)!r}?)" if suggestion else ""
        return TypeError(f"{function}() got an unexpected keyword argument {name!r}{hint}")
    file, path = _split(path, [temp_file, input_file])
    if file is not None and file == temp_file:
        file = None
    cls = {
        "invalid": InvalidInput,
        "contact_lost": ContactLost,
        "unreachable": Unreachable,
        "internal": InternalError,
        "not_converged": NotConverged,
    }
    return cls.get(kind, Error)(option_name(path), message, file)


NativeError = _platefield.NativeError
