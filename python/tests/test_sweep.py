"""sweep: serial and on a 2-worker Dask LocalCluster, the same bytes."""

import json

import pytest

import platefield

FRICTION = [0.2, 0.5]
# The first limits leave every primitive of the sink (the paper's envelope);
# the second forbid the LineSinks' x and y tilt accelerations above 100 rad/s²,
# which the sequenced sink then cannot use.
SHAKER = [None, {"angular": [100.0, 100.0, 9055.0]}]


def small_sink(root):
    t = json.loads((root / "targets" / "sink.json").read_text())
    t["grid"]["n"] = [9, 9]
    return t


def test_dask_local_cluster_equals_serial(root, scratch):
    distributed = pytest.importorskip("distributed")
    targets = [small_sink(root)]
    opts = dict(friction=FRICTION, shaker=SHAKER, method="sequence")
    serial = platefield.sweep(targets, **opts)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        parallel = platefield.sweep(targets, client=client, **opts)
    # In the order targets x friction x shaker, each designed for its own.
    assert [(r["friction"], r["shaker"]) for r in serial] == [
        (mu, lim) for mu in FRICTION for lim in SHAKER
    ]
    for r in serial:
        spec = r["schedule"]["target_spec"]
        assert spec["friction"] == r["friction"]
        assert spec.get("shaker") == r["shaker"]
    assert json.dumps(parallel) == json.dumps(serial)
    # The four designs differ: the sweep changed what was designed.
    assert len({json.dumps(r["schedule"]["segments"]) for r in serial}) == 4
