"""examples/python at a small size: the fibre-angle study and the gore post-processing run and
write their table and figures."""
import csv
import os
import subprocess
import sys

import pytest

from conftest import SOURCE

EXAMPLES = SOURCE / "examples" / "python"


def run_script(*args):
    env = dict(os.environ)
    p = subprocess.run([sys.executable, *map(str, args)], capture_output=True, text=True, env=env,
                       timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


def test_fibre_study_and_gore_stress(tmp_path):
    out = tmp_path / "study"
    run_script(EXAMPLES / "c9_fibre_study.py", "--small", "--angles", "30", "60", "--out", out)
    rows = list(csv.DictReader(open(out / "study.csv")))
    assert [float(r["angle"]) for r in rows] == [30, 60]
    for r in rows:
        assert r["status"] == "converged"
        assert 0 < float(r["skirt_diameter"]) < 28 and float(r["max_stress"]) > 0
    assert (out / "fibre_angle.png").stat().st_size > 10000
    # The two angles give different canopies.
    assert float(rows[0]["skirt_diameter"]) != pytest.approx(float(rows[1]["skirt_diameter"]),
                                                             rel=1e-4)

    text = run_script(EXAMPLES / "gore_stress.py", out / "angle_60", out / "c9.yaml",
                      "--out", tmp_path / "gore.png")
    lines = [ln.split() for ln in text.splitlines() if ln.startswith("  ")]
    assert len(lines) == 3  # the small model: 3 quad9 along the radius
    dist = [float(ln[0]) for ln in lines]
    assert dist == sorted(dist) and dist[0] > 0
    assert all(float(ln[1]) >= float(ln[2]) for ln in lines)  # max principal >= min principal
    assert (tmp_path / "gore.png").stat().st_size > 10000
