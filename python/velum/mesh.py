"""Inline meshes from numpy arrays or from a meshio mesh: the dict that goes into
``model["mesh"]``. Connectivities and node sets given here are 0-based row indices into the
points (as in meshio); the dict holds the node ids the model file uses."""
from collections.abc import Mapping

import numpy as np

# meshio cell type -> Velum element type (both in VTK/Gmsh node order, which agree for these).
MESHIO_TYPES = {"triangle": "tri3", "triangle6": "tri6", "quad": "quad4", "quad8": "quad8",
                "quad9": "quad9", "line": "cable2", "line3": "cable3"}
_CORNERS = {"tri3": 3, "tri6": 6, "quad4": 4, "quad8": 8, "quad9": 9, "cable2": 2, "cable3": 3}


def mesh(points, elements, node_sets=None, node_ids=None):
    """An inline mesh.

    points:    (N, 3) coordinates (or (N, 2): z = 0)
    elements:  {set name: (type, connectivity)} or a list of (set, type, connectivity);
               type one of tri3 tri6 quad4 quad8 quad9 cable2 cable3, connectivity (E, k)
               0-based indices into points in Gmsh node order
    node_sets: {name: indices into points} (or {name: {"box": [...]}}, kept as is)
    node_ids:  the nodes' ids (default 1..N)
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise ValueError(f"points: expected an (N, 3) or (N, 2) array, got shape {points.shape}")
    if points.shape[1] == 2:
        points = np.hstack([points, np.zeros((len(points), 1))])
    n = len(points)
    ids = np.arange(1, n + 1) if node_ids is None else np.asarray(node_ids, dtype=np.int64)
    if ids.shape != (n,):
        raise ValueError(f"node_ids: expected {n} ids, got shape {ids.shape}")
    if len(np.unique(ids)) != n:
        raise ValueError("node_ids: ids must be unique")
    items = elements.items() if isinstance(elements, Mapping) else (
        (s, (t, c)) for s, t, c in elements)
    groups = []
    for set_name, (etype, conn) in items:
        conn = np.asarray(conn, dtype=np.int64)
        if etype not in _CORNERS:
            raise ValueError(f"elements[{set_name!r}]: unknown type {etype!r} "
                             f"(one of {', '.join(_CORNERS)})")
        if conn.ndim != 2 or conn.shape[1] != _CORNERS[etype]:
            raise ValueError(f"elements[{set_name!r}]: {etype} needs (E, {_CORNERS[etype]}) "
                             f"connectivity, got shape {conn.shape}")
        if conn.size and (conn.min() < 0 or conn.max() >= n):
            raise ValueError(f"elements[{set_name!r}]: indices must be in 0..{n - 1}")
        groups.append({"set": str(set_name), "type": etype, "connectivity": ids[conn]})
    out = {"nodes": np.column_stack([ids.astype(float), points]), "elements": groups}
    if node_sets:
        out["node_sets"] = {}
        for name, idx in node_sets.items():
            if isinstance(idx, Mapping):
                out["node_sets"][str(name)] = dict(idx)
            else:
                out["node_sets"][str(name)] = ids[np.asarray(idx, dtype=np.int64)]
    return out


def mesh_from_meshio(m, cables=(), element_sets=None):
    """An inline mesh from a meshio.Mesh (meshio.read of a .msh, .vtu, .inp, ...).

    Element sets are meshio's cell sets (Gmsh physical groups): a set of surface cells becomes
    a membrane element set; a set of line cells becomes a cable element set only when named
    in ``cables`` (a boundary curve otherwise). Every cell set also becomes a node set of its
    cells' nodes, and point sets become node sets. Without cell sets, all surface cells form
    the set "all" (line cells are left out). ``element_sets`` restricts which cell sets become
    element sets. Cell types Velum has no element for (vertices, volumes) are
    used for node sets only.
    """
    points = np.asarray(m.points, dtype=float)
    cell_sets = {k: v for k, v in (m.cell_sets or {}).items() if not k.startswith("gmsh:")}
    if not cell_sets:
        cell_sets = _gmsh_physical_sets(m)
    elements, node_sets = [], {}
    if cell_sets:
        for name, per_block in cell_sets.items():
            nodes = []
            for block, idx in zip(m.cells, per_block):
                if idx is None:
                    continue
                idx = np.asarray(idx, dtype=np.int64)
                if idx.size == 0:
                    continue
                conn = np.asarray(block.data)[idx]
                nodes.append(conn.ravel())
                etype = MESHIO_TYPES.get(block.type)
                if etype is None or (element_sets is not None and name not in element_sets):
                    continue
                if etype.startswith("cable") and name not in cables:
                    continue
                elements.append((name, etype, conn))
            if nodes:
                node_sets[name] = np.unique(np.concatenate(nodes))
    else:
        for block in m.cells:
            etype = MESHIO_TYPES.get(block.type)
            if etype is not None and not etype.startswith("cable"):
                elements.append(("all", etype, np.asarray(block.data)))
    for name, idx in (m.point_sets or {}).items():
        node_sets.setdefault(name, np.asarray(idx, dtype=np.int64))
    # One group per (set, type): merge blocks of the same set and type.
    merged = {}
    for name, etype, conn in elements:
        merged.setdefault((name, etype), []).append(conn)
    groups = [(s, t, np.vstack(c)) for (s, t), c in merged.items()]
    if not groups:
        raise ValueError("the meshio mesh has no membrane or cable cells in its sets")
    used = np.unique(np.concatenate([c.ravel() for _, _, c in groups] +
                                    [v for v in node_sets.values()]))
    # Points no cell or set uses (Gmsh's geometry points) are dropped; ids follow meshio's
    # row numbers + 1.
    keep = np.zeros(len(points), dtype=bool)
    keep[used] = True
    new_index = np.cumsum(keep) - 1
    ids = np.nonzero(keep)[0] + 1
    return mesh(points[keep], [(s, t, new_index[c]) for s, t, c in groups],
                node_sets={k: new_index[v] for k, v in node_sets.items()}, node_ids=ids)


def _gmsh_physical_sets(m):
    """Cell sets from Gmsh physical tags (meshio gives no cell sets for Gmsh 2.2 files): named
    by $PhysicalNames (field_data), else by their tag, as Velum's own Gmsh reader does."""
    tags = (m.cell_data or {}).get("gmsh:physical")
    if not tags:
        return {}
    names = {}
    for name, (tag, dim) in (m.field_data or {}).items():
        names[(int(tag), int(dim))] = name
    dims = {"vertex": 0, "line": 1, "line3": 1, "triangle": 2, "triangle6": 2, "quad": 2,
            "quad8": 2, "quad9": 2}
    sets = {}
    for b, (block, block_tags) in enumerate(zip(m.cells, tags)):
        dim = dims.get(block.type, 3)
        for tag in np.unique(block_tags):
            name = names.get((int(tag), dim), str(int(tag)))
            per_block = sets.setdefault(name, [np.zeros(0, dtype=np.int64)] * len(m.cells))
            per_block[b] = np.flatnonzero(np.asarray(block_tags) == tag)
    return sets
