"""`bench/compare-ccx --explicit N`: explicit dynamics side by side with CalculiX (issue 46).

The square of compare-ccx (side 1.2/sqrt(2) m, E = 588 MPa, nu = 0.4, t = 0.6 mm, edges held,
a small dome so that the flat sheet is not singular) on an N x N quad4 mesh, loaded by a 5 kPa
follower pressure ramped linearly from 0 at t = 0 to its full value at the end time, run to
that time by central differences in both codes, each at its own stable step: Velum at its
default safety (0.6 of its estimate since 2026-12-07, 0.9 before: the readings in
docs/performance.md up to then took 2/3 of today's steps), CalculiX's *DYNAMIC, EXPLICIT with its automatic increment (with DIRECT CalculiX
2.20 never advances past t = 0 on membranes). Printed: steps, CPU, CPU per element-step, the
centre's height at the end (CalculiX prints the centre at every increment: that is how its
increments are counted), and the CPU ratio for the same simulated time, printed only when the
two centres agree within 1 % of the centre's travel.

CalculiX's side is a layer of C3D8 bricks of the sheet's thickness, which is what CalculiX
expands an M3D4 membrane into, so its stable step is set by the wave crossing the thickness:
about a hundred times shorter than the membrane's own. M3D4 itself (`--ccx-membrane` adds the
row) is not the same problem in explicit dynamics: measured 2026-12-05, its centre travels one
third of what the load and the sheet's mass give (held load: 5.55 mm against ½ p/(ρt) T² =
16.67 mm of free flight; ramped: 1.85 mm against 5.56 mm), as if the expanded nodes each
carried the whole mass, while its static answers agree with Velum's. The brick layer's centre
agrees with Velum's within 0.2 % of the travel from N = 40 (coarser layers ring: N = 20 is 4 %
short, N = 10 12 % past free flight).
"""
import csv
import json
import math
import os


def write_velum(d, m, end, write_msh):
    write_msh(os.path.join(d, "mesh.msh"), m)
    sets = "\n".join(f"    {k}: [{', '.join(map(str, v))}]" for k, v in m["sets"].items())
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(f"""title: compare-ccx explicit
mesh:
  file: mesh.msh
  node_sets:
{sets}
materials:
  film: {{type: isotropic, E: {m['E']!r}, nu: {m['nu']!r}, density: 1000.0}}
sections:
  - {{elements: sheet, material: film, thickness: {m['t']!r}}}
boundary:
  - {{nodes: edge, fix: [x, y, z]}}
loads:
  - {{type: pressure, elements: sheet, value: {m['p']!r}, function: ramp}}
functions:
  ramp: {{type: table, points: [[0.0, 0.0], [{end!r}, 1.0]]}}
analysis:
  type: dynamic
  integrator: {{scheme: central-difference}}
  time: {{end: {end!r}, step: {end!r}}}
output:
  directory: out
  interval: {end!r}
  fields: false
  history:
    - {{name: zc, quantity: position, node: {m['centre']}, component: z}}
""")


def write_ccx(d, m, end, membrane=False):
    """CalculiX's model: a layer of C3D8 bricks of the sheet's thickness (what CalculiX expands
    an M3D4 membrane into, without the expansion's knot), or M3D4 itself with `membrane`."""
    t, nn = m["t"], max(m["nodes"])
    with open(os.path.join(d, "run.inp"), "w") as f:
        f.write("*HEADING\ncompare-ccx explicit\n*NODE\n")
        for k, (x, y, z) in m["nodes"].items():
            if membrane:
                f.write(f"{k},{x:.12g},{y:.12g},{z:.12g}\n")
            else:  # the lower face at k, the upper one at k + nn
                f.write(f"{k},{x:.12g},{y:.12g},{z - t / 2:.12g}\n")
                f.write(f"{k + nn},{x:.12g},{y:.12g},{z + t / 2:.12g}\n")
        f.write(f"*ELEMENT,TYPE={'M3D4' if membrane else 'C3D8'},ELSET=EALL\n")
        for e, c in enumerate(m["elems"], 1):
            ids = list(c) if membrane else list(c) + [k + nn for k in c]
            f.write(f"{e},{','.join(map(str, ids))}\n")
        f.write("*NSET,NSET=EDGE\n")
        edge = m["sets"]["edge"] + ([] if membrane else [k + nn for k in m["sets"]["edge"]])
        for i in range(0, len(edge), 12):
            f.write(",".join(map(str, edge[i:i + 12])) + "\n")
        centre = m["centre"] if membrane else f"{m['centre']},{m['centre'] + nn}"
        f.write(f"*NSET,NSET=CENTRE\n{centre}\n*BOUNDARY\nEDGE,1,3\n")
        f.write(f"*MATERIAL,NAME=FILM\n*ELASTIC\n{m['E']!r},{m['nu']!r}\n*DENSITY\n1000.\n")
        f.write(f"*MEMBRANE SECTION,ELSET=EALL,MATERIAL=FILM\n{t!r}\n" if membrane else
                "*SOLID SECTION,ELSET=EALL,MATERIAL=FILM\n")
        # the pressure on the lower face (SNEG of the membrane, S1 of the brick) pushes along +z,
        # ramped from 0 to the full load over the step, as Velum's table function
        f.write(f"*SURFACE,NAME=SLOAD,TYPE=ELEMENT\nEALL,{'SNEG' if membrane else 'S1'}\n"
                f"*AMPLITUDE,NAME=RAMP\n0.,0.,{end!r},1.\n")
        f.write(f"*STEP,NLGEOM,INC=100000000\n*DYNAMIC,EXPLICIT\n{end / 100!r},{end!r}\n"
                f"*DSLOAD,AMPLITUDE=RAMP\nSLOAD,P,{m['p']!r}\n*NODE PRINT,NSET=CENTRE,FREQUENCY=1\nU\n"
                "*END STEP\n")


def ccx_centre(d, m, membrane):
    """CalculiX's increments (the centre is printed at every one: the .sta file stays empty in
    explicit runs) and the centre's height at the end (the mean of the brick's two faces)."""
    blocks = open(os.path.join(d, "run.dat")).read().split("displacements")
    vals = [ln.split() for ln in blocks[-1].strip().splitlines()[1:] if ln.split()]
    w = sum(float(v[3]) for v in vals) / len(vals)
    return len(blocks) - 1, m["nodes"][m["centre"]][2] + w


def run(args, square_mesh, write_msh, timed):
    n, end = args.explicit, args.explicit_end
    m = square_mesh(n, incs=1)
    elements = len(m["elems"])
    base = os.path.join(args.out, f"explicit-{n}")
    rows = []
    d = os.path.join(base, "velum")
    os.makedirs(d, exist_ok=True)
    write_velum(d, m, end, write_msh)
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    rc, wall, cpu, rss, out = timed([args.velum, "run", "model.yaml", "-o", "out", "--quiet",
                                     "--threads", "1"], d, env)
    try:
        s = json.load(open(os.path.join(d, "out", "summary.json")))
        steps = s.get("steps", float("nan"))
        hist = list(csv.reader(open(os.path.join(d, "out", "history.csv"))))
        zc = float(hist[-1][1])
    except (OSError, ValueError, IndexError, KeyError):
        steps, zc = float("nan"), float("nan")
    rows.append(dict(code="velum", rc=rc, cpu=cpu, steps=steps, zc=zc))
    for membrane in ([False, True] if args.ccx_membrane else [False]):
        d = os.path.join(base, "ccx-m3d4" if membrane else "ccx")
        os.makedirs(d, exist_ok=True)
        write_ccx(d, m, end, membrane)
        try:
            rc, wall, cpu, rss, out = timed(["ccx", "-i", "run"], d, env, args.ccx_timeout)
        except Exception:  # subprocess.TimeoutExpired
            rc, cpu = -1, float("nan")
        try:
            steps, zc = ccx_centre(d, m, membrane)
        except (OSError, ValueError, IndexError, ZeroDivisionError):
            steps, zc = float("nan"), float("nan")
        rows.append(dict(code="ccx M3D4" if membrane else "ccx C3D8 layer", rc=rc, cpu=cpu,
                         steps=steps, zc=zc))
    print(f"explicit square n = {n} ({elements} quad4), 5 kPa ramped from 0 over {end:g} s, one thread")
    print("| code | exit | steps | CPU s | µs per element-step | centre z at the end [m] |")
    print("|---|---:|---:|---:|---:|---:|")
    for r in rows:
        steps = r["steps"]
        per = 1e6 * r["cpu"] / (elements * steps) if math.isfinite(steps) and steps > 0 else float("nan")
        print(f"| {r['code']} | {r['rc']} | {r['steps']} | {r['cpu']:.3f} | {per:.3f} | {r['zc']:.6g} |")
    z0 = m["nodes"][m["centre"]][2]
    print(f"free flight under the ramp (no membrane force) would reach "
          f"{z0 + m['p'] / (6000.0 * m['t']) * end ** 2:.6g} m (from {z0:.6g} m)")
    v, c = rows[0], rows[1]
    travel = max(abs(v["zc"] - z0), abs(c["zc"] - z0))
    agree = math.isfinite(travel) and travel > 0 and abs(v["zc"] - c["zc"]) <= 0.01 * travel
    if v["cpu"] > 0 and math.isfinite(c["cpu"]) and agree:
        print(f"centres agree within {abs(v['zc'] - c['zc']) / travel:.2%} of the travel")
        print(f"CPU ratio CalculiX / Velum for the same simulated time: {c['cpu'] / v['cpu']:.0f}x")
    else:
        print("no CPU ratio: the runs did not both finish with the same centre "
              "(within 1 % of its travel), so they did not solve the same problem")
    with open(os.path.join(base, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
