"""A time series as XDMF 3 with its arrays in binary HDF5: ``<stem>.xdmf`` (the light XML
ParaView opens) and ``<stem>.h5`` beside it (the heavy data, gzip-compressed).

The mesh is written once (``/mesh/points``, ``/mesh/topology``) and each frame's fields under
``/frames/<k>/point`` and ``/frames/<k>/cell``. The XML holds one temporal collection of one
grid per frame, every grid pointing at the same mesh arrays: ParaView shows one block whose
reference geometry Warp By Vector on "displacement" deforms, and meshio's
``TimeSeriesReader`` reads it back.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape, quoteattr

import numpy as np

__all__ = ["write_xdmf"]

# meshio cell type -> (XDMF topology type, XDMF mixed-topology index, nodes per cell)
_TOPOLOGY = {"triangle": ("Triangle", 4, 3), "line": ("Polyline", 2, 2)}


def write_xdmf(
    path: Path,
    points: np.ndarray,
    cells: list[tuple[str, np.ndarray]],
    frames: Iterable[tuple[float, dict[str, np.ndarray], dict[str, list[np.ndarray]]]],
) -> None:
    """Write a time series to ``path`` (.xdmf) and its arrays to ``path`` with suffix .h5.

    Parameters
    ----------
    path : pathlib.Path
        The .xdmf file; its folder must exist. The .h5 file beside it is overwritten.
    points : numpy.ndarray, shape (n, 3)
        The reference coordinates (length units), written once.
    cells : list of (str, numpy.ndarray)
        Cell blocks: a meshio cell type ("triangle" or "line") and its (c, nodes per cell)
        connectivity; several blocks are written as one XDMF "Mixed" topology.
    frames : iterable of (float, dict, dict)
        Per frame: its time, the point data {name: (n, ...)} and the cell data {name: one
        (c_b, ...) array per cell block}, in the fields' own units.

    Raises
    ------
    ValueError
        A cell type other than triangle or line.
    OSError
        A file could not be written.
    ImportError
        h5py is not installed (it is a dependency of the project).
    """
    try:
        import h5py
    except ImportError:
        raise ImportError(
            "XDMF output writes its arrays with h5py, a dependency of fibreshell that is not "
            "installed here: pip install h5py (or pip install -e . in the project)"
        ) from None

    unknown = sorted({kind for kind, _ in cells} - set(_TOPOLOGY))
    if unknown:
        raise ValueError(
            f"XDMF output: cell types {unknown} are not supported; expected {sorted(_TOPOLOGY)}"
        )
    heavy = path.with_suffix(".h5")
    where = heavy.name
    # The light file last: until the arrays are all written, no .xdmf points at them.
    path.unlink(missing_ok=True)
    points = np.asarray(points, dtype=float)
    with h5py.File(heavy, "w", libver=_FORMAT) as h5:
        dataset = _Datasets(h5)
        dataset("mesh/points", points)
        topology, count = _topology(cells)
        dataset("mesh/topology", topology[1])
        mesh_xml = (
            f'<Topology {topology[0]} NumberOfElements="{count}">'
            f"{_item(where, 'mesh/topology', topology[1])}</Topology>"
            f'<Geometry GeometryType="XYZ">{_item(where, "mesh/points", points)}</Geometry>'
        )
        grids = []
        for k, (time, point_data, cell_data) in enumerate(frames):
            attributes = []
            for centre, data in (
                ("Node", point_data),
                ("Cell", {name: np.concatenate(blocks) for name, blocks in cell_data.items()}),
            ):
                for name, values in data.items():
                    values = np.asarray(values, dtype=float)
                    key = f"frames/{k}/{centre.lower()}/{name}"
                    dataset(key, values)
                    attributes.append(
                        f'<Attribute Name={quoteattr(name)} AttributeType="{_kind(values)}" '
                        f'Center="{centre}">{_item(where, key, values)}</Attribute>'
                    )
            grids.append(
                f'    <Grid Name="frame_{k}" GridType="Uniform">\n'
                f'     <Time Value="{float(time)!r}"/>\n     {mesh_xml}\n'
                + "".join(f"     {a}\n" for a in attributes)
                + "    </Grid>\n"
            )
    path.write_text(
        '<?xml version="1.0"?>\n<Xdmf Version="3.0">\n <Domain>\n'
        '  <Grid Name="result" GridType="Collection" CollectionType="Temporal">\n'
        + "".join(grids)
        + "  </Grid>\n </Domain>\n</Xdmf>\n"
    )


# The HDF5 1.10 file format (2017; readers on HDF5 1.10 or newer, as VTK's and so ParaView's
# are, open it): a dataset of one chunk then needs no chunk index, which in the 1.8 format costs
# about 1.4 kB per dataset, a third of the file of a small mesh.
_FORMAT = ("v110", "v110")

# gzip (in every HDF5 build, so every reader has it) after the byte shuffle, which groups the
# alike exponent bytes of neighbouring floats.
_PACKED = {"compression": "gzip", "compression_opts": 1, "shuffle": True}


class _Datasets:
    """Writes arrays as ``_PACKED`` datasets of an open HDF5 file, the creation properties of
    each shape and type made once.

    h5py's ``create_dataset`` works out a dataset's creation properties (chunk shape, the
    filters checked and set) and looks its groups up by path for each call, most of the time
    of a small dataset, and a series writes a dataset per field and frame. Here the first
    array of a shape and type goes through ``create_dataset``, the others of that shape and
    type are created at the low level with its properties (``get_create_plist``) in groups
    kept by path: the same layout, chunks and filters, so the same bytes in the file. The six
    series of two paper cases (20 frames of 231 nodes): 0.61 -> 0.27 s of CPU
    (benchmarks/case_outside_solves.py).

    Parameters
    ----------
    h5 : h5py.File
        The file, open for writing.
    """

    def __init__(self, h5) -> None:
        import h5py

        self._h5py = h5py
        self._h5 = h5
        self._made: dict[tuple[tuple[int, ...], str], tuple] = {}
        self._groups: dict[str, Any] = {"": h5}

    def __call__(self, key: str, values: np.ndarray) -> None:
        """Write ``values`` (any shape, a numeric type) as dataset ``key`` ("group/.../name":
        the groups made as needed)."""
        values = np.ascontiguousarray(values)
        kind = (values.shape, values.dtype.str)
        made = self._made.get(kind)
        if made is None:
            first = self._h5.create_dataset(key, data=values, **_PACKED)
            space = self._h5py.h5s.create_simple(values.shape)
            self._made[kind] = (first.id.get_create_plist(), first.id.get_type(), space)
            return
        plist, datatype, space = made
        parent, _, name = key.rpartition("/")
        group = self._groups.get(parent)
        if group is None:  # h5py's lookup of a path costs more than the dataset's creation
            group = self._groups[parent] = self._h5.require_group(parent)
        created = self._h5py.h5d.create(group.id, name.encode(), datatype, space, dcpl=plist)
        created.write(self._h5py.h5s.ALL, self._h5py.h5s.ALL, values)


def _topology(cells: list[tuple[str, np.ndarray]]) -> tuple[tuple[str, np.ndarray], int]:
    """The XDMF Topology's attributes and its array, and the number of cells. One block: its
    type and (c, k) connectivity; several: "Mixed", each cell its type index (a line also
    its node count 2) then its nodes."""
    count = sum(len(block) for _, block in cells)
    if len(cells) == 1:
        kind, block = cells[0]
        name, _, nodes = _TOPOLOGY[kind]
        extra = ' NodesPerElement="2"' if kind == "line" else ""
        return (f'TopologyType="{name}"{extra}', np.asarray(block, dtype=np.int64)), count
    parts = []
    for kind, block in cells:
        _, index, nodes = _TOPOLOGY[kind]
        head = [index, nodes] if kind == "line" else [index]
        lead = np.broadcast_to(np.array(head, dtype=np.int64), (len(block), len(head)))
        parts.append(np.hstack([lead, np.asarray(block, dtype=np.int64)]).ravel())
    flat = np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)
    return ('TopologyType="Mixed"', flat), count


def _kind(values: np.ndarray) -> str:
    """The XDMF AttributeType of an array: Scalar (one value per node or cell), else Vector,
    whose components VTK's XDMF reader takes from the array's last dimension (a "Matrix" it
    reads as one tuple of every value; two components it pads with a zero third)."""
    return "Scalar" if values.ndim == 1 else "Vector"


def _item(where: str, key: str, values: np.ndarray) -> str:
    """A DataItem pointing at dataset ``key`` of the HDF5 file ``where``."""
    number = "Int" if values.dtype.kind in "iu" else "Float"
    dims = " ".join(str(d) for d in values.shape)
    return (
        f'<DataItem DataType="{number}" Precision="{values.dtype.itemsize}" '
        f'Dimensions="{dims}" Format="HDF">{escape(where)}:/{escape(key)}</DataItem>'
    )
