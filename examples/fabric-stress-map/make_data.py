#!/usr/bin/python3
"""Writes biaxial.csv: a SYNTHETIC biaxial test of a PVC-coated polyester fabric at the
EN 17117-1 load ratios (engineering strain, nominal stress in kN/m), made from a stiffening
law with warp-fill interaction and strain noise of 2e-4, for the fitting example. Real lab
data go in the same columns (docs/materials.md, "Fitting biaxial tests")."""
import numpy as np

RATIOS = {"1:1": (1, 1), "2:1": (2, 1), "1:2": (1, 2), "1:0": (1, 0), "0:1": (0, 1)}


def stress(E):
    e1, e2 = E
    return np.array([600 * e1 + 150 * e2 + 9000 * e1**3 + 4000 * e1 * e2**2,
                     150 * e1 + 400 * e2 + 20000 * e2**3 + 3000 * e1**2 * e2])


def strain(S):
    E = np.zeros(2)
    for _ in range(60):  # Newton with a difference Jacobian
        J = np.column_stack([(stress(E + 1e-7 * d) - stress(E - 1e-7 * d)) / 2e-7
                             for d in np.eye(2)])
        E = E - np.linalg.solve(J, stress(E) - S)
    return E


rng = np.random.default_rng(17117)
with open("biaxial.csv", "w") as f:
    f.write("# SYNTHETIC biaxial test (make_data.py), PVC/PES-like, loading branches only\n"
            "# engineering strain (-), nominal stress (kN/m)\n"
            "ratio,strain_warp,strain_fill,stress_warp,stress_fill\n")
    for ratio, (a, b) in RATIOS.items():
        for t in np.linspace(1.0, 30.0, 30):
            S = t * np.array([a, b]) / max(a, b)
            lam = np.sqrt(1 + 2 * strain(S))
            eps = lam - 1 + 2e-4 * rng.standard_normal(2)
            P = lam * S
            f.write(f"{ratio},{eps[0]:.6f},{eps[1]:.6f},{P[0]:.4f},{P[1]:.4f}\n")
