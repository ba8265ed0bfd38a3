"""Result of a solve: frames of nodal and element fields, energies, and VTU/XDMF export."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from femcore.mesh import Mesh


@dataclass
class Frame:
    """One output instant.

    time : s (explicit) or pseudo-time; load_factor : fraction of the loads applied.
    positions, velocities, directors : (n, 3); reactions, reaction_moments : (n, 3), the
    forces (N) and moments (N mm) the supports exert at constrained DOFs (zero elsewhere).
    fields : {"point": {...}, "triangle": {...}, "line": {...}} element outputs.
    """

    time: float
    load_factor: float
    positions: np.ndarray
    velocities: np.ndarray
    directors: np.ndarray
    reactions: np.ndarray
    reaction_moments: np.ndarray
    fields: dict = field(default_factory=dict)


@dataclass
class Result:
    """What a solver returns.

    frames : list of Frame; the last one is the final state.
    steps : time steps (explicit) or iterations (dynamic relaxation) taken.
    wall_time : s; converged : whether the solver reached its goal.
    energies : {"time", "kinetic", "internal", "external_work", "damping"} arrays (N mm), one
        entry per recorded step.
    info : solver-specific figures (time step, added mass, iterations per increment, ...).
    """

    mesh: Mesh
    frames: list[Frame]
    steps: int = 0
    wall_time: float = 0.0
    converged: bool = False
    energies: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)
    has_rotation: np.ndarray | None = None

    # Shortcuts to the final frame.
    @property
    def positions(self) -> np.ndarray:
        """(n, 3) final nodal positions."""
        return self.frames[-1].positions

    @property
    def displacements(self) -> np.ndarray:
        """(n, 3) final nodal displacements from the mesh."""
        return self.frames[-1].positions - self.mesh.points

    @property
    def velocities(self) -> np.ndarray:
        return self.frames[-1].velocities

    @property
    def directors(self) -> np.ndarray:
        """(n, 3) final unit directors; NaN rows at nodes without a director."""
        directors = self.frames[-1].directors.copy()
        if self.has_rotation is not None:
            directors[~self.has_rotation] = np.nan
        return directors

    @property
    def reactions(self) -> np.ndarray:
        """(n, 3) final support forces at constrained translational DOFs (N)."""
        return self.frames[-1].reactions

    @property
    def reaction_moments(self) -> np.ndarray:
        return self.frames[-1].reaction_moments

    @property
    def thickness(self) -> np.ndarray | None:
        """(n,) final thickness along the director, when the element provides it."""
        return self.frames[-1].fields.get("point", {}).get("thickness")

    @property
    def times(self) -> np.ndarray:
        return np.array([f.time for f in self.frames])

    @property
    def load_factors(self) -> np.ndarray:
        return np.array([f.load_factor for f in self.frames])

    # ----------------------------------------------------------------------- export
    def to_meshio(self, frame: int = -1):
        """A meshio.Mesh of one frame (deformed coordinates, point and cell data)."""
        import meshio

        f = self.frames[frame]
        cells, point_data, cell_data = self._meshio_data(f)
        return meshio.Mesh(f.positions, cells, point_data=point_data, cell_data=cell_data)

    def _meshio_data(self, f: Frame):
        cells = []
        kinds = []
        if len(self.mesh.triangles):
            cells.append(("triangle", self.mesh.triangles))
            kinds.append("triangle")
        if len(self.mesh.lines):
            cells.append(("line", self.mesh.lines))
            kinds.append("line")
        point_data = {
            "displacement": f.positions - self.mesh.points,
            "velocity": f.velocities,
            "reaction": f.reactions,
        }
        if self.has_rotation is not None and self.has_rotation.any():
            point_data["director"] = f.directors
            point_data["reaction_moment"] = f.reaction_moments
        point_data.update(f.fields.get("point", {}))
        names = sorted({n for k in kinds for n in f.fields.get(k, {})})
        cell_data = {}
        for name in names:
            per_kind = []
            for kind in kinds:
                values = f.fields.get(kind, {}).get(name)
                count = len(self.mesh.triangles if kind == "triangle" else self.mesh.lines)
                if values is None:
                    shape = next(
                        f.fields[k][name].shape[1:] for k in kinds if name in f.fields.get(k, {})
                    )
                    values = np.full((count,) + shape, np.nan)
                per_kind.append(np.asarray(values, dtype=float))
            cell_data[name] = per_kind
        return cells, point_data, cell_data

    def write(self, path: str | os.PathLike, frame: int | None = None) -> Path:
        """Write for ParaView.

        ``.vtu``: one frame (the last unless ``frame`` is given). ``.pvd``: every frame as a
        VTU series next to a ParaView collection file. ``.xdmf``: every frame in one XDMF time
        series (XML data, no HDF5 needed). Returns the path written.
        """
        import meshio

        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".vtu":
            self.to_meshio(-1 if frame is None else frame).write(path)
        elif suffix == ".pvd":
            stem = path.with_suffix("")
            entries = []
            for i, f in enumerate(self.frames):
                part = stem.parent / f"{stem.name}_{i:04d}.vtu"
                self.to_meshio(i).write(part)
                entries.append(
                    f"    <DataSet timestep={quoteattr(repr(f.time))} file={quoteattr(part.name)}/>"
                )
            path.write_text(
                '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n"
            )
        elif suffix == ".xdmf":
            first = self.frames[0]
            cells, _, _ = self._meshio_data(first)
            with meshio.xdmf.TimeSeriesWriter(path, data_format="XML") as writer:
                writer.write_points_cells(self.mesh.points, cells)
                for f in self.frames:
                    _, point_data, cell_data = self._meshio_data(f)
                    writer.write_data(f.time, point_data=point_data, cell_data=cell_data)
        else:
            raise ValueError(f"cannot write {path.name!r}: expected a .vtu, .pvd or .xdmf path")
        return path
