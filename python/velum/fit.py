"""Fits sheet laws to biaxial tests of a coated fabric (EN 17117-1 load ratios 1:1, 2:1, 1:2,
1:0, 0:1): (a) the linear orthotropic law (E1, E2, nu12, G12 as `type: orthotropic`), (b) a
stress map (`type: stress_map`: the grid file it reads). Reports the residual per load ratio
and draws data against both fits in a PNG. Guide: docs/materials.md, "Fitting biaxial tests".

    python3 -m velum.fit biaxial.csv [--shear shear.csv] [--name pvc] [--out DIR]

The biaxial CSV has the header `ratio,strain_warp,strain_fill,stress_warp,stress_fill`: the
load ratio as "warp:fill" (e.g. 2:1), the strains (engineering, dL/L0, unless --green) and the
stresses (force per unit reference width, e.g. kN/m, or force per reference area; the fitted
moduli come in the same unit). With --green the columns are already Green-Lagrange strains and
2nd Piola-Kirchhoff stresses. Both fits are linear least-squares problems, solved directly:
(a) on the compliance form (strain = C stress: the strains are what a load-controlled test
measures with error), (b) a polynomial S(E) without constant term, sampled on the grid.
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

BIAXIAL_COLUMNS = ["ratio", "strain_warp", "strain_fill", "stress_warp", "stress_fill"]
SHEAR_COLUMNS = ["shear_strain", "shear_stress"]
GRID_COLUMNS = ["strain_warp", "strain_fill", "stress_warp", "stress_fill"]


class FitError(Exception):
    """Bad input: the message names the file, line and column."""


# ---- reading ---------------------------------------------------------------------------------

def read_table(path, columns, text_columns=()):
    """Rows of a CSV with the given header ('#' comments, blank lines skipped) as dicts, each
    with its 1-based line under '_line'."""
    rows, header = [], None
    with open(path, newline="") as f:
        for ln, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in next(csv.reader([s]))]
            if header is None:
                header = [c.lower() for c in cells]
                if header != columns:
                    raise FitError(f"{path}:{ln}: expected the header '{','.join(columns)}'")
                continue
            if len(cells) != len(columns):
                raise FitError(f"{path}:{ln}: expected {len(columns)} values, got {len(cells)}")
            row = {"_line": ln}
            for c, v in zip(columns, cells):
                if c in text_columns:
                    row[c] = v
                    continue
                try:
                    row[c] = float(v)
                except ValueError:
                    row[c] = math.nan
                if not math.isfinite(row[c]):
                    raise FitError(f"{path}:{ln}: {c}: '{v}' is not a finite number")
            rows.append(row)
    if header is None:
        raise FitError(f"{path}: empty file (expected the header '{','.join(columns)}')")
    return rows


def read_biaxial(path, green=False):
    """{ratio: (E, S)}, E and S (n, 2) arrays of Green-Lagrange strain and 2nd PK stress."""
    rows = read_table(path, BIAXIAL_COLUMNS, text_columns=("ratio",))
    out = {}
    for r in rows:
        parts = r["ratio"].split(":")
        try:
            ok = len(parts) == 2 and all(float(p) >= 0 for p in parts) and \
                sum(float(p) for p in parts) > 0
        except ValueError:
            ok = False
        if not ok:
            raise FitError(f"{path}:{r['_line']}: ratio: expected warp:fill such as 2:1, "
                           f"got '{r['ratio']}'")
        eps = np.array([r["strain_warp"], r["strain_fill"]])
        sig = np.array([r["stress_warp"], r["stress_fill"]])
        if not green:
            if np.any(eps <= -1):
                raise FitError(f"{path}:{r['_line']}: an engineering strain must exceed -1")
            lam = 1 + eps
            E, S = 0.5 * (lam * lam - 1), sig / lam  # P = F S with F = diag(lambda)
        else:
            E, S = eps, sig
        out.setdefault(r["ratio"], ([], []))
        out[r["ratio"]][0].append(E)
        out[r["ratio"]][1].append(S)
    if not out:
        raise FitError(f"{path}: no data rows")
    return {k: (np.array(e), np.array(s)) for k, (e, s) in out.items()}


# ---- (a) the linear orthotropic law -----------------------------------------------------------

def fit_orthotropic(data):
    """Compliance c = (1/E1, -nu12/E1, 1/E2) by least squares on E1 = c11 S1 + c12 S2,
    E2 = c12 S1 + c22 S2 over every point; returns (E1, E2, nu12)."""
    A, b = [], []
    for E, S in data.values():
        for e, s in zip(E, S):
            A.append([s[0], s[1], 0.0])
            b.append(e[0])
            A.append([0.0, s[0], s[1]])
            b.append(e[1])
    A, b = np.array(A), np.array(b)
    if np.linalg.matrix_rank(A) < 3:
        raise FitError("the data do not determine E1, E2 and nu12 (need at least two load "
                       "ratios with independent stresses)")
    c, *_ = np.linalg.lstsq(A, b, rcond=None)
    if c[0] <= 0 or c[2] <= 0:
        raise FitError(f"the fitted compliance is not positive (1/E1 = {c[0]:.4g}, 1/E2 = "
                       f"{c[2]:.4g}): check the data's signs and units")
    return 1 / c[0], 1 / c[2], -c[1] / c[0]


def orthotropic_strain(E1, E2, nu12, S):
    C = np.array([[1 / E1, -nu12 / E1], [-nu12 / E1, 1 / E2]])
    return S @ C.T


def firt_shear_modulus(E1, E2, nu12):
    """Velum's `G12: firt` (src/material/plane_stress.cpp)."""
    nu21 = nu12 * E2 / E1
    return math.sqrt(E1 * E2) / (2 * (1 + math.sqrt(max(nu12 * nu21, 0.0))))


def fit_shear(path):
    rows = read_table(path, SHEAR_COLUMNS)
    g = np.array([r["shear_strain"] for r in rows])
    t = np.array([r["shear_stress"] for r in rows])
    if not np.any(g != 0):
        raise FitError(f"{path}: no non-zero shear strain")
    G = float(g @ t / (g @ g))
    return G, g, t


# ---- (b) the stress map ----------------------------------------------------------------------

def monomials(E, degree):
    """Columns E1^i E2^j, 1 <= i + j <= degree (no constant: zero stress at zero strain)."""
    return np.column_stack([E[:, 0] ** i * E[:, 1] ** (d - i)
                            for d in range(1, degree + 1) for i in range(d + 1)])


def fit_polynomial(data, degree):
    E = np.vstack([e for e, _ in data.values()])
    S = np.vstack([s for _, s in data.values()])
    A = monomials(E, degree)
    if np.linalg.matrix_rank(A) < A.shape[1]:
        raise FitError(f"too few independent points for a map of degree {degree} "
                       f"({A.shape[1]} coefficients per stress): lower --degree")
    coef, *_ = np.linalg.lstsq(A, S, rcond=None)
    return coef


def axis(lo, hi, n):
    """n steps of hi/n from 0 up to hi, and the same steps down to lo when lo < 0."""
    h = hi / n
    down = math.ceil(-lo / h - 1e-9) if lo < 0 else 0
    return np.array([k * h for k in range(-down, n + 1)])


def make_grid(data, coef, degree, n):
    E = np.vstack([e for e, _ in data.values()])
    e1 = axis(E[:, 0].min(), E[:, 0].max(), n)
    e2 = axis(E[:, 1].min(), E[:, 1].max(), n)
    X, Y = np.meshgrid(e1, e2)  # rows over e2, columns over e1
    P = np.column_stack([X.ravel(), Y.ravel()])
    S = monomials(P, degree) @ coef
    S11, S22 = S[:, 0].reshape(X.shape), S[:, 1].reshape(X.shape)
    bad = np.argwhere(np.diff(S11, axis=1) <= 0)
    if bad.size:
        j, i = bad[0]
        raise FitError(f"the fitted warp stress does not increase with the warp strain at "
                       f"E22 = {e2[j]:.4g}, E11 = {e1[i]:.4g}: lower --degree or --points")
    bad = np.argwhere(np.diff(S22, axis=0) <= 0)
    if bad.size:
        j, i = bad[0]
        raise FitError(f"the fitted fill stress does not increase with the fill strain at "
                       f"E11 = {e1[i]:.4g}, E22 = {e2[j]:.4g}: lower --degree or --points")
    return e1, e2, S11, S22


def pchip_slopes(x, y):
    """The slopes velum's stress map uses (src/material/monotone_cubic.cpp)."""
    h, d = np.diff(x), np.diff(y) / np.diff(x)
    n = len(x)
    m = np.empty(n)
    if n == 2:
        return np.array([d[0], d[0]])
    for k in range(1, n - 1):
        if d[k - 1] * d[k] <= 0:
            m[k] = 0
        else:
            w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
            m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k])

    def end(h0, h1, d0, d1):
        s = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
        if s * d0 <= 0:
            return 0.0
        if d0 * d1 <= 0 and abs(s) > abs(3 * d0):
            return 3 * d0
        return s
    m[0] = end(h[0], h[1], d[0], d[1])
    m[-1] = end(h[-1], h[-2], d[-1], d[-2])
    return m


def hermite(x, t):
    """Interval and the weights of (y_i, y_i+1, y'_i, y'_i+1) at t (linear beyond the ends)."""
    i = int(np.clip(np.searchsorted(x, t, side="right") - 1, 0, len(x) - 2))
    x0, h = x[i], x[i + 1] - x[i]
    if t < x0:
        return i, np.array([1, 0, t - x0, 0])
    if t > x0 + h:
        return i, np.array([0, 1, 0, t - x0 - h])
    s = (t - x0) / h
    return i, np.array([2 * s**3 - 3 * s**2 + 1, -2 * s**3 + 3 * s**2,
                        (s**3 - 2 * s**2 + s) * h, (s**3 - s**2) * h])


class StressMap:
    """Velum's interpolation of a grid (S[j, i] at e1[i], e2[j]), for residuals and plots."""

    def __init__(self, e1, e2, S):
        self.e1, self.e2, self.f = e1, e2, S
        self.fx = np.array([pchip_slopes(e1, row) for row in S])
        self.fy = np.array([pchip_slopes(e2, col) for col in S.T]).T
        self.fxy = np.array([pchip_slopes(e2, col) for col in self.fx.T]).T

    def __call__(self, E1, E2):
        i, wx = hermite(self.e1, E1)
        j, wy = hermite(self.e2, E2)
        v = 0.0
        for a in range(4):
            for b in range(4):
                jj, ii = j + b % 2, i + a % 2
                F = (self.f if b < 2 else self.fy) if a < 2 else (self.fx if b < 2 else self.fxy)
                v += wx[a] * wy[b] * F[jj, ii]
        return v


# ---- report ----------------------------------------------------------------------------------

def residuals(data, E1, E2, nu12, map11, map22):
    """Per ratio: RMS strain residual of the linear law (at the measured stresses) and RMS
    stress residual of the map (at the measured strains)."""
    out = {}
    for ratio, (E, S) in data.items():
        lin = np.sqrt(np.mean(np.sum((orthotropic_strain(E1, E2, nu12, S) - E) ** 2, axis=1)))
        Sm = np.array([[map11(*e), map22(*e)] for e in E])
        mp = np.sqrt(np.mean(np.sum((Sm - S) ** 2, axis=1)))
        out[ratio] = (lin, mp, len(E))
    return out


def plot(path, data, E1, E2, nu12, map11, map22):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for k, (ratio, (E, S)) in enumerate(sorted(data.items())):
        col = f"C{k}"
        Elin = orthotropic_strain(E1, E2, nu12, S)
        Sm = np.array([[map11(*e), map22(*e)] for e in E])
        for c, ax in enumerate(axes):
            ax.plot(E[:, c], S[:, c], "o", color=col, ms=3, label=f"{ratio} data")
            ax.plot(Elin[:, c], S[:, c], "-", color=col, lw=1, label=f"{ratio} linear")
            ax.plot(E[:, c], Sm[:, c], "--", color=col, lw=1, label=f"{ratio} map")
    for c, ax in enumerate(axes):
        ax.set_xlabel(["E11 (warp, Green-Lagrange)", "E22 (fill, Green-Lagrange)"][c])
        ax.set_ylabel(["S11 (warp, 2nd PK)", "S22 (fill, 2nd PK)"][c])
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6, ncol=2)
    fig.suptitle("biaxial data against the fitted linear law and stress map")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_grid(path, e1, e2, S11, S22, source):
    with open(path, "w") as f:
        f.write(f"# stress map fitted by velum.fit to {os.path.basename(source)}: Green-Lagrange "
                "strains, 2nd PK stresses\n")
        f.write(",".join(GRID_COLUMNS) + "\n")
        for j, y in enumerate(e2):
            for i, x in enumerate(e1):
                f.write(f"{x:.10g},{y:.10g},{S11[j, i]:.12g},{S22[j, i]:.12g}\n")


def fit(biaxial, shear=None, name="fabric", out=".", degree=3, points=10, green=False,
        png=True, log=None):
    """Both fits; writes OUT/NAME-map.csv (and OUT/NAME-fit.png). Returns a dict of the
    constants, the grid and the residuals per ratio."""
    log = log or sys.stdout
    data = read_biaxial(biaxial, green)
    E1, E2, nu12 = fit_orthotropic(data)
    G = None
    if shear:
        G, _, _ = fit_shear(shear)
    coef = fit_polynomial(data, degree)
    e1, e2, S11, S22 = make_grid(data, coef, degree, points)
    m11, m22 = StressMap(e1, e2, S11), StressMap(e1, e2, S22)
    res = residuals(data, E1, E2, nu12, m11, m22)
    os.makedirs(out, exist_ok=True)
    grid_path = os.path.join(out, f"{name}-map.csv")
    write_grid(grid_path, e1, e2, S11, S22, biaxial)
    png_path = os.path.join(out, f"{name}-fit.png") if png else None
    if png:
        plot(png_path, data, E1, E2, nu12, m11, m22)
    g12 = f"{G:.8g}" if G is not None else "firt  # no shear data: Firt's estimate"
    print(f"# linear orthotropic law (compliance least squares over {sum(len(e) for e, _ in data.values())} points)", file=log)
    print("materials:", file=log)
    print(f"  {name}:", file=log)
    print(f"    type: orthotropic\n    E1: {E1:.8g}\n    E2: {E2:.8g}\n    nu12: {nu12:.8g}"
          f"\n    G12: {g12}\n    density: 1.0  # set", file=log)
    print(f"  {name}_map:", file=log)
    print(f"    type: stress_map\n    map: {os.path.basename(grid_path)}", file=log)
    G_map = G if G is not None else firt_shear_modulus(E1, E2, nu12)
    note = "" if G is not None else "  # no shear data: Firt's estimate"
    print(f"    G12: {G_map:.8g}{note}\n    density: 1.0  # set", file=log)
    print("# residual per load ratio: RMS strain (linear law), RMS stress (map), points",
          file=log)
    for ratio, (lin, mp, n) in sorted(res.items()):
        print(f"#   {ratio:>5}  {lin:.3e}  {mp:.3e}  {n}", file=log)
    return {"E1": E1, "E2": E2, "nu12": nu12, "G12": G, "grid": (e1, e2, S11, S22),
            "residuals": res, "map": grid_path, "png": png_path, "coef": coef}


def main(argv=None):
    ap = argparse.ArgumentParser(prog=os.environ.get("VELUM_FIT_PROG", "python3 -m velum.fit"),
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("biaxial", help="CSV: ratio,strain_warp,strain_fill,stress_warp,stress_fill")
    ap.add_argument("--shear", help="CSV: shear_strain,shear_stress (gamma = 2 E12)")
    ap.add_argument("--name", default="fabric", help="material name (and file prefix)")
    ap.add_argument("--out", default=".", help="folder of NAME-map.csv and NAME-fit.png")
    ap.add_argument("--degree", type=int, default=3, help="polynomial degree of the map fit")
    ap.add_argument("--points", type=int, default=10, help="grid steps over the positive strains")
    ap.add_argument("--green", action="store_true",
                    help="the columns are Green-Lagrange strain and 2nd PK stress")
    ap.add_argument("--no-png", action="store_true")
    a = ap.parse_args(argv)
    try:
        fit(a.biaxial, a.shear, a.name, a.out, a.degree, a.points, a.green, not a.no_png)
    except (FitError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
