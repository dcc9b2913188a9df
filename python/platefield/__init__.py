"""platefield: vibration-induced friction fields on a rigid 6-DOF plate.

The Python interface to the platefield Rust crate. Every function makes the
same library call as the command-line tool, so the numbers are the CLI's:

- :func:`design` -- ``platefield design TARGET --json``, as a dict;
- :func:`verify` -- ``platefield verify SCHEDULE --json``, as a dict;
- :func:`field` -- ``platefield field SCENE``, as numpy arrays;
- :func:`export` -- ``platefield export SCHEDULE``, as an (n, 7) numpy array;
- :func:`poses` -- ``platefield poses PART SOURCE --json``, as a dict;
- :func:`sweep` -- many designs (targets x friction x shaker limits), serially
  or on a Dask ``Client``.

Keyword options are the command's flags with ``-`` written ``_``
(``polish_plays=50`` is ``--polish-plays 50``; ``quiet=True`` is
``--quiet``). Errors are :class:`Error` subclasses carrying the JSON path or
option they are about (:attr:`Error.path`). See docs/python.md.
"""

from ._api import design, export, field, poses, verify
from ._errors import (
    ContactLost,
    Error,
    InternalError,
    InvalidInput,
    NotConverged,
    PhysicalError,
    Unreachable,
)
from ._sweep import sweep

__all__ = [
    "design",
    "verify",
    "field",
    "export",
    "poses",
    "sweep",
    "Error",
    "InvalidInput",
    "PhysicalError",
    "ContactLost",
    "Unreachable",
    "InternalError",
    "NotConverged",
]
