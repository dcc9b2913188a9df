"""Type hints of the platefield package (see __init__.py and docs/python.md)."""

import os
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

_Document = Union[str, os.PathLike[str], Mapping[str, Any]]
_Folder = Union[str, os.PathLike[str]]
_Method = Literal["auto", "sequence", "synthesize", "mix", "mirror"]
_Friction = Union[float, str]

class Error(Exception):
    path: str
    message: str
    file: Optional[str]
    def __init__(self, path: str, message: str, file: Optional[str] = ...) -> None: ...

class InvalidInput(Error, ValueError): ...
class PhysicalError(Error, RuntimeError): ...
class ContactLost(PhysicalError): ...
class Unreachable(PhysicalError): ...
class InternalError(Error, RuntimeError): ...
class NotConverged(Error, RuntimeError): ...

def design(
    target: _Document,
    method: _Method = ...,
    *,
    out: Optional[_Folder] = ...,
    friction: Optional[_Friction] = ...,
    **options: Any,
) -> dict[str, Any]: ...
def verify(schedule: _Document, *, out: Optional[_Folder] = ..., **options: Any) -> dict[str, Any]: ...
def field(scene: _Document, *, quiet: bool = ..., allow_long: bool = ...) -> dict[str, Any]: ...
@overload
def export(
    schedule: _Document,
    rate: float = ...,
    *,
    steady_cycles: Optional[int] = ...,
    format: Literal["csv"] = ...,
    peaks: Literal[False] = ...,
) -> npt.NDArray[np.float64]: ...
@overload
def export(
    schedule: _Document,
    rate: float = ...,
    *,
    steady_cycles: Optional[int] = ...,
    format: Literal["csv"] = ...,
    peaks: Literal[True],
) -> Tuple[npt.NDArray[np.float64], dict[str, list[float]]]: ...
@overload
def export(
    schedule: _Document,
    rate: float = ...,
    *,
    steady_cycles: Optional[int] = ...,
    format: Literal["harmonics"],
    peaks: bool = ...,
) -> dict[str, Any]: ...
def poses(
    part: _Document,
    source: _Document,
    *,
    drops: int = ...,
    play: Optional[float] = ...,
    out: Optional[_Folder] = ...,
    allow_long: bool = ...,
) -> dict[str, Any]: ...
def sweep(
    targets: Sequence[_Document],
    client: Any = ...,
    *,
    friction: Sequence[Any] = ...,
    shaker: Sequence[Any] = ...,
    method: _Method = ...,
    **options: Any,
) -> list[dict[str, Any]]: ...

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
