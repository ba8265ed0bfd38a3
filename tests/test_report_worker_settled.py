"""A report's worker starts its cases with what its imports made frozen out of the cyclic
garbage collector's walks (validation/report.py ``_settled``): a full collection in a case
then walks what the cases made, not the libraries' objects."""

import gc

from validation import report


def test_settling_freezes_what_the_process_holds_out_of_full_collections():
    """After ``_settled`` this process's objects (pytest, numpy, numba, the project: some
    10^5) are frozen and a full collection walks none of them but what was made since."""
    assert gc.get_freeze_count() == 0
    try:
        report._settled()
        frozen, walked = gc.get_freeze_count(), len(gc.get_objects())
    finally:
        gc.unfreeze()
    assert frozen > 50_000
    assert walked < frozen / 10
    assert gc.get_freeze_count() == 0


def test_a_worker_settles_after_it_ties_its_end_to_the_reports(monkeypatch):
    """The pool's initializer (``_start_worker``, the one ``_run_all`` gives its pool) ties the
    worker's end to the report's process first (a worker whose report is gone ends at once,
    before the full collection of its settling), then settles."""
    calls: list[tuple] = []
    monkeypatch.setattr(report, "_end_with", lambda parent: calls.append(("end", parent)))
    monkeypatch.setattr(report, "_settled", lambda: calls.append(("settled",)))
    report._start_worker(1234)
    assert calls == [("end", 1234), ("settled",)]
