"""pytest-xdist's schedulers replayed on given test durations, without running any test:
which worker runs which test and when each worker ends (tests/test_suite_setup.py checks the
suite's ``--dist`` with it; benchmarks/suite_schedule.py replays a whole run's measured
durations under each scheduler).

The schedulers are xdist's own classes, driven as its controller drives them: each worker
runs the tests it was sent in order, and starts one only when it holds the next one too (or
was told to shut down), as xdist's worker does (it fetches the next test before it runs the
current one, for the teardown); a steal takes back the asked tests the worker has not
fetched yet."""

from __future__ import annotations

from types import SimpleNamespace

from xdist.scheduler import LoadScheduling, WorkStealingScheduling

#: ``--dist`` names and xdist's scheduler classes replayed here.
SCHEDULERS = {"load": LoadScheduling, "worksteal": WorkStealingScheduling}


class _Worker:
    """What the schedulers see of an xdist worker: its queue, its shutdown, a steal."""

    def __init__(self, name: str, steals: list) -> None:
        self.gateway = SimpleNamespace(id=name)
        self.shutting_down = False
        self.queue: list[int] = []  # sent, not yet started
        self.steals = steals

    def send_runtest_some(self, indices) -> None:
        self.queue.extend(indices)

    def send_runtest_all(self) -> None:  # pragma: no cover - collections of < 2 per worker
        raise NotImplementedError("replay collections of at least two tests per worker")

    def shutdown(self) -> None:
        self.shutting_down = True

    def send_steal(self, indices) -> None:
        self.steals.append((self, list(indices)))

    def __repr__(self) -> str:
        return self.gateway.id


def replay(dist: str, durations: list[float], workers: int = 2) -> dict[str, list]:
    """The tests of ``durations`` (s, in the session's order) run by ``workers`` workers
    under xdist's ``dist`` scheduler (a key of ``SCHEDULERS``): per worker, the (index,
    start, end) of each test it ran, in its order."""
    if dist not in SCHEDULERS:
        raise ValueError(f"dist {dist!r}: replayed are {sorted(SCHEDULERS)}")
    if len(durations) < 2 * workers:
        raise ValueError(f"{len(durations)} tests: at least two per worker ({workers}) needed")
    config = SimpleNamespace(
        getvalue=lambda name: [f"{workers}*popen"],
        getoption=lambda name: None,  # maxschedchunk: xdist's default
    )
    quiet = SimpleNamespace(loadsched=lambda *args: None, workstealsched=lambda *args: None)
    scheduler = SCHEDULERS[dist](config, log=quiet)
    steals: list = []
    nodes = [_Worker(f"gw{k}", steals) for k in range(workers)]
    names = [f"t{i}" for i in range(len(durations))]
    for node in nodes:
        scheduler.add_node(node)
    for node in nodes:
        scheduler.add_node_collection(node, names)
    scheduler.schedule()
    clock = 0.0
    running: dict[_Worker, tuple[int, float, float]] = {}
    ran: dict[str, list] = {node.gateway.id: [] for node in nodes}
    while True:
        while steals:  # a worker gives back what it has not fetched (all but its next test)
            node, asked = steals.pop(0)
            keep = node.queue[:1] if node in running else []
            given = [i for i in node.queue[len(keep) :] if i in set(asked)]
            node.queue = [i for i in node.queue if i not in set(given)]
            scheduler.remove_pending_tests_from_node(node, given)
        for node in nodes:
            if node not in running and node.queue and (len(node.queue) > 1 or node.shutting_down):
                index = node.queue.pop(0)
                running[node] = (index, clock, clock + durations[index])
        if steals:
            continue
        if not running:
            break
        node = min(running, key=lambda n: running[n][2])
        index, start, end = running.pop(node)
        clock = end
        ran[node.gateway.id].append((index, start, end))
        scheduler.mark_test_complete(node, index, end - start)
    if sum(len(tests) for tests in ran.values()) != len(durations):
        raise RuntimeError("the replay lost tests: a scheduler's protocol not modelled here")
    return ran


def ends(ran: dict[str, list]) -> dict[str, float]:
    """Each worker's end (s) in a ``replay``."""
    return {name: max((end for _, _, end in tests), default=0.0) for name, tests in ran.items()}
