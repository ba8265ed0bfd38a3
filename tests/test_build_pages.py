"""A model's build and the assembled stable-step bound run with numpy's advice of huge pages
held back (femcore/memory.py ``small_pages``): their large arrays are touched a few times, and
the kernel's zeroing and compaction of huge pages cost a 400k-triangle build more system time
than its own work (benchmarks/model_memory.py). The advice is numpy's again afterwards."""

import numpy as np
import pytest

pytest.importorskip("numpy._core.multiarray", reason="numpy without the huge-page switch")
from numpy._core.multiarray import _get_madvise_hugepage, _set_madvise_hugepage  # noqa: E402

import femcore.compiled  # noqa: E402
import femcore.compiled_tangent  # noqa: E402
from elements import MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from femcore.memory import small_pages  # noqa: E402
from materials import ElasticShell  # noqa: E402


@pytest.fixture
def advised():
    """numpy advising huge pages (its default on Linux) for the test, as before it after."""
    before = _set_madvise_hugepage(True)
    yield
    _set_madvise_hugepage(before)


def sheet() -> Model:
    model = Model(Mesh.rectangle(10.0, 10.0, nx=4, ny=4))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.fix("left")
    return model


def test_small_pages_holds_the_advice_back_and_gives_it_back_even_after_an_error(advised):
    with small_pages():
        assert _get_madvise_hugepage() is False
    assert _get_madvise_hugepage() is True
    with pytest.raises(RuntimeError, match="inside"), small_pages():
        raise RuntimeError("inside")
    assert _get_madvise_hugepage() is True
    _set_madvise_hugepage(False)  # a setting of the user's own is kept too
    with small_pages():
        pass
    assert _get_madvise_hugepage() is False


def test_a_model_is_built_on_small_pages_and_the_advice_restored(advised, monkeypatch):
    seen = []
    checks = femcore.compiled.check_triangles

    def spy(*args, **kwargs):
        seen.append(_get_madvise_hugepage())
        return checks(*args, **kwargs)

    monkeypatch.setattr(femcore.compiled, "check_triangles", spy)
    sheet().compile()
    assert seen == [False]
    assert _get_madvise_hugepage() is True


def test_the_assembled_stable_step_is_bounded_on_small_pages(advised, monkeypatch):
    compiled = sheet().compile()
    state = compiled.initial_state()
    mass, inertia = compiled.lumped_mass(state)
    bound = compiled.assembled_stable_dt(state, mass, inertia)
    seen = []
    largest = femcore.compiled_tangent.gershgorin_largest

    def spy(*args, **kwargs):
        seen.append(_get_madvise_hugepage())
        return largest(*args, **kwargs)

    monkeypatch.setattr(femcore.compiled_tangent, "gershgorin_largest", spy)
    again = compiled.assembled_stable_dt(state, mass, inertia)
    assert seen == [False]
    assert _get_madvise_hugepage() is True
    assert np.isfinite(bound) and again == bound


def test_holds_left_out_of_order_give_the_advice_back_once_the_last_is_left(advised):
    """Two threads building models at once enter and leave in any order: the advice is one
    setting of the process, held back while any hold is open and given back after the last
    (left first-in first-out here, as two threads can)."""
    first, second = small_pages(), small_pages()
    first.__enter__()
    second.__enter__()
    first.__exit__(None, None, None)
    assert _get_madvise_hugepage() is False  # the second build still runs
    second.__exit__(None, None, None)
    assert _get_madvise_hugepage() is True


def test_an_error_inside_a_hold_without_numpys_switch_is_raised_as_itself(monkeypatch):
    """Without numpy's switch the hold does nothing, and an error of the build comes out
    alone, not chained to the switch's missing import."""
    import femcore.memory

    monkeypatch.setattr(femcore.memory, "_hugepage_switch", lambda: None)
    with pytest.raises(ValueError, match="the build's own") as raised, small_pages():
        raise ValueError("the build's own")
    assert raised.value.__context__ is None


def test_the_mindlin_step_calibration_runs_on_small_pages(advised, monkeypatch):
    """The Mindlin cells' first stable step calibrates each reference shape on (m, 3, 3)
    temporaries (elements/mindlin.py ``cell_stable_dt``, elements/mindlin_steps.py
    ``reference_steps``): on ordinary pages too."""
    import elements.mindlin_steps

    compiled = sheet().compile()
    seen = []
    congruent = elements.mindlin_steps._congruent_cells

    def spy(*args, **kwargs):
        seen.append(_get_madvise_hugepage())
        return congruent(*args, **kwargs)

    monkeypatch.setattr(elements.mindlin_steps, "_congruent_cells", spy)
    steps = compiled.cell_stable_dt(compiled.initial_state())
    assert seen == [False]
    assert _get_madvise_hugepage() is True
    assert all(np.isfinite(s).all() for s in steps)
