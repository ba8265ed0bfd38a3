"""Solvers: explicit central difference and dynamic relaxation and static Newton-Raphson."""

from solvers.common import ConvergenceError, DivergenceError, SolverError
from solvers.explicit import CentralDifference
from solvers.relaxation import DynamicRelaxation
from solvers.static import Static

__all__ = [
    "CentralDifference",
    "ConvergenceError",
    "DivergenceError",
    "DynamicRelaxation",
    "SolverError",
    "Static",
]
