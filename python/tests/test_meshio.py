"""Models built from meshio meshes: the same results as the command line reading the same Gmsh
file itself, and a mesh made in memory."""
import numpy as np
import pytest

import velum

meshio = pytest.importorskip("meshio")

from conftest import SOURCE  # noqa: E402

DATA = SOURCE / "tests" / "cli" / "data"

# The command-line tests' square (tests/cli/cli_cases.py): left edge held, a corner pulled.
REST = {
    "materials": {"iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0}},
    "sections": [{"elements": "sheet", "material": "iso", "thickness": 0.1}],
    "boundary": [{"nodes": "left", "fix": ["x", "y", "z"]}, {"nodes": "sheet", "fix": ["z"]}],
    "loads": [{"type": "point", "nodes": "corner", "force": [0.1, 0.1, 0]}],
    "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.5}},
    "output": {"interval": 0.5, "history": [
        {"name": "ux", "quantity": "displacement", "node": 3, "component": "x"},
        {"name": "uy", "quantity": "displacement", "node": 3, "component": "y"},
        {"name": "Rx", "quantity": "reaction", "nodes": "left", "component": "x"}]},
}


@pytest.mark.parametrize("msh", ["square_quad4_v41.msh", "square_quad4_v22.msh",
                                 "square_quad9_v41_binary.msh"])
def test_meshio_mesh_matches_the_gmsh_file(tmp_path, run_cli, msh):
    from_file = velum.Model(dict(REST, mesh={"file": str(DATA / msh)}))
    p = run_cli("run", from_file.save(tmp_path / "file.yaml"), "-o", tmp_path / "cli",
                "--threads", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    cli = velum.open_results(tmp_path / "cli")

    m = velum.Model(dict(REST, mesh=velum.mesh_from_meshio(meshio.read(DATA / msh))))
    assert sorted(m["mesh"]["node_sets"]) == ["corner", "left", "sheet"]
    assert [g["set"] for g in m["mesh"]["elements"]] == ["sheet"]  # "left" stays a curve
    r = velum.run(m, output=tmp_path / "py", threads=1, quiet=True)
    assert r.status == "converged"
    for col in ("ux", "uy", "Rx"):
        assert np.allclose(r.history[col], cli.history[col], rtol=1e-10, atol=1e-14), col
    assert r.history["ux"][-1] > 0 and r.history["Rx"][-1] == pytest.approx(-0.1, rel=1e-6)


def test_meshio_mesh_in_memory_with_cables(tmp_path):
    # Two triangles and a cable along their shared diagonal, built in memory.
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]])
    cells = [meshio.CellBlock("triangle", np.array([[0, 1, 2], [0, 2, 3]])),
             meshio.CellBlock("line", np.array([[0, 2], [0, 1]]))]
    mesh = meshio.Mesh(points, cells,
                       cell_sets={"sheet": [np.array([0, 1]), np.array([], dtype=int)],
                                  "diagonal": [np.array([], dtype=int), np.array([0])],
                                  "bottom": [np.array([], dtype=int), np.array([1])]},
                       point_sets={"far": np.array([2])})
    d = velum.mesh_from_meshio(mesh, cables=["diagonal"])
    groups = {(g["set"], g["type"]): g["connectivity"].tolist() for g in d["elements"]}
    assert groups == {("sheet", "tri3"): [[1, 2, 3], [1, 3, 4]], ("diagonal", "cable2"): [[1, 3]]}
    assert d["node_sets"]["bottom"].tolist() == [1, 2] and d["node_sets"]["far"].tolist() == [3]
    m = velum.Model({"mesh": d,
                     "materials": {"iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3,
                                           "density": 1.0},
                                   "rope": {"type": "cable", "E": 1.0e5, "density": 1.0}},
                     "sections": [{"elements": "sheet", "material": "iso", "thickness": 0.1},
                                  {"elements": "diagonal", "material": "rope", "area": 0.01}],
                     "boundary": [{"nodes": "bottom", "fix": ["x", "y", "z"]},
                                  {"nodes": "sheet", "fix": ["z"]}],
                     "loads": [{"type": "point", "nodes": "far", "force": [0, 1.0, 0]}],
                     "analysis": {"type": "static", "time": {"end": 1.0, "step": 1.0}},
                     "output": {"history": [{"name": "uy", "quantity": "displacement",
                                             "node": 3, "component": "y"}]}})
    r = velum.run(m, output=tmp_path, threads=1, quiet=True)
    assert r.history["uy"][-1] > 0
    assert {b.set for b in r.blocks} == {"sheet", "diagonal"}
    assert r.frame(-1).force[r.cells("diagonal")][0] > 0  # the diagonal cable is in tension
