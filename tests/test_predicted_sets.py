"""solvers/contact_sets.py, the ply contact's predicted active set: the rows G_i = dg_i/dq
of a predicted contact set, dense by point
(``SetRows``), against the same rows as a scipy sparse matrix (the products the prediction
made before: G dq, G_S^T, G_S X, G_S^T y, sum w_i G_i^T G_i), on random rows; and a
prediction's step against the dense solution of its linear model.

Reference: scipy.sparse's products of the csr matrix of the same entries and numpy's dense
solve. Tolerance: round-off of sums of at most 30 terms (1e-12 of the largest term)."""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse as sp

from solvers.contact_sets import SetRows


def _rows(seed: int, nodes: int = 40, points: int = 25):
    """Random rows: each point's six distinct nodes' five unknowns, 1/5 of the unknowns
    prescribed, the prescribed motion left on them; (SetRows, csr (r, n 5), dofs, left)."""
    rng = np.random.default_rng(seed)
    nodes_of = np.array([rng.choice(nodes, 6, replace=False) for _ in range(points)])
    slots = (nodes_of[:, :, None] * 5 + np.arange(5)).reshape(points, 30)
    values = rng.standard_normal((points, 30))
    gap = rng.normal(0.0, 1e-3, points)
    prescribed = rng.random(5 * nodes) < 0.2
    dofs = SimpleNamespace(
        free=~prescribed.reshape(nodes, 5),
        free_slots=np.flatnonzero(~prescribed),
        prescribed_slots=np.flatnonzero(prescribed),
    )
    left = np.where(prescribed, rng.standard_normal(5 * nodes), 0.0).reshape(nodes, 5)
    row = np.repeat(np.arange(points), 30)
    matrix = sp.csr_matrix((values.ravel(), (row, slots.ravel())), shape=(points, 5 * nodes))
    return SetRows(slots, values, gap, dofs, left), matrix, dofs, left


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_dense_rows_give_the_sparse_rows_products(seed):
    rows, matrix, dofs, left = _rows(seed)
    free, moved = dofs.free_slots, dofs.prescribed_slots
    g_free = matrix[:, free]
    rng = np.random.default_rng(10 + seed)
    step = rng.standard_normal(free.size)
    points = np.array([3, 0, 17, 8])
    weight = rng.uniform(-2.0, 2.0, points.size)
    scale = np.abs(matrix.data).max() * max(np.abs(step).max(), np.abs(left).max())

    imposed = rows.gap + matrix[:, moved] @ left.ravel()[moved]
    assert np.allclose(rows.imposed, imposed, rtol=0, atol=1e-12 * scale)
    assert np.allclose(rows.linear(step), imposed + g_free @ step, rtol=0, atol=1e-12 * scale)
    columns = g_free[points].T.toarray()
    assert np.array_equal(rows.columns(points), columns)
    block = rng.standard_normal((free.size, points.size))
    assert np.allclose(rows.times(points, block), columns.T @ block, rtol=0, atol=1e-12 * scale)
    assert np.allclose(rows.times(points, step), columns.T @ step, rtol=0, atol=1e-12 * scale)
    assert np.allclose(rows.transposed(points, weight), columns @ weight, rtol=0, atol=1e-12)
    spread = matrix[points].T @ weight
    assert np.allclose(rows.spread(points, weight), spread, rtol=0, atol=1e-12)
    update = (g_free[points].T @ sp.diags(weight) @ g_free[points]).toarray()
    assert np.allclose(rows.update(points, weight).toarray(), update, rtol=0, atol=1e-12)


def test_the_update_adds_no_entry_outside_the_points_free_couplings():
    # A structural entry between a free unknown and a prescribed one's stand-in (free
    # unknown 0) would widen the band every factorisation of the updated K_ff takes.
    rows, matrix, dofs, _ = _rows(4)
    points = np.arange(6)
    g_free = matrix[:, dofs.free_slots][points]
    pattern = (abs(g_free).T @ abs(g_free)).toarray() != 0.0
    made = rows.update(points, np.ones(points.size)).tocoo()  # explicit zeros kept
    assert made.nnz and np.all(pattern[made.row, made.col])


@pytest.mark.parametrize("refactor_at", [None, 0])
def test_a_predicted_step_solves_its_sets_linear_model(monkeypatch, refactor_at):
    """On the 2-ply sag of tests/test_ply_active_set.py: each predicted step (by the
    Sherman-Morrison-Woodbury formula on the factors made, solvers/contact_sets.py, or with
    ``REFACTOR_AT = 0`` by factorising the updated K_ff at every pass, the branch taken past
    REFACTOR_AT new solves) is the dense solution of K_ff + sum s k G_i^T G_i over the
    switched points, right-hand side r_f - K_fp dq_p - sum s k g_i G_i^T, within 1e-8 of its
    largest entry (the solves' round-off on a K_ff of condition ~1e6; measured 1.7e-12 to
    2.5e-9), within 1e-7 when refactorised."""
    from test_ply_active_set import _sag_model

    from elements import ply_active_set
    from solvers import Static, contact_sets

    if refactor_at is not None:
        monkeypatch.setattr(contact_sets, "REFACTOR_AT", refactor_at)

    original = contact_sets.predicted_sets
    errors: list[float] = []

    def checked(run, state, frames, factor, delta_free, left):
        out = original(run, state, frames, factor, delta_free, left)
        if out is None:
            return out
        new, step, _ = out
        model = run.model
        first = len(model.parts) - len(model.interactions)
        pieces = []
        for i, part in enumerate(model.interactions):
            if isinstance(part, ply_active_set.ActiveSetPlyContactBlock):
                found = part.set_model(state, state.history[first + i], frames, model.dofs)
                if found is not None and len(found["points"]):
                    after = new.history[first + i].active[found["points"]]
                    pieces.append((found, after))
        rows = SetRows.of([(0, None, found) for found, _ in pieces], model.dofs, left)
        before = np.concatenate([found["active"] for found, _ in pieces])
        after = np.concatenate([active for _, active in pieces])
        k = np.concatenate([found["stiffness"] for found, _ in pieces])
        switched = np.flatnonzero(before != after)
        weight = np.where(after[switched], 1.0, -1.0) * k[switched]
        matrix = (factor.matrix + rows.update(switched, weight)).toarray()
        right = factor.matrix @ delta_free - rows.transposed(
            switched, weight * rows.imposed[switched]
        )
        expected = np.linalg.solve(matrix, right)
        errors.append(np.abs(step - expected).max() / np.abs(expected).max())
        return out

    monkeypatch.setattr(contact_sets, "predicted_sets", checked)
    result = Static(increments=1, progress=False).solve(_sag_model(2, "active_set"))
    assert result.converged and errors
    # the refactorised updated K_ff's own round-off: measured 1.5e-10 to 2.3e-8
    assert max(errors) <= (1e-8 if refactor_at is None else 1e-7)


@pytest.mark.parametrize("spoilt", [np.nan, 1e3])
def test_a_step_that_does_not_solve_its_linear_model_is_not_taken(monkeypatch, spoilt):
    """A capacitance solve gone wrong (here its solution times NaN or 1e3; a nearly singular
    capacitance matrix does the like) gives a step that does not solve its linear model:
    the prediction is given up and the step taken as it was (the 2-ply sag still converges,
    no set predicted), where it was taken unchecked before."""
    from test_ply_active_set import _sag_model

    from solvers import Static, contact_sets

    right = contact_sets._capacity_solve
    monkeypatch.setattr(contact_sets, "_capacity_solve", lambda c, b: spoilt * right(c, b))
    result = Static(increments=1, progress=False).solve(_sag_model(2, "active_set"))
    assert result.converged
    assert result.info.get("predicted_sets", 0) == 0
