"""Result of a solve: frames of nodal and element fields, energies, and VTU/PVD/XDMF export.

Cell fields are stored per cell kind (the kinds of :data:`femcore.mesh.CELL_KINDS`), and every
export loops over the kinds present in the mesh, so a new cell kind needs no change here.
"""

from __future__ import annotations

import dataclasses
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_path, as_reals
from femcore.field_names import component_names, parts_fields
from femcore.mesh import CELL_KINDS, Mesh
from femcore.writable import OutputError, check_folder, frame_bytes

if TYPE_CHECKING:
    import meshio

__all__ = ["Frame", "Result", "series_timesteps", "write_vtu"]


def series_timesteps(times: Any, by_index: bool = False) -> list[float]:
    """The ``timestep`` of each frame of a series (.pvd, .xdmf): its time ``times[k]`` where
    the times rise from frame to frame (explicit runs: s; relaxation and Static under load
    control: the load factor), else, or with ``by_index`` (Static along an arc-length path),
    its index k. ParaView's readers sort a series by its timesteps, and an arc-length path's
    load factor falls past a limit point: its frames would play out of order. Each VTU frame
    keeps its time and load factor as field data (``write_vtu``).

    Parameters
    ----------
    times : sequence of float, shape (k,)
        The frames' times, in the order written.
    by_index : bool
        The frame's index whatever the times do.

    Returns
    -------
    list of float, length k
    """
    values = [float(t) for t in times]
    rising = all(b > a for a, b in zip(values, values[1:]))
    return values if rising and not by_index else [float(k) for k in range(len(values))]


# A cell block for meshio: (meshio cell type, (c, nodes_per_cell) connectivity).
_CellBlock = tuple[str, np.ndarray]


@dataclass
class Frame:
    """One output instant.

    Parameters
    ----------
    time : float
        Time (s) in the explicit solver, pseudo-time in the quasi-static ones.
    load_factor : float
        Fraction of the loads applied (dimensionless).
    positions : numpy.ndarray, shape (n, 3)
        Nodal positions (length units).
    velocities : numpy.ndarray, shape (n, 3)
        Nodal velocities (length units / s).
    directors : numpy.ndarray, shape (n, 3)
        Unit directors (dimensionless).
    reactions : numpy.ndarray, shape (n, 3)
        Forces (N) the supports exert at constrained translational DOFs (zero elsewhere).
    reaction_moments : numpy.ndarray, shape (n, 3)
        Moments (N mm) the supports exert at constrained rotational DOFs (zero elsewhere).
    fields : dict[str, dict[str, numpy.ndarray]]
        Element outputs: ``{"point": {name: (n, ...)}, <cell kind>: {name: (c, ...)}}``, the
        cell kinds being those of :data:`femcore.mesh.CELL_KINDS` ("triangle", "line"); a
        cell field spans all cells of its kind, NaN where no element block covers a cell.
    tool_forces : numpy.ndarray, shape (t, 3)
        The force (N) the model exerts on each rigid tool, in the order of the contacts
        (``Model.contact``); (0, 3) without tools.
    tool_displacements : numpy.ndarray, shape (t, 3)
        Each rigid tool's translation from where it was given (mm): its prescribed motion,
        and for a force-driven tool its free translation; (0, 3) without tools.
    """

    time: float
    load_factor: float
    positions: np.ndarray
    velocities: np.ndarray
    directors: np.ndarray
    reactions: np.ndarray
    reaction_moments: np.ndarray
    fields: dict[str, dict[str, np.ndarray]] = dataclasses.field(default_factory=dict)
    tool_forces: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 3)))
    tool_displacements: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 3)))


@dataclass
class Result:
    """What a solver returns.

    Parameters
    ----------
    mesh : Mesh
        The undeformed mesh the model was built on.
    frames : list of Frame
        Output instants; the last one is the final state.
    steps : int
        Time steps (explicit) or iterations (dynamic relaxation, static) taken.
    wall_time : float
        Elapsed time of the solve, s; a solve resumed from a checkpoint counts the parts
        before the stop too (up to that checkpoint: ``info["wall_time_before_resume"]``).
    converged : bool
        Whether the solver reached its goal.
    energies : dict[str, numpy.ndarray]
        The explicit solver: ``{"time", "kinetic", "internal", "external_work", "damping",
        "friction"}`` arrays (N mm, time in s), one entry per recorded step (external work
        includes that of moving tools; friction is what the interactions dissipated: tools'
        and plies' Coulomb friction, contact damping; internal is the energy the model
        stores, the internal forces' work less that: kinetic + internal + damping + friction
        = external work, docs/theory.md §6.1 "The energy records").
        Static: ``{"time", "internal", "friction"}``, the strain energy of each frame and
        what the interactions' friction dissipated up to it (time = load factor). Dynamic
        relaxation: empty.
    info : dict[str, Any]
        Solver-specific figures (time step, added mass, iterations per increment, ...).
    has_rotation : numpy.ndarray of bool, shape (n,), optional
        Which nodes carry a director (rotational DOFs); None if unknown.
    """

    mesh: Mesh
    frames: list[Frame]
    steps: int = 0
    wall_time: float = 0.0
    converged: bool = False
    energies: dict[str, np.ndarray] = dataclasses.field(default_factory=dict)
    info: dict[str, Any] = dataclasses.field(default_factory=dict)
    has_rotation: np.ndarray | None = None

    # Shortcuts to the final frame.
    @property
    def positions(self) -> np.ndarray:
        """(n, 3) final nodal positions (length units)."""
        return self.frames[-1].positions

    @property
    def displacements(self) -> np.ndarray:
        """(n, 3) final nodal displacements from the mesh (length units)."""
        return self.frames[-1].positions - self.mesh.points

    @property
    def velocities(self) -> np.ndarray:
        """(n, 3) final nodal velocities (length units / s)."""
        return self.frames[-1].velocities

    @property
    def directors(self) -> np.ndarray:
        """(n, 3) final unit directors; NaN rows at nodes without a director."""
        directors = self.frames[-1].directors.copy()
        if self.has_rotation is not None:
            directors[~self.has_rotation] = np.nan
        return directors

    @property
    def tool_forces(self) -> np.ndarray:
        """(frames, t, 3) the force (N) on each rigid tool at each frame (the tool's reaction
        is its opposite), t the number of contacts in the order of ``Model.contact``."""
        return np.array([frame.tool_forces for frame in self.frames]).reshape(
            len(self.frames), -1, 3
        )

    @property
    def tool_displacements(self) -> np.ndarray:
        """(frames, t, 3) each rigid tool's translation (mm) at each frame, in the order of
        ``tool_forces`` (a force-driven tool's travel)."""
        return np.array(
            [getattr(frame, "tool_displacements", np.zeros((0, 3))) for frame in self.frames]
        ).reshape(len(self.frames), -1, 3)

    @property
    def reactions(self) -> np.ndarray:
        """(n, 3) final support forces at constrained translational DOFs (N)."""
        return self.frames[-1].reactions

    @property
    def reaction_moments(self) -> np.ndarray:
        """(n, 3) final support moments at constrained rotational DOFs (N mm)."""
        return self.frames[-1].reaction_moments

    @property
    def thickness(self) -> np.ndarray | None:
        """(n,) final thickness along the director (length units), or None.

        The nodal fields "thickness", "thickness_2", ... of the final frame (one per element
        block that provides it: both shells do, NaN off the block's nodes) merged, each node's
        from the first block it belongs to; NaN at nodes of no such block; None when no block
        provides it. With one such block, ``field("thickness")``.
        """
        fields = self.frames[-1].fields.get("point", {})
        parts = [np.asarray(part, dtype=float) for part in parts_fields(fields, "thickness")]
        if len(parts) < 2:
            return parts[0] if parts else None
        merged = parts[0].copy()
        for part in parts[1:]:
            merged = np.where(np.isnan(merged), part, merged)
        return merged

    def director_angle(self, normal: ArrayLike = (0.0, 0.0, 1.0), frame: int = -1) -> np.ndarray:
        """The angle (deg) between each director and a chosen plane, given by its normal:
        90 for a director along the normal, 0 for one lying in the plane (the default plane
        is the horizontal one: 90 = vertical). NaN at nodes without a director.

        Parameters
        ----------
        normal : array_like, shape (3,)
            Normal of the plane (normalised here).
        frame : int, optional
            Frame index; the last frame by default.

        Returns
        -------
        numpy.ndarray, shape (n,)
            Degrees in [0, 90].

        Raises
        ------
        ValueError
            A normal that is not a non-zero finite 3-vector, ``frame`` out of range, or a
            result without any director.
        """
        axis = as_reals(normal, "normal", "a non-zero 3-vector").ravel()
        if axis.shape != (3,) or not np.isfinite(axis).all() or not np.linalg.norm(axis) > 0:
            raise ValueError(f"normal must be a non-zero 3-vector, got {normal!r}")
        directors = self.frames[self._frame_index(frame)].directors
        # A node without a director (a cable's) has a zero row: its angle is undefined, not 0.
        present = np.linalg.norm(directors, axis=1) > 0
        if not present.any():
            raise ValueError(
                "director_angle: no node of this result has a director (a model of cables "
                "only); directors come from shell elements"
            )
        sine = np.abs(directors @ (axis / np.linalg.norm(axis)))
        angle = np.degrees(np.arcsin(np.clip(sine, 0.0, 1.0)))
        return np.where(present, angle, np.nan)

    @property
    def times(self) -> np.ndarray:
        """(f,) time (s) or pseudo-time of each frame."""
        return np.array([f.time for f in self.frames])

    @property
    def timesteps(self) -> list[float]:
        """Each frame's timestep in a series file (``series_timesteps``): its time where the
        times rise, else (and for a Static run along an arc-length path, ``info["path"]``)
        its index."""
        return series_timesteps(self.times, by_index=self.info.get("path") == "arc_length")

    @property
    def load_factors(self) -> np.ndarray:
        """(f,) load factor of each frame (dimensionless)."""
        return np.array([f.load_factor for f in self.frames])

    def field(self, name: str, frame: int = -1) -> np.ndarray:
        """A nodal or cell output field of one frame, by name.

        Looks in the element outputs of the frame (``Frame.fields``): first the nodal fields,
        then the cell fields of each cell kind present in the mesh. Positions, displacements,
        velocities, directors and reactions are attributes of :class:`Frame` and of this
        result, not fields.

        Parameters
        ----------
        name : str
            Field name, e.g. "thickness" (nodal) or "axial_force", "warp_strain" (cell).
        frame : int, optional
            Frame index; the last frame by default.

        Returns
        -------
        numpy.ndarray
            (n, ...) for a nodal field, (c, ...) over all cells of its kind for a cell field
            (NaN at cells no element block covers), in the field's own units.

        Raises
        ------
        ValueError
            No field of that name (the message lists the available ones), a cell field of
            that name on more than one cell kind, or ``frame`` out of range.
        """
        fields = self.frames[self._frame_index(frame)].fields
        point = fields.get("point", {})
        if name in point:
            return point[name]
        owners = [kind for kind in self.mesh.cell_kinds if name in fields.get(kind, {})]
        if len(owners) == 1:
            return fields[owners[0]][name]
        if owners:
            raise ValueError(
                f"field {name!r} is defined on several cell kinds {owners}; read it from "
                f"frames[{frame}].fields[kind]"
            )
        available = sorted(
            {*point, *(n for kind in self.mesh.cell_kinds for n in fields.get(kind, {}))}
        )
        raise ValueError(
            f"no field {name!r} in frame {frame}; available fields: {available or 'none'}"
        )

    def _frame_index(self, frame: int) -> int:
        """``frame`` checked: an integer in -len(frames) .. len(frames) - 1."""
        count = len(self.frames)
        if isinstance(frame, bool) or not isinstance(frame, int | np.integer):
            raise ValueError(f"frame must be an integer index, got {frame!r}")
        if not -count <= frame < count:
            raise ValueError(
                f"frame {frame} out of range: the result has {count} frame(s) (0..{count - 1}, "
                "or negative from the end)"
            )
        return int(frame)

    # ----------------------------------------------------------------------- export
    def to_meshio(self, frame: int = -1) -> meshio.Mesh:
        """A meshio mesh of one frame.

        Parameters
        ----------
        frame : int, optional
            Frame index; the last frame by default.

        Returns
        -------
        meshio.Mesh
            The reference coordinates (n, 3), as in every format written (ParaView: Warp By
            Vector with "displacement" shows the deformed shape), one cell block per cell kind
            present, point data (displacement, velocity, reaction, director and
            reaction_moment if some node has rotations, nodal element fields), cell data
            (cell element fields) and field data: the frame's ``time`` and ``load_factor``.
        """
        import meshio

        f = self.frames[self._frame_index(frame)]
        cells, point_data, cell_data = self._meshio_data(f)
        # the frame's time and load factor: a series' timestep may be neither (series_timesteps)
        field_data = {"time": np.array([f.time]), "load_factor": np.array([f.load_factor])}
        return meshio.Mesh(self.mesh.points, cells, point_data=point_data, cell_data=cell_data,
                           field_data=field_data)  # fmt: skip

    def _meshio_data(
        self, f: Frame
    ) -> tuple[list[_CellBlock], dict[str, np.ndarray], dict[str, list[np.ndarray]]]:
        kinds = self.mesh.cell_kinds
        cells = [(CELL_KINDS[kind].meshio_name, self.mesh.cells(kind)) for kind in kinds]
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
            # A field some kinds lack is NaN on their blocks, with the shape of the others.
            shape = next(f.fields[k][name].shape[1:] for k in kinds if name in f.fields.get(k, {}))
            per_kind = []
            for kind in kinds:
                values = f.fields.get(kind, {}).get(name)
                if values is None:
                    values = np.full((len(self.mesh.cells(kind)),) + shape, np.nan)
                per_kind.append(np.asarray(values, dtype=float))
            cell_data[name] = per_kind
        return cells, point_data, cell_data

    def write(self, path: str | os.PathLike[str], frame: int | None = None) -> Path:
        """Write for ParaView.

        ``.vtu``: one frame (the last unless ``frame`` is given). ``.pvd``: every frame as a
        VTU series next to a ParaView collection file. A streamed explicit run
        (``CentralDifference(output=...)``) holds only its first and last frames: a series
        written from it has those two, and a UserWarning names the streamed series that
        holds every frame. ``.xdmf``: every frame in one XDMF
        time series whose arrays are in binary HDF5 beside it (``<stem>.h5``, the mesh once,
        the fields per frame; femcore.xdmf). Every format holds the same thing: the
        reference coordinates and, per frame, the "displacement" field with the other nodal
        and cell fields, so one ParaView pipeline (Warp By Vector on "displacement") shows
        the deformed shape of any of them. The VTU arrays with several components name them
        (``ComponentName0`` ...: "x", "y", "z"; "11", "22", "12"; "bottom", ..., "top"; see
        femcore.field_names).

        Parameters
        ----------
        path : str or os.PathLike
            Output file; its suffix selects the format.
        frame : int, optional
            Frame to write to a ``.vtu`` file (ignored by the series formats).

        Returns
        -------
        pathlib.Path
            The path written.

        Raises
        ------
        ValueError
            A suffix other than .vtu, .pvd or .xdmf, or a folder that does not exist or is a
            file.
        femcore.writable.OutputError
            The folder is not writable or its disk too full for the frames (checked before
            writing), or a write failed: the message names the file and what was written.
        """
        path = as_path(path, "Result.write path")
        suffix = path.suffix.lower()
        if suffix not in (".vtu", ".pvd", ".xdmf"):
            raise ValueError(f"cannot write {path.name!r}: expected a .vtu, .pvd or .xdmf path")
        streamed = self.info.get("streamed_frames", 0)
        if suffix != ".vtu" and streamed > len(self.frames):
            warnings.warn(
                f"{path.name!r} gets the {len(self.frames)} frames this result holds of the "
                f"{streamed} of its run: the solver streamed them to "
                f"{str(self.info.get('output'))!r}, which holds every one (and keeps only the "
                "first and the last in memory)",
                UserWarning,
                stacklevel=2,
            )
        frames = 1 if suffix == ".vtu" else len(self.frames)
        check_folder(path.parent, "write", needed=frames * frame_bytes(self.mesh), create=False)
        written: list[str] = []
        try:
            self._write(path, suffix, frame, written)
        except OSError as error:
            kept = f"the frame files {', '.join(written)}" if written else "no complete file"
            raise OutputError.from_error(error, kept) from None
        return path

    def _write(self, path: Path, suffix: str, frame: int | None, written: list[str]) -> None:
        """Write ``path`` in the format of ``suffix``, listing in ``written`` each frame file
        of a .pvd series once it is complete."""
        if suffix == ".vtu":
            write_vtu(self.to_meshio(-1 if frame is None else frame), path)
        elif suffix == ".pvd":
            stem = path.with_suffix("")
            entries = []
            for i, step in enumerate(self.timesteps):
                part = stem.parent / f"{stem.name}_{i:05d}.vtu"  # as a streamed series names them
                write_vtu(self.to_meshio(i), part)
                written.append(part.name)
                entries.append(
                    f"    <DataSet timestep={quoteattr(repr(step))} file={quoteattr(part.name)}/>"
                )
            path.write_text(
                '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n"
            )
        elif suffix == ".xdmf":
            from femcore.xdmf import write_xdmf

            cells, _, _ = self._meshio_data(self.frames[0])
            series = (
                (step, *self._meshio_data(f)[1:]) for step, f in zip(self.timesteps, self.frames)
            )
            write_xdmf(path, self.mesh.points, cells, series)


# The opening tag of a data array as meshio writes it, one to a line (its data never starts a
# line with "<": base64 text).
_DATA_ARRAY = re.compile(
    rb'^<DataArray type="[^"]*" Name="([^"]*)" NumberOfComponents="(\d+)"', re.MULTILINE
)


def write_vtu(mesh: meshio.Mesh, path: Path) -> None:
    """Write ``mesh`` to the VTU file ``path`` (binary, zlib-compressed, by meshio) with the
    names of the components of its multi-component arrays (``ComponentName0`` ...
    attributes, which VTK's XML reader and so ParaView read) where femcore.field_names
    knows them, and its field data (one-tuple values: a frame's ``time`` and
    ``load_factor``) in the grid's ``FieldData``, which meshio's writer leaves out.

    Parameters
    ----------
    mesh : meshio.Mesh
        The mesh and its point and cell data.
    path : pathlib.Path
        The .vtu file; its folder must exist.
    """
    mesh.write(path)
    text = path.read_bytes()

    def named(match: re.Match[bytes]) -> bytes:
        names = component_names(match[1].decode(), int(match[2]))
        if names is None:
            return match[0]
        extra = "".join(f" ComponentName{i}={quoteattr(n)}" for i, n in enumerate(names))
        return match[0] + extra.encode()

    renamed = _DATA_ARRAY.sub(named, text)
    scalars = {name: np.ravel(values) for name, values in mesh.field_data.items()}
    grid = b"<UnstructuredGrid>\n"
    if scalars and b"<FieldData>" not in renamed and grid in renamed:
        # meshio's VTU writer leaves field data out; VTK reads it from the grid's FieldData
        arrays = "".join(
            f'<DataArray type="Float64" Name={quoteattr(name)} NumberOfTuples="{len(values)}" '
            f'format="ascii">{" ".join(repr(float(v)) for v in values)}</DataArray>\n'
            for name, values in scalars.items()
        )
        renamed = renamed.replace(grid, grid + f"<FieldData>\n{arrays}</FieldData>\n".encode(), 1)
    if renamed != text:
        path.write_bytes(renamed)
