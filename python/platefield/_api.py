"""design, verify, field, export and poses: the CLI's library calls, from Python."""

import json
import os
import tempfile

from . import _platefield
from ._errors import NativeError, raised


def _text(value):
    """A keyword value as its command-line text (floats round-trip exactly)."""
    return repr(value) if isinstance(value, float) else str(value)


def flags(options):
    """The command-line flags of keyword ``options``.

    ``name=value`` is ``--name=value`` (``_`` written ``-``; one token, so
    that a negative value is not read as a flag); ``True`` is the
    bare flag and ``False`` or ``None`` leaves it out; a list of numbers or
    names is one comma-separated value (``primitives=["sink", "squeeze"]``),
    a list of lists repeats the flag (``shift=[(0.01, 0), (0, 0.01)]``).
    """
    argv = []
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            argv.append(flag)
        elif isinstance(value, (list, tuple)):
            if value and all(isinstance(v, (list, tuple)) for v in value):
                argv += [f"{flag}={','.join(_text(x) for x in v)}" for v in value]
            else:
                argv.append(f"{flag}={','.join(_text(x) for x in value)}")
        else:
            argv.append(f"{flag}={_text(value)}")
    return argv


def _is_path(x):
    return isinstance(x, (str, os.PathLike))


def _as_file(document, folder, name):
    """(the path of ``document``, the temporary file it was written to or None):
    itself if a path, else the dict written to ``folder/name``."""
    if _is_path(document):
        return os.fspath(document), None
    if not isinstance(document, dict):
        raise TypeError(f"expected a path or a dict, got {type(document).__name__}")
    path = os.path.join(folder, name)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(document, f)
    return path, path


def _run_json(function, native, document, file_name, out, options):
    """Runs the command ``native`` on ``document`` with ``options`` and ``--json``.

    Files go to ``out`` when given, else to a temporary folder removed after.
    """
    with tempfile.TemporaryDirectory(prefix="platefield-") as tmp:
        path, temp_file = _as_file(document, tmp, file_name)
        folder = os.fspath(out) if out is not None else os.path.join(tmp, "out")
        argv = [function, path, "--out", folder] + flags(options)
        try:
            text = native(argv)
        except NativeError as e:
            raise raised(e, function, path, temp_file) from None
    return json.loads(text)


def design(target, method="auto", *, out=None, **options):
    """Designs a plate motion for ``target``: ``platefield design TARGET --json``.

    ``target`` is a target file's path or the target as a dict (the schema of
    ``targets/*.json``). ``method`` is ``"auto"``, ``"sequence"``,
    ``"synthesize"``, ``"mix"`` or ``"mirror"``. ``options`` are ``design``'s
    flags (``polish_plays=50``, ``mode="budget"``, ``budget=0.1``,
    ``quiet=True``, ...); ``friction=0.3`` or ``friction="0.2:0.4"`` replaces
    the target's friction, as ``--friction`` does. The files ``design`` writes go to ``out/<name>/``
    when ``out`` is given, else nowhere. The basis cache is
    ``./.platefield-cache`` as for the CLI (``no_cache=True``: none).

    Returns the schedule as a dict, equal to what ``design --json`` prints.

    >>> import platefield
    >>> s = platefield.design("targets/sink.json", method="sequence", quiet=True)
    >>> s["played"]["realised_shape_error"] < 0.2  # doctest: +SKIP
    True
    """
    return _run_json(
        "design", _platefield.design, target, "target.json", out,
        dict(method=method, **options),
    )


def verify(schedule, *, out=None, **options):
    """Closed-loop verification of ``schedule``: ``platefield verify SCHEDULE --json``.

    ``schedule`` is a ``schedule.json`` path or a schedule dict (what
    :func:`design` returns). ``options`` are ``verify``'s flags
    (``points=5``, ``swarm=9``, ``friction="0.2:0.4:5"``, ``quiet=True``,
    ...). Files go to ``out/<target>/verify/`` when ``out`` is given, else
    nowhere. Returns the summary dict ``verify --json`` prints.
    """
    return _run_json(
        "verify", _platefield.verify, schedule, "schedule.json", out, options,
    )


def field(scene, *, quiet=False, allow_long=False):
    """The field of ``scene`` (a scene file's path or a dict): ``platefield field``.

    Returns a dict of numpy arrays: ``fx``, ``fy`` (shape (ny, nx): m/s for
    velocity fields, N/kg for force fields), ``valid`` (ny, nx booleans),
    ``x`` (nx) and ``y`` (ny) in metres, so that ``fx[i, j]`` is the field at
    ``(x[j], y[i])``; and ``kind`` (``"velocity"`` or ``"force"``).
    """
    path, text = (os.fspath(scene), None) if _is_path(scene) else (None, json.dumps(scene))
    try:
        return _platefield.field(path, text, quiet, allow_long)
    except NativeError as e:
        raise raised(e, "field", path) from None


def export(schedule, rate=10000.0, *, steady_cycles=None, format="csv", peaks=False):
    """The schedule's six plate-centre signals: ``platefield export``.

    ``schedule`` is a ``schedule.json`` path or a schedule dict.

    ``format="csv"`` (default): the held samples at ``rate`` samples/s, an
    (n, 7) numpy array, the CSV's rows: t (s), a_x, a_y, a_z (m/s²),
    alpha_x, alpha_y, alpha_z (rad/s², the plate's angular acceleration about
    the world axes: integrate it to ω and compose the rotation, docs/shaker.md).
    ``steady_cycles``: as ``export --steady-cycles`` (default the CLI's). With ``peaks=True`` returns
    ``(rows, peaks)``: ``peaks`` is the header's dict of ``acceleration``,
    ``velocity`` and ``stroke``, six numbers each (x, y, z linear, then
    angular), of the file as played from rest.

    ``format="harmonics"`` (``export --format harmonics``; a schedule of
    one six-signal motion): a dict of ``period`` (s), ``terms`` (an (m, 4)
    array of channel 0-5, harmonic n, amplitude A, phase φ (rad): the
    channel is the sum of A·sin(n·2πt/T + φ)) and the steady motion's
    ``peaks``.

    >>> import platefield
    >>> rows, p = platefield.export("results/sink/schedule.json", peaks=True)  # doctest: +SKIP
    >>> h = platefield.export("results/sink/schedule.json", format="harmonics")  # doctest: +SKIP
    """
    if format not in ("csv", "harmonics"):
        raise ValueError(f'format must be "csv" or "harmonics", got {format!r}')
    if steady_cycles is None:
        steady_cycles = _platefield.default_steady_cycles()
    path, text = (os.fspath(schedule), None) if _is_path(schedule) else (None, json.dumps(schedule))
    try:
        if format == "harmonics":
            return _platefield.harmonics(path, text)
        rows, found = _platefield.export(path, text, float(rate), int(steady_cycles))
        return (rows, found) if peaks else rows
    except NativeError as e:
        # A dict's errors name it "schedule" (the library's origin prefix).
        raise raised(e, "export", path, None if path else "schedule") from None


def poses(part, source, *, drops=200, play=None, out=None, allow_long=False):
    """Where a part with planar extent comes to rest: ``platefield poses PART SOURCE --json``.

    ``part`` is a part file's path or a dict (the schema of
    ``targets/parts/*.json``); ``source`` a target, a scene or a designed
    schedule, as a path or a dict. ``drops``: random drops for the basin
    fractions; ``play``: seconds each drop is also played by the planar
    simulator (schedule sources only). Files (``poses.json``,
    ``poses.svg``) go to ``out`` when given, else nowhere. Played drops
    whose work estimate exceeds the limit are refused unless
    ``allow_long``, as ``--allow-long`` does.

    Returns the dict ``poses --json`` prints: ``{"equilibria": [{"x", "y",
    "theta_deg", "stable", "basin"}, ...], ...}`` (metres, degrees).
    """
    with tempfile.TemporaryDirectory(prefix="platefield-") as tmp:
        part_path, part_temp = _as_file(part, tmp, "part.json")
        source_path, source_temp = _as_file(source, tmp, "source.json")
        folder = os.fspath(out) if out is not None else None
        try:
            text = _platefield.poses(
                part_path, source_path, int(drops), play, folder, bool(allow_long)
            )
        except NativeError as e:
            # The error names the file it is about before its JSON path.
            own = e.args[1].startswith(part_path + ": ")
            file, temp = (part_path, part_temp) if own else (source_path, source_temp)
            raise raised(e, "poses", file, temp) from None
    return json.loads(text)
