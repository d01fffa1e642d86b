"""Results of a run as numpy arrays, read from the files the run wrote (docs/model-format.md):
summary.json, history.csv, steps.csv and the ParaView frames. What Python sees is what the
command line writes, to the digit.
"""
import csv
import json
import re
import xml.etree.ElementTree as ET
from collections import namedtuple
from pathlib import Path

import numpy as np

CellBlock = namedtuple("CellBlock", "set type ids start stop")
CellBlock.__doc__ = ("One element block in frame order: its element set, type, the user's "
                     "element ids, and its cells start:stop in the frames' cell arrays.")


class Results:
    """What a run wrote into ``directory``.

    ``status`` and ``summary`` are summary.json's; ``history`` maps each history.csv column
    (``"time"`` first) to a numpy array; ``steps`` maps steps.csv's columns to arrays (the
    residuals as a list of arrays); ``times`` holds the frames' times and ``frame(i)`` reads
    frame i (negative counts from the end). ``node_ids`` are the user's node ids in the frames'
    point order; ``blocks`` the element blocks in the frames' cell order.
    """

    def __init__(self, directory, node_ids=None, blocks=None, stopped=False, warnings=()):
        self.directory = Path(directory)
        self.node_ids = None if node_ids is None else np.asarray(node_ids)
        self.blocks = []
        start = 0
        for b in blocks or []:
            ids = np.asarray(b["ids"])
            self.blocks.append(CellBlock(b["set"], b["type"], ids, start, start + len(ids)))
            start += len(ids)
        self.stopped = bool(stopped)
        self.warnings = list(warnings)
        self._history = None
        self._steps = None
        self._times = None

    def __repr__(self):
        return (f"<velum.Results {str(self.directory)!r}: {self.status}, "
                f"{self.summary.get('steps')} steps, {len(self.times)} frames>")

    @property
    def summary(self):
        with open(self.directory / "summary.json") as f:
            return json.load(f)

    @property
    def status(self):
        """"converged" or "failed", as in summary.json."""
        return self.summary["status"]

    @property
    def history(self):
        if self._history is None:
            self._history = read_csv_columns(self.directory / "history.csv")
        return self._history

    @property
    def steps(self):
        if self._steps is None:
            self._steps = read_csv_columns(self.directory / "steps.csv")
        return self._steps

    @property
    def times(self):
        """The frames' times (results.pvd)."""
        if self._times is None:
            self._times, self._frame_files = _read_pvd(self.directory / "results.pvd")
        return self._times

    def __len__(self):
        return len(self.times)

    def frame(self, i):
        """Frame i (negative: from the end) as a ``Frame``."""
        n = len(self.times)
        if n == 0:
            raise IndexError(f"{self.directory}: no frames (output.fields is false, or the "
                             "run stopped before its first output)")
        if not -n <= i < n:
            raise IndexError(f"frame {i} out of range: {n} frames")
        i %= n
        return Frame(self.directory / self._frame_files[i], self._times[i], self.node_ids,
                     self.blocks)

    @property
    def frames(self):
        """Every frame, read one at a time."""
        return (self.frame(i) for i in range(len(self.times)))

    def cells(self, element_set):
        """Indices into the frames' cell arrays of the cells of an element set."""
        parts = [np.arange(b.start, b.stop) for b in self.blocks if b.set == element_set]
        if not parts:
            raise KeyError(f"no element set {element_set!r} (sets: "
                           f"{sorted({b.set for b in self.blocks})})")
        return np.concatenate(parts)


class Frame:
    """One ParaView frame: ``points`` (N, 3) reference coordinates, ``displacement`` and
    ``velocity`` (N, 3), ``position`` = points + displacement; the cell fields
    (``true_stress_max``, ``true_stress_min``, ``stress_dir_max``, ``stress_dir_min``,
    ``fiber_angle_change``, ``force`` and any others the run wrote) in ``cell_data`` and as
    attributes; the point fields (``reaction``, ``node_id`` and the cell fields averaged to
    the nodes, docs/model-format.md) in ``point_data``; ``connectivity`` as a list of
    point-index arrays, one per cell."""

    def __init__(self, path, time, node_ids=None, blocks=()):
        self.path = Path(path)
        self.time = float(time)
        self.node_ids = node_ids
        self.blocks = blocks
        read = read_pvtu if self.path.suffix == ".pvtu" else read_vtu
        arrays, self.point_data, self.cell_data = read(self.path)
        self.point_names, self.cell_names = list(self.point_data), list(self.cell_data)
        self.points = arrays["Points"].reshape(-1, 3)
        offsets = arrays["offsets"]
        conn = arrays["connectivity"]
        self.connectivity = np.split(conn, offsets[:-1])
        self.cell_types = arrays["types"]

    @property
    def displacement(self):
        return self.point_data["displacement"]

    @property
    def velocity(self):
        return self.point_data["velocity"]

    @property
    def position(self):
        return self.points + self.displacement

    def __getattr__(self, name):
        data = self.__dict__.get("cell_data", {})
        if name in data:
            return data[name]
        raise AttributeError(name)

    def __repr__(self):
        return (f"<velum.Frame t = {self.time:.6g}: {len(self.points)} points, "
                f"{len(self.cell_types)} cells>")


def read_csv_columns(path):
    """A CSV file with a header row as {column: numpy array}; a column that is not numeric
    (steps.csv's residuals) becomes a list of arrays of its space-separated numbers."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    head, body = rows[0], [r for r in rows[1:] if r]
    out = {}
    for j, name in enumerate(head):
        col = [r[j] for r in body]
        try:
            out[name] = np.array([float(v) for v in col])
        except ValueError:
            out[name] = [np.array([float(x) for x in v.split()]) for v in col]
    return out


def _read_pvd(path):
    if not path.exists():
        return np.zeros(0), []
    sets = ET.parse(path).getroot().findall("./Collection/DataSet")
    return np.array([float(d.get("timestep")) for d in sets]), [d.get("file") for d in sets]


_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1",
          "UInt64": "<u8", "Int8": "i1"}
_ARRAY = re.compile(rb"<DataArray ([^>]*?)/?>")
_ATTR = re.compile(rb'(\w+)="([^"]*)"')


def read_vtu(path):
    """The arrays of a VTK XML unstructured grid with raw appended data (as Velum writes
    them): ({name: array} of the points and cells, {name: point array}, {name: cell array});
    a point and a cell array may share a name (the cell values averaged to the nodes).
    Multi-component arrays are (n, components)."""
    raw = Path(path).read_bytes()
    marker = raw.find(b'<AppendedData encoding="raw">')
    if marker < 0:
        raise ValueError(f"{path}: not a VTU file with raw appended data")
    base = raw.index(b"_", marker) + 1
    header = raw[:marker]
    point_start, cell_start = header.find(b"<PointData"), header.find(b"<CellData")
    point_end, cell_end = header.find(b"</PointData>"), header.find(b"</CellData>")
    arrays, point_data, cell_data = {}, {}, {}
    for m in _ARRAY.finditer(header):
        attrs = {k.decode(): v.decode() for k, v in _ATTR.findall(m.group(1))}
        at = base + int(attrs["offset"])
        nbytes = int(np.frombuffer(raw, "<u8", 1, at)[0])
        data = np.frombuffer(raw, _TYPES[attrs["type"]], nbytes // np.dtype(
            _TYPES[attrs["type"]]).itemsize, at + 8).copy()
        comps = int(attrs.get("NumberOfComponents", "1"))
        if comps > 1:
            data = data.reshape(-1, comps)
        name = attrs["Name"]
        if point_start <= m.start() < point_end:
            point_data[name] = data
        elif cell_start <= m.start() < cell_end:
            cell_data[name] = data
        else:
            arrays[name] = data
    return arrays, point_data, cell_data


def read_pvtu(path):
    """A frame of a run on several processes (a .pvtu naming one piece per process) as
    ``read_vtu`` gives a one-process frame: the pieces put together in the one-process point
    and cell order by their ``node_index`` and ``cell_index`` arrays (which are dropped)."""
    path = Path(path)
    root = ET.parse(path).getroot()
    pieces = [read_vtu(path.parent / p.get("Source")) for p in root.iter("Piece")]
    if not pieces:
        raise ValueError(f"{path}: no pieces")
    nodes = [pd["node_index"] for _, pd, _ in pieces]
    cells = [cd["cell_index"] for _, _, cd in pieces]
    n_points = 1 + max(int(n.max()) for n in nodes if n.size)
    n_cells = 1 + max((int(c.max()) for c in cells if c.size), default=-1)

    def scatter(parts, index, size):
        first = parts[0]
        out = np.zeros((size,) + first.shape[1:], first.dtype)
        for part, at in zip(parts, index):
            out[at] = part
        return out

    point_data = {name: scatter([pd[name] for _, pd, _ in pieces], nodes, n_points)
                  for name in pieces[0][1] if name != "node_index"}
    cell_data = {name: scatter([cd[name] for _, _, cd in pieces], cells, n_cells)
                 for name in pieces[0][2] if name != "cell_index"}
    arrays = {"Points": scatter([a["Points"].reshape(-1, 3) for a, _, _ in pieces], nodes,
                                n_points)}
    # Each cell's nodes, renumbered to the one-process points, in the one-process cell order.
    conn = [None] * n_cells
    types = np.zeros(n_cells, np.uint8)
    for (a, _, _), at_nodes, at_cells in zip(pieces, nodes, cells):
        starts = np.concatenate(([0], a["offsets"][:-1]))
        for k, c in enumerate(at_cells):
            conn[c] = at_nodes[a["connectivity"][starts[k]:a["offsets"][k]]]
            types[c] = a["types"][k]
    arrays["connectivity"] = np.concatenate(conn) if conn else np.zeros(0, np.int64)
    arrays["offsets"] = np.cumsum([len(c) for c in conn]).astype(np.int64)
    arrays["types"] = types
    for name in pieces[0][0]:
        if name not in arrays:  # TIME
            arrays[name] = pieces[0][0][name]
    return arrays, point_data, cell_data
