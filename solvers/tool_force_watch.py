"""Whether a force-driven tool's contact force is the force prescribed on it, over the last
half of an explicit run (docs/theory.md §6.3, "The force-driven tools").

A free tool (a blank holder, elements/tools.py) is a mass m on the penalty springs k of its
contact: a step load F on it rings undamped at sqrt(k / m), its contact force swinging between
0 and 2 F about a mean of F, and the frames and history rows sample it anywhere on that swing
(a 100-g holder, 1e-4 t, pressed by 100 N read 0-1 N at every 1-ms frame, ringing with a
period of 0.5 ms). KE / W does not see it (its energy is a small part of the run's work).
Its inertia m c'' and its damping (a dashpot's c v against a drift) also take their share of
F: the body then feels F less them.

The watch keeps, at every step of the last half of the run (``TOOL_CHECK_FROM``), the force
the tool presses the body with beside the force prescribed on its node (``CompiledModel.
driven_tools``), along the axes it is free along: their running sums, extremes and the
squared difference, a few (k, 3) arrays, so the ringing cannot alias as the energy records,
thinned to about 4000 in a run, can (the tool's contact mode is in the stable step's bound,
docs/theory.md §9.5, and may be the run's fastest). The last half, not KE / W's judged
records: it is known when the run starts (a running sum needs no record), it leaves the
tool's first landing and the closing of a ramped force to the first half, and it holds the
frames a forming run is read at. The difference is judged as its root mean square over
that of the prescribed force: above ``TOOL_FORCE_SHARE`` the run warns once.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from solvers.common import outside_stacklevel

__all__ = ["TOOL_CHECK_FROM", "TOOL_FORCE_SHARE", "ToolForceWatch"]

#: The share of the duration from which the tools' forces are judged (the last half).
TOOL_CHECK_FROM = 0.5
#: The largest root mean square of (contact - prescribed) force over that of the prescribed
#: force: the quasi-static bound on KE / W, a tenth, put on the tool's own mode. A ringing of
#: amplitude A about F on the springs K holds (A / F)^2 times the springs' static energy F^2 /
#: 2K, and its root mean square is A / sqrt(2): a departure d is a ringing of 2 d^2 of that
#: energy, a tenth at d = 0.22; 0.2 (2 d^2 = 0.08) lets through a ringing of 28 % of F, or a
#: mean 20 % off. An undamped step load rings at 0.71. Measured on the shipped cases with a
#: holder (docs/theory.md §6.3): 0.04-0.16, and 0.27-0.33 where the holder rings at kHz on a
#: Mindlin blank.
TOOL_FORCE_SHARE = 0.2

AXES = ("x", "y", "z")


class ToolForceWatch:
    """The running comparison of the force-driven tools' contact forces with their prescribed
    forces over [``TOOL_CHECK_FROM`` x duration, duration] of an explicit run.

    Parameters
    ----------
    model : CompiledModel (its ``driven_tools``).
    duration : s.
    """

    def __init__(self, model, duration: float):
        tools = model.driven_tools
        self.names = tools.names()
        self.free = tools.free.copy()
        self.start = TOOL_CHECK_FROM * duration
        self.duration = duration
        k = len(tools)
        self.weight = 0.0  # s, the time observed
        self.push = np.zeros((k, 3))  # time integrals, N s
        self.load = np.zeros((k, 3))
        self.squared_difference = np.zeros(k)  # N^2 s
        self.squared_load = np.zeros(k)
        self.lowest = np.full((k, 3), np.inf)
        self.highest = np.full((k, 3), -np.inf)
        self.nodes = np.asarray(tools.nodes, dtype=np.int64).copy()
        self.reference = np.asarray(model.reference_positions)[self.nodes].copy()

    def __len__(self) -> int:
        return len(self.names)

    def observe(self, model, state, dt: float) -> None:
        """Count the forces at ``state`` (t(i), the step's forces) for the step ``dt`` (s) it
        begins; nothing before the judged part of the run."""
        if state.time < self.start or not len(self.names):
            return
        push = model.driven_tool_pushes(state) * self.free
        load = model.driven_tools.loads(state.time / self.duration) * self.free
        difference = push - load
        self.weight += dt
        self.push += dt * push
        self.load += dt * load
        self.squared_difference += dt * np.einsum("ij,ij->i", difference, difference)
        self.squared_load += dt * np.einsum("ij,ij->i", load, load)
        np.minimum(self.lowest, push, out=self.lowest)
        np.maximum(self.highest, push, out=self.highest)

    def report(self, state=None) -> list[dict[str, Any]]:
        """One dict per tool node: ``tool`` ("tool2", or "tool2+tool3" for a node two
        contacts share), ``axes`` its free axes, ``from_s`` where the judged part begins, and
        along those axes (lists, N) ``force_min``, ``force_max`` and ``force_mean`` of the
        force the tool pressed the body with (minus ``tool_forces``: the prescribed force's
        sign), ``prescribed_mean``; ``departure`` the root mean square of their difference
        over that of the prescribed force (None where no force is prescribed, or before the
        judged part); ``travel`` (mm, along the free axes) its free translation at ``state``
        (the run's last; None without it)."""
        out = []
        seen = self.weight > 0.0
        travel = None
        if state is not None and hasattr(self, "nodes"):  # (a watch pickled before: none)
            travel = np.asarray(state.positions)[self.nodes] - self.reference
        for k, name in enumerate(self.names):
            axes = np.flatnonzero(self.free[k])
            share = None
            if seen and self.squared_load[k] > 0.0:
                share = float(np.sqrt(self.squared_difference[k] / self.squared_load[k]))
            mean = self.push[k] / self.weight if seen else None
            prescribed = self.load[k] / self.weight if seen else None
            out.append(
                {
                    "tool": name,
                    "axes": [AXES[a] for a in axes],
                    "from_s": self.start,
                    "force_min": _along(self.lowest[k], axes),
                    "force_max": _along(self.highest[k], axes),
                    "force_mean": _along(mean, axes),
                    "prescribed_mean": _along(prescribed, axes),
                    "departure": share,
                    "travel": None if travel is None else _along(travel[k], axes),
                }
            )
        return out

    @staticmethod
    def loose(report: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """The tools of ``report`` that pressed nothing over the judged part of the run
        (contact force exactly 0 along every free axis: no node touched them) while a force
        was prescribed on them: they fly off under it."""
        return [
            tool for tool in report
            if tool["force_min"] is not None and tool["force_max"] is not None
            and not any(tool["force_min"]) and not any(tool["force_max"])
            and tool["prescribed_mean"] is not None and any(tool["prescribed_mean"])
        ]  # fmt: skip

    def kinetic_note(
        self, report: list[dict[str, Any]], state, mass: np.ndarray, kinetic: float
    ) -> str | None:
        """Where tools of ``report`` fly loose (``loose``), what the KE / W warning should say
        instead of the run's inertia: the share of the run's kinetic energy at the end
        (``kinetic``, N mm) that is theirs, 1/2 m v^2 of their nodes (``mass`` (n,) t,
        ``state`` the last); None where none is loose."""
        names = {tool["tool"] for tool in self.loose(report)}
        if not names or not hasattr(self, "nodes"):
            return None
        flying = [k for k, name in enumerate(self.names) if name in names]
        nodes = self.nodes[flying]
        v = np.asarray(state.velocities)[nodes]
        own = 0.5 * float(np.sum(np.asarray(mass)[nodes] * np.einsum("ij,ij->i", v, v)))
        share = own / kinetic if kinetic > 0.0 else 0.0
        return (
            f"{share:.3g} of the kinetic energy at the end is the force-driven tools' own "
            f"({', '.join(sorted(names))}, which pressed nothing over the last half of the "
            "run and fly off under their force: see their warning), not the body's inertia"
        )

    def warn(self, report: list[dict[str, Any]]) -> None:
        """One UserWarning for the tools of ``report`` whose departure is above
        TOOL_FORCE_SHARE: each tool's range and mean against its prescribed force, and what to
        do."""
        loose = self.loose(report)
        if loose:
            said = "; ".join(_loose_phrase(tool) for tool in loose)
            warnings.warn(
                "a force-driven tool never touched the body over the last half of the run "
                f"(t >= {self.start:.6g} s): {said}. Its force must point towards the body "
                "(from the tool's face to the body's side of it): as it is, the tool leaves "
                "the body, or never reaches it, and presses nothing; turn its force's sign, "
                "or start it on the body",
                UserWarning,
                stacklevel=outside_stacklevel(),
            )
        lines = []
        for tool in report:
            if tool in loose:
                continue
            if tool["departure"] is None or tool["departure"] <= TOOL_FORCE_SHARE:
                continue
            along = ", ".join(
                f"along {axis} {low:.4g} to {high:.4g} N, mean {mean:.4g} N against "
                f"{prescribed:.4g} N prescribed"
                for axis, low, high, mean, prescribed in zip(
                    tool["axes"], tool["force_min"], tool["force_max"], tool["force_mean"],
                    tool["prescribed_mean"],
                )
            )  # fmt: skip
            lines.append(
                f"{tool['tool']}'s contact force {along} (departure {tool['departure']:.3g})"
            )
        if not lines:
            return
        warnings.warn(
            "a force-driven tool does not press the body with its prescribed force over the "
            f"last half of the run (t >= {self.start:.6g} s): " + "; ".join(lines) + ". The "
            "departure is the root mean square of the difference over that of the prescribed "
            f"force, above TOOL_FORCE_SHARE = {TOOL_FORCE_SHARE:g}: a range about the "
            "prescribed force is the tool ringing on its contact springs (a step load swings "
            "it between 0 and twice its force), and the frames and the history sample it "
            "anywhere on its swing; a mean off it is the tool's inertia or damping. Damp the "
            "ringing: the contact's damping = 1 (critical on each node's spring, [[contact]] "
            "damping; 0.2 may leave it ringing), a Dashpot on the tool's node "
            '(critical_damping(m, k)), or a force that grows smoothly (amplitude = "smooth"); '
            "a lighter tool for its inertia. For a dynamic run, set kinetic_bound=None",
            UserWarning,
            stacklevel=outside_stacklevel(),
        )


def _along(values: np.ndarray | None, axes: np.ndarray) -> list[float] | None:
    """The components of ``values`` (3,) along ``axes``, as floats (None: nothing seen)."""
    if values is None or not np.all(np.isfinite(values[axes])):
        return None
    return [float(v) for v in values[axes]]


def _loose_phrase(tool: dict[str, Any]) -> str:
    """What a loose tool of a report did: its prescribed force and its travel, per free
    axis."""
    travel = tool["travel"] or [None] * len(tool["axes"])
    return f"{tool['tool']} pressed it with 0 N along " + ", ".join(
        f"{axis} against {prescribed:.4g} N prescribed"
        + ("" if move is None else f", and travelled {move:.4g} mm")
        for axis, prescribed, move in zip(tool["axes"], tool["prescribed_mean"], travel)
    )
