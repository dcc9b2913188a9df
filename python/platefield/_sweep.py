"""sweep: many designs, targets x friction x shaker limits, serial or on Dask."""

import itertools
import json
import os

from ._api import design


def _target_dict(target):
    """``target`` as a dict: a file read (named by its stem when it has no name)."""
    if isinstance(target, dict):
        return dict(target)
    path = os.fspath(target)
    with open(path, encoding="utf-8") as f:
        t = json.load(f)
    if not str(t.get("name", "")).strip():
        t["name"] = os.path.splitext(os.path.basename(path))[0]
    return t


def jobs(targets, friction, shaker):
    """The sweep's designs in order: every target, then friction, then shaker limits.

    Each is (target dict with ``friction`` and ``shaker`` set, friction,
    shaker); ``None`` keeps the target's own.
    """
    out = []
    for t, mu, lim in itertools.product([_target_dict(t) for t in targets], friction, shaker):
        t = dict(t)
        if mu is not None:
            t["friction"] = mu
        if lim is not None:
            t["shaker"] = lim
        out.append((t, mu, lim))
    return out


def run_job(job, method, options):
    """One sweep design: the record :func:`sweep` returns for ``job``."""
    target, mu, lim = job
    return {
        "target": target.get("name", ""),
        "friction": mu,
        "shaker": lim,
        "schedule": design(target, method, **options),
    }


def sweep(targets, client=None, *, friction=(None,), shaker=(None,), method="auto", **options):
    """Designs every target at every friction and every set of shaker limits.

    ``targets``: target paths or dicts. ``friction``: the parts' friction
    values to design for (a target ``friction``: a number, ``[low, high]``
    or ``{"static": .., "kinetic": ..}``; ``None``: the target's own).
    ``shaker``: shaker limit objects (a target ``shaker``, e.g.
    ``{"linear": [20, 20, 0.1]}``; ``None``: the target's own). ``method``
    and ``options`` are :func:`design`'s (``quiet`` defaults to ``True``).

    With ``client`` (a ``dask.distributed.Client``: a ``LocalCluster`` on one
    machine, or a cluster by address) the designs run as Dask tasks, one per
    design, on the workers (which must have platefield installed); without,
    one after another here. Either way the result is the same list, in the
    order targets x friction x shaker, of dicts ``{"target", "friction",
    "shaker", "schedule"}``, ``schedule`` being :func:`design`'s dict.
    """
    options = dict(options)
    options.setdefault("quiet", True)
    todo = jobs(targets, list(friction), list(shaker))
    if client is None:
        return [run_job(j, method, options) for j in todo]
    futures = client.map(run_job, todo, method=method, options=options, pure=False)
    return client.gather(futures)
