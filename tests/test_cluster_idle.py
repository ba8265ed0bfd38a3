"""The local Dask cluster of sweeps and fits (fibreshell.cluster.dask_client) stays out of the
way of the machine: its scheduler's HTTP routes on a free port of this machine, not on 8787
(where a second cluster or a user's dashboard finds it taken and Dask warns), and its workers
polling at the idle intervals of IDLE_CONFIG (benchmarks/cluster_idle.py measures the CPU)."""

import socket
import warnings

import dask
import pytest

from fibreshell.cluster import IDLE_CONFIG, dask_client

pytestmark = pytest.mark.waits  # on LocalClusters of their own, idle by design


def _worker_config(keys):
    import dask

    return {key: dask.config.get(key) for key in keys}


def test_a_local_cluster_leaves_port_8787_alone_and_says_nothing_when_it_is_taken():
    taken = socket.socket()
    taken.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        taken.bind(("0.0.0.0", 8787))
        taken.listen()
    except OSError:
        pass  # another process holds it: taken all the same
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with dask_client(workers=1) as (client, _):
                assert client.submit(abs, -3).result() == 3
                link = client.cluster.scheduler.http_server
                ports = {s.getsockname()[1] for s in link._sockets.values()}
    finally:
        taken.close()
    assert 8787 not in ports
    assert not [w for w in caught if "8787" in str(w.message)]


def test_the_workers_poll_at_the_idle_intervals():
    with dask_client(workers=1) as (client, _):
        seen = list(client.run(_worker_config, list(IDLE_CONFIG)).values())[0]
    assert seen == IDLE_CONFIG
    assert dask.config.get("distributed.admin.tick.interval") != "500ms"  # only the cluster's
