"""velum.fit (python/velum/fit.py): recovers the constants of synthetic biaxial data made from a
known orthotropic law to 1e-8 and a known polynomial fabric law's stress map on its grid;
reports residuals near the noise on noisy data; the grid it writes is a map velum accepts;
bad data are named by file and line."""
import os
import subprocess
import sys

import numpy as np
import pytest

from velum import fit as vf

RATIOS = {"1:1": (1, 1), "2:1": (2, 1), "1:2": (1, 2), "1:0": (1, 0), "0:1": (0, 1)}
E1, E2, NU12, G12 = 600.0, 400.0, 0.25, 25.0


def linear_strain(S):
    return vf.orthotropic_strain(E1, E2, NU12, S)


def fabric_stress(E):
    """A stiffening law, a cubic polynomial without constant (what a degree-3 map fits)."""
    e1, e2 = E[..., 0], E[..., 1]
    return np.stack([600 * e1 + 150 * e2 + 9000 * e1**3 + 4000 * e1 * e2**2,
                     150 * e1 + 400 * e2 + 20000 * e2**3 + 3000 * e1**2 * e2], axis=-1)


def fabric_strain(S):
    """E with fabric_stress(E) = S, by Newton from the linear law's strain."""
    E = linear_strain(S)
    for _ in range(50):
        h = 1e-7
        R = fabric_stress(E) - S
        J = np.stack([(fabric_stress(E + h * np.eye(2)[c]) - fabric_stress(E - h * np.eye(2)[c]))
                      / (2 * h) for c in range(2)], axis=-1)
        E = E - np.linalg.solve(J, R[..., None])[..., 0]
    return E


def write_biaxial(path, strain_of, smax=10.0, n=12, noise=0.0, seed=1):
    """Engineering strain and nominal stress along each ratio's stress path."""
    rng = np.random.default_rng(seed)
    with open(path, "w") as f:
        f.write("# synthetic biaxial test\nratio,strain_warp,strain_fill,stress_warp,stress_fill\n")
        for ratio, (a, b) in RATIOS.items():
            for t in np.linspace(smax / n, smax, n):
                S = t * np.array([a, b]) / max(a, b)
                E = strain_of(S)
                lam = np.sqrt(1 + 2 * E)
                eps = lam - 1 + noise * rng.standard_normal(2)
                P = lam * S
                f.write(f"{ratio},{eps[0]!r},{eps[1]!r},{P[0]!r},{P[1]!r}\n")


def write_shear(path):
    g = np.linspace(0, 0.1, 6)
    with open(path, "w") as f:
        f.write("shear_strain,shear_stress\n")
        for x in g:
            f.write(f"{x!r},{G12 * x!r}\n")


def test_recovers_a_linear_law(tmp_path, capsys):
    write_biaxial(tmp_path / "b.csv", linear_strain)
    write_shear(tmp_path / "s.csv")
    r = vf.fit(str(tmp_path / "b.csv"), str(tmp_path / "s.csv"), out=str(tmp_path))
    err = max(abs(r["E1"] / E1 - 1), abs(r["E2"] / E2 - 1), abs(r["nu12"] / NU12 - 1),
              abs(r["G12"] / G12 - 1))
    print(f"linear law recovery, max relative error {err:.2e}", file=sys.stderr)
    assert err < 1e-8
    for ratio, (lin, mp, n) in r["residuals"].items():
        assert lin < 1e-12 and mp < 1e-9 * 10, (ratio, lin, mp)
        assert n == 12
    out = capsys.readouterr().out
    assert "type: orthotropic" in out and "type: stress_map" in out
    assert os.path.getsize(r["png"]) > 10000


def test_recovers_a_fabric_map(tmp_path):
    write_biaxial(tmp_path / "b.csv", fabric_strain, smax=30)
    r = vf.fit(str(tmp_path / "b.csv"), out=str(tmp_path), name="pvc", png=False)
    e1, e2, S11, S22 = r["grid"]
    X, Y = np.meshgrid(e1, e2)
    S = fabric_stress(np.stack([X, Y], axis=-1))
    err = max(np.abs(S11 - S[..., 0]).max(), np.abs(S22 - S[..., 1]).max()) / np.abs(S).max()
    print(f"map recovery on its grid, max relative error {err:.2e}", file=sys.stderr)
    assert err < 1e-8
    for ratio, (lin, mp, n) in r["residuals"].items():
        print(f"  {ratio}: map RMS stress residual {mp:.2e} (interpolation between grid points)",
              file=sys.stderr)
        assert mp < 1e-2 * 30, (ratio, mp)


def test_noisy_data_give_residuals_near_the_noise(tmp_path):
    sigma = 2e-4
    write_biaxial(tmp_path / "b.csv", linear_strain, smax=10, n=40, noise=sigma)
    r = vf.fit(str(tmp_path / "b.csv"), out=str(tmp_path), png=False)
    for ratio, (lin, mp, n) in sorted(r["residuals"].items()):
        print(f"  {ratio}: linear RMS strain residual {lin:.2e} (noise {sigma * np.sqrt(2):.2e})",
              file=sys.stderr)
        # Two strains per point, each with noise sigma (slightly more in Green strain).
        assert 0.5 * sigma * np.sqrt(2) < lin < 2 * sigma * np.sqrt(2), (ratio, lin)
    assert abs(r["E1"] / E1 - 1) < 0.05 and abs(r["E2"] / E2 - 1) < 0.05
    assert abs(r["nu12"] - NU12) < 0.05


def test_the_grid_is_a_map_velum_reads(tmp_path, run_cli):
    write_biaxial(tmp_path / "b.csv", fabric_strain, smax=30)
    r = vf.fit(str(tmp_path / "b.csv"), out=str(tmp_path), name="pvc", png=False)
    (tmp_path / "model.yaml").write_text(f"""mesh:
  nodes: [[1, 0, 0, 0], [2, 1, 0, 0], [3, 1, 1, 0], [4, 0, 1, 0]]
  elements: [{{set: s, type: quad4, connectivity: [[1, 2, 3, 4]]}}]
  node_sets: {{left: [1, 4], right: [2, 3], all: [1, 2, 3, 4]}}
materials:
  pvc: {{type: stress_map, map: {os.path.basename(r["map"])}, G12: 25, density: 1}}
sections: [{{elements: s, material: pvc, thickness: 1}}]
boundary: [{{nodes: left, fix: [x, y, z]}}, {{nodes: all, fix: [z]}}, {{nodes: [1], fix: [y]}}]
loads: [{{type: edge, nodes: right, force_per_length: [10, 0, 0], function: f}}]
functions: {{f: {{type: ramp, duration: 1}}}}
analysis: {{type: static, time: {{end: 1, step: 1}}}}
""")
    p = run_cli("run", tmp_path / "model.yaml", "-o", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr


def test_bad_data_are_named(tmp_path):
    (tmp_path / "b.csv").write_text("ratio,strain_warp,strain_fill,stress_warp,stress_fill\n"
                                    "1:1,0.01,0.01,1,1\n2-1,0.02,0.01,2,1\n")
    with pytest.raises(vf.FitError, match=r"b.csv:3: ratio: expected warp:fill"):
        vf.fit(str(tmp_path / "b.csv"), out=str(tmp_path), png=False)
    (tmp_path / "c.csv").write_text("ratio,strain_warp,strain_fill,stress_warp\n")
    with pytest.raises(vf.FitError, match=r"c.csv:1: expected the header"):
        vf.fit(str(tmp_path / "c.csv"), out=str(tmp_path), png=False)
    (tmp_path / "d.csv").write_text("ratio,strain_warp,strain_fill,stress_warp,stress_fill\n"
                                    "1:1,0.01,x,1,1\n")
    p = subprocess.run([sys.executable, "-m", "velum.fit", str(tmp_path / "d.csv"),
                        "--out", str(tmp_path)], capture_output=True, text=True)
    assert p.returncode == 1 and "d.csv:2: strain_fill: 'x' is not a finite number" in p.stderr
