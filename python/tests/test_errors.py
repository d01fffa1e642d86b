"""Errors from Python: velum.InputError names the key (as the command line does),
velum.SolveError carries the partial results, velum.OutputError for unwritable results."""
import pytest

import velum


def test_input_error_names_the_key(square, run_cli, tmp_path):
    m = velum.load(square)
    m["materials"]["fabric"]["E"] = "stiff"
    with pytest.raises(velum.InputError) as e:
        velum.run(m, output=tmp_path, quiet=True)
    assert f"{square}: materials.fabric.E: expected a number" in e.value.messages
    assert all(msg.startswith(f"{square}: ") for msg in e.value.messages)
    # The same model from its file: the command line says the same, with the line.
    path = m.save(tmp_path / "bad.yaml")
    p = run_cli("check", path)
    assert p.returncode == 1 and "materials.fabric.E: expected a number" in p.stderr
    assert not (tmp_path / "summary.json").exists()  # nothing ran


def test_every_problem_is_reported_with_suggestions(square):
    m = velum.load(square)
    m["materials"]["fabric"]["youngs"] = m["materials"]["fabric"].pop("E")
    m["analysis"]["time"]["stpe"] = 0.1
    m["sections"][0]["material"] = "fabrik"
    with pytest.raises(velum.InputError) as e:
        velum.check(m)
    text = str(e.value)
    assert "materials.fabric.youngs: unknown key" in text
    assert "analysis.time.stpe: unknown key (did you mean 'step'?)" in text
    assert "fabrik" in text
    assert len(e.value.messages) >= 3


def test_values_python_cannot_write():
    m = velum.Model({"title": object()})
    with pytest.raises(TypeError, match="title: cannot write a object"):
        velum.check(m)


def test_yaml_syntax_error_names_the_line(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("mesh:\n  nodes: [[1, 0, 0, 0]\nmaterials: {}\n")
    with pytest.raises(velum.InputError, match=r"bad.yaml:\d+: YAML syntax error"):
        velum.load(bad)
    with pytest.raises(velum.InputError, match="cannot open the model file"):
        velum.load(tmp_path / "missing.yaml")


def test_missing_mesh_file_is_relative_to_the_model(tmp_path, square):
    m = velum.Model(velum.load(square), base_dir=tmp_path)
    m["mesh"] = {"file": "sheet.msh"}
    with pytest.raises(velum.InputError, match="mesh.file"):
        velum.check(m)


def test_solve_error_keeps_the_partial_results(tmp_path, square):
    # A flat sheet has no stiffness against a pressure at its reference state: a static step by
    # plain Newton-Raphson (no line search to start it) is singular however far it is cut
    # (tests/cli/cli_cases.py, solve_fails).
    m = velum.load(square)
    m["analysis"] = {"type": "static", "time": {"end": 1.0, "step": 0.5, "min_step": 0.1},
                     "newton": {"line_search": False}}
    m["output"]["interval"] = 0.5
    with pytest.raises(velum.SolveError) as e:
        velum.run(m, output=tmp_path, threads=1, quiet=True)
    r = e.value.results
    assert "the solve failed at t =" in str(e.value)
    assert r.status == "failed" and r.summary["reason"]
    assert r.summary["final_time"] < 1.0
    assert r.history["time"][0] == 0.0 and r.history["centre_uz"][0] == 0.0
    assert r.frame(0).time == 0.0


def test_output_error(tmp_path, square):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(velum.OutputError):
        velum.run(square, output=blocker / "out", quiet=True)
