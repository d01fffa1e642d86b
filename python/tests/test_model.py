"""velum.Model: loading, editing, building from arrays, saving YAML that `velum check` accepts."""
import math

import numpy as np
import pytest

import velum


def test_load_gives_dicts_and_arrays(square):
    m = velum.load(square)
    assert isinstance(m, velum.Model) and m.name == str(square)
    assert list(m)[:3] == ["title", "mesh", "materials"]
    assert m["materials"]["fabric"] == {"type": "isotropic", "E": 1.0e5, "nu": 0.3,
                                        "density": 1.0}
    nodes = m["mesh"]["nodes"]
    assert isinstance(nodes, np.ndarray) and nodes.shape == (81, 4) and nodes.dtype == float
    assert nodes[40].tolist() == [41, 0.5, 0.5, 0.0]
    conn = m["mesh"]["elements"][0]["connectivity"]
    assert conn.dtype == np.int64 and conn.shape == (64, 4) and conn[0].tolist() == [1, 2, 11, 10]
    assert m["mesh"]["node_sets"]["rim"] == {"box": [-0.01, -0.01, -0.01, 1.01, 0.01, 0.01]}
    assert m["mesh"]["node_sets"]["edge"].dtype == np.int64
    assert m["boundary"][0]["fix"] == ["x", "y", "z"]
    assert m["analysis"]["time"]["adaptive"] is True


def test_check_statistics(square):
    s = velum.check(square)
    assert (s["nodes"], s["elements"], s["dofs"]) == (81, 64, 3 * 81 - 3 * 32)
    assert s["materials"] == {"fabric": "isotropic"}
    assert s["node_ids"].tolist() == list(range(1, 82))


def test_save_round_trip_and_command_line_check(tmp_path, run_cli, square):
    m = velum.load(square)
    m["materials"]["fabric"]["E"] = 0.1 + 0.2  # a float whose shortest text has 17 digits
    m["title"] = "a title: with a colon # and a hash"
    path = m.save(tmp_path / "saved.yaml")
    p = run_cli("check", path)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "is valid" in p.stdout
    back = velum.load(path)
    assert back["materials"]["fabric"]["E"] == 0.1 + 0.2  # every bit
    assert back["title"] == m["title"]
    assert np.array_equal(back["mesh"]["nodes"], m["mesh"]["nodes"])
    assert back["output"]["history"] == m["output"]["history"]
    assert back["loads"] == m["loads"]


def test_save_rewrites_relative_paths(tmp_path):
    (tmp_path / "a").mkdir()
    m = velum.Model({"mesh": {"file": "sheet.msh"}, "output": {"directory": "results"}},
                    base_dir=tmp_path / "a")
    (tmp_path / "b").mkdir()
    text = m.to_yaml(base_dir=tmp_path / "b")
    assert "file: ../a/sheet.msh" in text and "directory: ../a/results" in text
    assert m["mesh"]["file"] == "sheet.msh"  # the model itself is unchanged


def test_scalars_keep_their_types(tmp_path):
    m = velum.Model({"title": "1e5", "analysis": {"type": "static"}, "x": [True, None, "y",
                                                                           "yes", 3, -0.0]})
    back = velum.load(m.save(tmp_path / "m.yaml"))
    assert back["title"] == "1e5"  # quoted: stays text
    assert back["x"][:5] == [True, None, "y", "yes", 3]
    assert math.copysign(1, back["x"][5]) == -1


def plate(n=4):
    """A unit square of n x n quad4 under pressure, edges fixed, from numpy arrays."""
    g = np.linspace(0, 1, n + 1)
    X, Y = np.meshgrid(g, g)
    points = np.column_stack([X.ravel(), Y.ravel()])
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    quads = np.column_stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(),
                             idx[1:, :-1].ravel()])
    edge = np.unique(np.concatenate([idx[0], idx[-1], idx[:, 0], idx[:, -1]]))
    m = velum.Model()
    m["mesh"] = velum.mesh(points, {"sheet": ("quad4", quads)}, node_sets={"edge": edge},
                           node_ids=np.arange(len(points)) + 101)
    m["materials"] = {"fabric": {"type": "isotropic", "E": 1.0e5, "nu": 0.3, "density": 1.0}}
    m["sections"] = [{"elements": "sheet", "material": "fabric", "thickness": 0.01}]
    m["boundary"] = [{"nodes": "edge", "fix": ["x", "y", "z"]}]
    m["loads"] = [{"type": "pressure", "elements": "sheet", "value": 5.0, "function": "ramp"}]
    m["functions"] = {"ramp": {"type": "ramp", "duration": 0.05}}
    m["analysis"] = {"type": "dynamic", "time": {"end": 0.06, "step": 0.002},
                     "damping": {"mass": 20.0}}
    m["output"] = {"interval": 0.02,
                   "history": [{"name": "w", "quantity": "displacement",
                                "node": int(101 + idx[n // 2, n // 2]), "component": "z"}]}
    return m


def test_model_from_arrays_runs_and_saves(tmp_path, run_cli):
    m = plate()
    s = m.check()
    assert (s["nodes"], s["elements"]) == (25, 16)
    assert s["node_ids"][0] == 101
    r = velum.run(m, output=tmp_path / "out", threads=1, quiet=True)
    assert r.history["w"][-1] > 0
    path = m.save(tmp_path / "plate.yaml")
    assert run_cli("check", path).returncode == 0


def test_mesh_rejects_bad_arrays():
    with pytest.raises(ValueError, match="quad4 needs"):
        velum.mesh(np.zeros((4, 3)), {"s": ("quad4", [[0, 1, 2]])})
    with pytest.raises(ValueError, match="indices must be"):
        velum.mesh(np.zeros((4, 3)), {"s": ("quad4", [[0, 1, 2, 4]])})
    with pytest.raises(ValueError, match="unknown type"):
        velum.mesh(np.zeros((4, 3)), {"s": ("hex8", [[0, 1, 2, 3]])})
