"""A count of the QDLDL factorisations solvers.linear makes (each one a measurement of a
pattern's ordering and fill), for the tests of its choice of factorisation."""

from solvers import linear


def counting_qdldl(monkeypatch) -> list:
    """The list that grows by one at each QDLDL factorisation solvers.linear makes, with
    ``qdldl.Solver`` wrapped through ``monkeypatch`` (undone after the test)."""
    made = []
    solver_class = linear.qdldl.Solver

    def counted(*args, **kwargs):
        made.append(1)
        return solver_class(*args, **kwargs)

    monkeypatch.setattr(linear.qdldl, "Solver", counted)
    return made
