"""A time series as XDMF 3 with its arrays in binary HDF5: ``<stem>.xdmf`` (the light XML
ParaView opens) and ``<stem>.h5`` beside it (the heavy data; arrays of ``PACKED_FROM_BYTES`` or more
gzip-compressed).

The mesh is written once (``/mesh/points``, ``/mesh/topology``) and each frame's fields under
``/frames/<k>/point`` and ``/frames/<k>/cell``. The XML holds one temporal collection of one
grid per frame, every grid pointing at the same mesh arrays: ParaView shows one block whose
reference geometry Warp By Vector on "displacement" deforms, and meshio's
``TimeSeriesReader`` reads it back.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import numpy as np

__all__ = ["PACKED_FROM_BYTES", "write_xdmf"]

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
        _dataset(h5, "mesh/points", points)
        topology, count = _topology(cells)
        _dataset(h5, "mesh/topology", topology[1])
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
                    _dataset(h5, key, values)
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

# The smallest array (bytes) written compressed. Below it the filters' set-up costs more than
# they save: a dataset of 500 nodes' vectors (12 kB) takes 0.36 ms gzip-compressed and 0.14 ms
# raw, for 10-20 % of its bytes; a series' frames hold a dataset per field, so a small mesh's
# series spent most of its time there (benchmarks/case_outside_solves.py). 64 KiB: about
# 2,700 nodes' vectors.
PACKED_FROM_BYTES = 65536


def _dataset(h5, key: str, values: np.ndarray) -> None:
    """Write ``values`` as dataset ``key`` of the open HDF5 file ``h5``: compressed when it
    holds ``PACKED_FROM_BYTES`` or more, else contiguous and raw."""
    if values.nbytes >= PACKED_FROM_BYTES:
        h5.create_dataset(key, data=values, **_PACKED)
    else:
        h5.create_dataset(key, data=values)


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
