"""A Velum model in Python: the model file as a dict that a script reads and edits.

``Model`` holds exactly the keys of the model file (docs/model-format.md): ``m["materials"]``,
``m["sections"]``, ``m["loads"]``, ``m["analysis"]``, ``m["output"]`` ... are plain dicts and
lists; the inline mesh is numpy: ``m["mesh"]["nodes"]`` an (N, 4) float array of rows
[id, x, y, z], each ``m["mesh"]["elements"][i]["connectivity"]`` an (E, k) int array of node
ids. The model is read and validated by the same reader as ``velum run`` when it is run or
checked, so every key means what it means in a file.
"""
import copy
import json
import math
import os
import re
from collections.abc import Mapping, MutableMapping
from pathlib import Path

import numpy as np

from . import _velum
from ._run import run_model
from .errors import InputError


class Model(MutableMapping):
    """A model: a dict of the model file's sections, with where it came from.

    ``name`` starts every message about it (the file name for a loaded model); ``base_dir`` is
    the directory that relative paths in it (``mesh.file``, ``output.directory``) start from.
    """

    def __init__(self, data=None, *, name="model", base_dir="."):
        self._data = dict(data) if data is not None else {}
        self.name = str(name)
        self.base_dir = Path(base_dir)

    # The mapping: the model file's top-level sections.
    def __getitem__(self, key):
        return self._data[key]

    def __setitem__(self, key, value):
        self._data[key] = value

    def __delitem__(self, key):
        del self._data[key]

    def __iter__(self):
        return iter(self._data)

    def __len__(self):
        return len(self._data)

    def __repr__(self):
        mesh = self._data.get("mesh") or {}
        nodes = mesh.get("nodes") if isinstance(mesh, Mapping) else None
        n = len(nodes) if nodes is not None else 0
        return f"<velum.Model {self.name!r}: {n} inline nodes, sections {list(self._data)}>"

    def copy(self):
        """A deep copy (arrays included) that can be edited independently."""
        return Model(copy.deepcopy(self._data), name=self.name, base_dir=self.base_dir)

    def check(self):
        """Validates the model as ``velum check`` does; its statistics as a dict, or
        ``velum.InputError``."""
        return check(self)

    def run(self, output=None, threads=0, quiet=False, progress=None):
        """``velum.run(self, output, threads, quiet, progress)``."""
        # stacklevel 3: a warning points at the caller of Model.run.
        return run_model(self, output, threads, quiet, progress, stacklevel=3)

    def to_yaml(self, base_dir=None):
        """The model as YAML text. Relative paths are rewritten for a file in ``base_dir``
        (default: the model's own base_dir, i.e. unchanged)."""
        data = self._data
        if base_dir is not None:
            data = _rebased(data, self.base_dir, Path(base_dir))
        return _emit(data)

    def save(self, path):
        """Writes the model as a YAML model file that ``velum check`` and ``velum run`` accept.
        Relative ``mesh.file`` and ``output.directory`` are rewritten relative to the new file
        so that they still name the same mesh and results directory (without
        ``output.directory``, results go to ``out`` next to the new file, as for any model
        file). Returns the path."""
        path = Path(path)
        text = self.to_yaml(base_dir=path.parent if str(path.parent) else Path("."))
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(text)
        os.replace(tmp, path)
        return path


def load(path):
    """Reads a model file into a ``Model`` (YAML syntax errors raise ``velum.InputError``; the
    model itself is validated when it is checked or run)."""
    path = Path(path)
    data = _velum.read_yaml(str(path))
    if not isinstance(data, dict):
        raise InputError([f"{path}:1: the model file must be a mapping of sections (mesh, "
                          "materials, sections, ...)"])
    _mesh_to_arrays(data)
    return Model(data, name=str(path), base_dir=path.parent)


def check(model):
    """Validates a model (a ``Model``, a dict or a file path) as ``velum check`` does and returns
    its statistics: title, nodes, elements, dofs, blocks, materials, warnings, node_ids."""
    model = as_model(model)
    return _velum.check(model._data, model.name, str(model.base_dir))


def as_model(model):
    if isinstance(model, Model):
        return model
    if isinstance(model, (str, os.PathLike)):
        return load(model)
    if isinstance(model, Mapping):
        return Model(model)
    raise TypeError(f"expected a velum.Model, a dict or a model file path, not "
                    f"{type(model).__name__}")


# ---- numpy arrays for the inline mesh ---------------------------------------------------------

def _rectangular(rows, width=None):
    """rows as a 2-D list when every row is a list of numbers of one length, else None."""
    if not isinstance(rows, list) or not rows:
        return None
    n = width or (len(rows[0]) if isinstance(rows[0], list) else 0)
    for r in rows:
        if not isinstance(r, list) or len(r) != n:
            return None
        for v in r:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                return None
    return rows


def _int_list(v):
    return (isinstance(v, list) and v and
            all(isinstance(i, int) and not isinstance(i, bool) for i in v))


def _mesh_to_arrays(data):
    """Inline nodes, connectivities, element ids and node-id sets become numpy arrays; anything
    malformed stays as read so that the reader reports it with its key."""
    mesh = data.get("mesh")
    if not isinstance(mesh, dict):
        return
    if _rectangular(mesh.get("nodes"), 4) is not None:
        mesh["nodes"] = np.array(mesh["nodes"], dtype=float)
    for group in mesh.get("elements") or []:
        if not isinstance(group, dict):
            continue
        conn = _rectangular(group.get("connectivity"))
        if conn is not None and all(_int_list(r) for r in conn):
            group["connectivity"] = np.array(conn, dtype=np.int64)
        if _int_list(group.get("ids")):
            group["ids"] = np.array(group["ids"], dtype=np.int64)
    sets = mesh.get("node_sets")
    if isinstance(sets, dict):
        for k, v in sets.items():
            if _int_list(v):
                sets[k] = np.array(v, dtype=np.int64)


# ---- YAML output ---------------------------------------------------------------------------

_PLAIN = re.compile(r"^[A-Za-z_./][A-Za-z0-9_.\-/]*$")
_NUMERIC = re.compile(r"^[-+]?(\.inf|\.nan|[0-9.]+([eE][-+]?[0-9]+)?)$", re.IGNORECASE)
_RESERVED = {"true", "false", "yes", "no", "on", "off", "y", "n", "null", "~"}


def _text(s):
    if _PLAIN.match(s) and not _NUMERIC.match(s) and s.lower() not in _RESERVED:
        return s
    return json.dumps(s)  # a double-quoted YAML string


def _number(v):
    v = float(v)
    if math.isnan(v):
        return ".nan"
    if math.isinf(v):
        return ".inf" if v > 0 else "-.inf"
    if v.is_integer() and abs(v) < 1e15 and not (v == 0 and math.copysign(1, v) < 0):
        return str(int(v))  # node ids in a float array stay integers; the value is the same
    return repr(v)  # shortest text that reads back to the same double


def _scalar(v):
    if v is None:
        return "null"
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return _number(v)
    if isinstance(v, str):
        return _text(v)
    if isinstance(v, os.PathLike):
        return _text(os.fspath(v))
    raise TypeError(f"cannot write a {type(v).__name__} into a model file")


def _is_scalar(v):
    return not isinstance(v, (Mapping, list, tuple, np.ndarray))


def _flow(v):
    """v in flow style ({a: 1, b: [1, 2]}), or None when it holds long or nested lists."""
    if _is_scalar(v):
        return _scalar(v)
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (list, tuple)):
        if len(v) > 12 and not all(_is_scalar(x) for x in v):
            return None
        parts = [_flow(x) for x in v]
        if any(p is None for p in parts):
            return None
        return "[" + ", ".join(parts) + "]"
    parts = []
    for k, x in v.items():
        f = _flow(x)
        if f is None:
            return None
        parts.append(f"{_text(str(k))}: {f}")
    return "{" + ", ".join(parts) + "}"


def _emit_value(out, v, indent):
    """Writes the value of a key (after "key:") at the given indentation."""
    pad = " " * indent
    f = _flow(v)
    if f is not None and (len(f) + indent <= 100 or _is_scalar(v)):
        out.append(" " + f + "\n")
        return
    if isinstance(v, np.ndarray):
        v = v.tolist()
    out.append("\n")
    if isinstance(v, Mapping):
        for k, x in v.items():
            out.append(f"{pad}{_text(str(k))}:")
            _emit_value(out, x, indent + 2)
        return
    for x in v:
        f = _flow(x)
        if f is not None:
            out.append(f"{pad}- {f}\n")
        elif isinstance(x, Mapping):
            first = True
            for k, y in x.items():
                out.append(f"{pad}- " if first else f"{pad}  ")
                out.append(f"{_text(str(k))}:")
                _emit_value(out, y, indent + 4)
                first = False
        else:
            out.append(f"{pad}-")
            _emit_value(out, x, indent + 2)


def _emit(data):
    out = ["# Written by velum (Python). Units: the model's own, never converted.\n"]
    for k, v in data.items():
        out.append(f"{_text(str(k))}:")
        _emit_value(out, v, 2)
    return "".join(out)


def _rebased(data, old_base, new_base):
    """data with relative mesh.file and output.directory rewritten from old_base to new_base."""
    def move(p):
        if not isinstance(p, str) or os.path.isabs(p):
            return p
        return os.path.relpath(os.path.join(old_base, p), new_base)

    if Path(os.path.abspath(old_base)) == Path(os.path.abspath(new_base)):
        return data
    data = dict(data)
    mesh = data.get("mesh")
    if isinstance(mesh, Mapping) and "file" in mesh:
        data["mesh"] = dict(mesh, file=move(mesh["file"]))
    out = data.get("output")
    if isinstance(out, Mapping) and "directory" in out:
        data["output"] = dict(out, directory=move(out["directory"]))
    return data
