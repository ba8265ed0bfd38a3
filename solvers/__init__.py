"""Solvers: explicit central difference and dynamic relaxation and static Newton-Raphson, and
the explicit step they are built on (for a solver loop of one's own)."""

from solvers.common import ConvergenceError, DivergenceError, SolverError
from solvers.explicit import CentralDifference
from solvers.interrupts import Interrupted, interruptible
from solvers.relaxation import DynamicRelaxation
from solvers.static import Static
from solvers.step import LumpedMasses, Step, explicit_step

__all__ = [
    "CentralDifference",
    "ConvergenceError",
    "DivergenceError",
    "DynamicRelaxation",
    "Interrupted",
    "LumpedMasses",
    "SolverError",
    "Static",
    "Step",
    "explicit_step",
    "interruptible",
]
