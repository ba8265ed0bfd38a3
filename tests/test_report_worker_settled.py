"""A report's worker starts its cases with what its imports made frozen out of the cyclic
garbage collector's walks (validation/report.py ``_settled``): a full collection in a case
then walks what the cases made, not the libraries' objects."""

import gc
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor

from validation import report


def test_a_worker_freezes_what_its_imports_made():
    """A worker started as the report starts its pool holds some 10^5 frozen objects (the
    case modules, numba, scipy, matplotlib: 137k measured) and none left for a full
    collection to walk but what it made since; this process, not a worker, froze none."""
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(
        1, mp_context=context, initializer=report._start_worker, initargs=(os.getpid(),)
    ) as pool:
        frozen, walked = pool.submit(_frozen_and_walked).result(timeout=300)
    assert frozen > 50_000
    assert walked < frozen / 10
    assert gc.get_freeze_count() == 0


def _frozen_and_walked() -> tuple[int, int]:
    """(the objects frozen, those a full collection would walk) in the calling process."""
    return gc.get_freeze_count(), len(gc.get_objects())
