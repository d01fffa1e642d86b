"""velum.run against `velum run`: the same files to the byte on the same model, results as numpy,
the edit-and-rerun path, and the progress callback."""
import json

import numpy as np
import pytest

import velum


def files_of(directory):
    return sorted(p.relative_to(directory).as_posix() for p in directory.rglob("*") if p.is_file())


def summary_without_clock(directory):
    s = json.loads((directory / "summary.json").read_text())
    s.pop("wall_seconds")
    s.pop("pid", None)
    s.pop("cpu_seconds")  # measured, and the process's peak memory (Python's own in a module run)
    s.pop("peak_memory_mb")
    return s


def test_same_files_as_the_command_line(tmp_path, run_cli, square):
    cli, py = tmp_path / "cli", tmp_path / "py"
    p = run_cli("run", square, "-o", cli, "--threads", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    r = velum.run(velum.load(square), output=py, threads=1, quiet=True)
    assert r.status == "converged"
    assert files_of(cli) == files_of(py)
    for name in files_of(cli):
        if name not in ("summary.json", ".velum.lock"):  # the lock holds the run's pid
            assert (cli / name).read_bytes() == (py / name).read_bytes(), name
    assert summary_without_clock(cli) == summary_without_clock(py)


def test_results_as_numpy(tmp_path, square):
    r = velum.run(square, output=tmp_path, threads=1, quiet=True)
    s = r.summary
    assert s["status"] == "converged" and s["steps"] > 0
    h = r.history
    assert list(h)[:3] == ["time", "centre_uz", "centre_vz"]
    assert isinstance(h["time"], np.ndarray) and len(h["time"]) == len(r.times)
    assert h["time"][-1] == pytest.approx(0.1)
    # The centre bulges along the pressure (+z) and the last frame agrees with the history.
    assert h["centre_uz"][-1] > 0
    f = r.frame(-1)
    assert r.node_ids.shape == (81,) and f.displacement.shape == (81, 3)
    centre = np.flatnonzero(r.node_ids == 41)[0]
    assert f.displacement[centre, 2] == pytest.approx(h["centre_uz"][-1], rel=1e-11)
    assert f.velocity[centre, 2] == pytest.approx(h["centre_vz"][-1], rel=1e-11, abs=1e-15)
    assert f.time == pytest.approx(h["time"][-1])
    assert f.true_stress_max.shape == (64,) and np.all(f.true_stress_max > 0)
    assert f.stress_dir_max.shape == (64, 3)
    assert np.allclose(np.linalg.norm(f.stress_dir_max, axis=1), 1)
    assert [b.set for b in r.blocks] == ["sheet"] and len(r.cells("sheet")) == 64
    assert r.blocks[0].ids.tolist() == list(range(1, 65))
    # steps.csv: one row per accepted step, iterations adding up to the summary's.
    assert len(r.steps["step"]) == s["steps"]
    assert r.steps["iterations"].sum() == s["newton_iterations"]


def test_edit_and_rerun(tmp_path, run_cli, square):
    m = velum.load(square)
    base = velum.run(m, output=tmp_path / "base", threads=1, quiet=True)
    stiff = m.copy()
    stiff["materials"]["fabric"]["E"] = 4 * m["materials"]["fabric"]["E"]
    r = velum.run(stiff, output=tmp_path / "stiff", threads=1, quiet=True)
    # The copy is independent, and four times the stiffness bulges less.
    assert m["materials"]["fabric"]["E"] == 1.0e5
    w0, w1 = base.history["centre_uz"][-1], r.history["centre_uz"][-1]
    assert 0 < w1 < w0
    assert w1 < 0.9 * w0
    # The edited model, saved, runs through the command line to the same files.
    saved = stiff.save(tmp_path / "stiff.yaml")
    p = run_cli("run", saved, "-o", tmp_path / "stiff_cli", "--threads", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    assert ((tmp_path / "stiff_cli" / "history.csv").read_bytes() ==
            (tmp_path / "stiff" / "history.csv").read_bytes())
    # Editing the mesh arrays: the model scaled by 2 in the plane carries the same pressure over
    # a larger span and bulges more.
    big = m.copy()
    big["mesh"]["nodes"][:, 1:3] *= 2
    big["output"]["history"][3]["point"] = [1.02, 1.04, 0.0]
    big["loads"][0]["value"] = 5.0
    r2 = velum.run(big, output=tmp_path / "big", threads=1, quiet=True)
    assert r2.history["centre_uz"][-1] > w0


def test_progress_callback_and_stop(tmp_path, square):
    seen = []
    r = velum.run(square, output=tmp_path / "all", threads=1, quiet=True,
                  progress=lambda t, step, iters: seen.append((t, step, iters)))
    assert seen[0][:2] == (0.0, 0)
    assert [s[1] for s in seen] == list(range(len(seen)))
    assert all(b[0] > a[0] for a, b in zip(seen, seen[1:]))
    assert len(seen) == r.summary["steps"] + 1
    assert sum(s[2] for s in seen) == r.summary["newton_iterations"]
    assert all(s[2] >= 1 for s in seen[1:])

    def stop_at_half(t, step, iters):
        return t < 0.05

    r = velum.run(square, output=tmp_path / "half", threads=1, quiet=True, progress=stop_at_half)
    assert r.stopped and r.status == "failed"
    assert 0.05 <= r.summary["final_time"] < 0.1
    assert "stopped" in r.summary["reason"]


def test_exception_in_callback_is_raised_after_the_summary(tmp_path, square):
    def boom(t, step, iters):
        if step == 3:
            raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        velum.run(square, output=tmp_path, threads=1, quiet=True, progress=boom)
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["status"] == "failed" and s["steps"] == 3


def test_open_results_of_a_command_line_run(tmp_path, run_cli, square):
    assert run_cli("run", square, "-o", tmp_path, "--threads", "1", "--quiet").returncode == 0
    r = velum.open_results(tmp_path, model=square)
    assert r.status == "converged"
    assert r.node_ids[40] == 41 and r.frame(0).time == 0.0
    with pytest.raises(IndexError):
        r.frame(len(r.times))


def test_dict_and_path_models(tmp_path, cable):
    data = dict(velum.load(cable))
    r = velum.run(data, output=tmp_path / "dict", threads=1, quiet=True)
    assert r.status == "converged"
    r2 = velum.run(str(cable), output=tmp_path / "path", threads=1, quiet=True)
    assert np.array_equal(r.history["mid_uz"], r2.history["mid_uz"])


def test_ctrl_c_stops_the_run_and_raises_keyboard_interrupt(tmp_path, square):
    # SIGINT while the solver runs (the GIL released): Python's handler runs at the next step's
    # check, the run stops there, writes summary.json, and KeyboardInterrupt is raised.
    import os
    import signal
    import threading

    m = velum.load(square)
    # 100,000 steps (several seconds; 5,000 ended in 0.33 s on a fast minute, before the timer)
    m["analysis"]["time"].update(step=1.0e-6, adaptive=False)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            velum.run(m, output=tmp_path, threads=1, quiet=True)
    finally:
        timer.cancel()
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["status"] == "failed" and "stopped" in s["reason"]
    assert 0 < s["final_time"] < 0.1
