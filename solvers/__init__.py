"""Solvers: explicit central difference and dynamic relaxation (static Newton comes next)."""

from solvers.common import ConvergenceError, DivergenceError, SolverError
from solvers.explicit import CentralDifference
from solvers.relaxation import DynamicRelaxation

__all__ = [
    "CentralDifference",
    "ConvergenceError",
    "DivergenceError",
    "DynamicRelaxation",
    "SolverError",
]
