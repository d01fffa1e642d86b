"""code_aster SSNL100 (validation manual V6.02.100): a cable fixed at O, over a pulley P1 at
the foot of a 10 m suspension from C and over a fixed pulley P2, spans 100 m, 30 N/m, E A 5e7 N,
10 m more cable given between O and P2. Published sag at both mid-spans 13.930 m (the
inextensible catenary of 105 m over 100 m); the elastic catenary gives 13.939 m. Velum: cable2
elements in the spans, sliding_cable chains over the pulleys (Q1 P1 R1, Q2 P2 R2), meshed in the
posed state's unstretched shape (a parabola of 105 m per span), gravity, static."""
import csv
import json
import math
import os
import subprocess
import sys

velum, out = sys.argv[1:3]
os.makedirs(out, exist_ok=True)
n, w, EA, span, length = 50, 30.0, 5.0e7, 100.0, 105.0
area, g = 1.0e-3, 9.81


def chords(f):
    xs = [span * i / n for i in range(n + 1)]
    zs = [-4 * f * x * (span - x) / span**2 for x in xs]
    return xs, zs, sum(math.dist((xs[i], zs[i]), (xs[i + 1], zs[i + 1])) for i in range(n))


lo, hi = 1.0, 30.0  # the parabola whose chords sum to the span's material length
for _ in range(100):
    mid = 0.5 * (lo + hi)
    lo, hi = (mid, hi) if chords(mid)[2] < length else (lo, mid)
xs, zs, _ = chords(0.5 * (lo + hi))
nodes, nid = [], {}
for side, x0 in ((0, 0.0), (1, span)):
    for i in range(n + 1):
        key = (side, i) if not (side == 1 and i == 0) else (0, n)
        if key not in nid:
            nid[key] = len(nodes) + 1
            nodes.append([nid[key], x0 + xs[i], 0.0, zs[i]])
P1, P2 = nid[(0, n)], nid[(1, n)]
C, R2 = len(nodes) + 1, len(nodes) + 2
nodes += [[C, span, 0.0, 10.0], [R2, 2 * span + 10.0, 0.0, 0.0]]
left = [nid[(0, i)] for i in range(n + 1)]
right = [nid[(1, i) if i else (0, n)] for i in range(n + 1)]
plain = [[left[i], left[i + 1]] for i in range(n - 1)] + [[right[i], right[i + 1]] for i in range(1, n - 1)]
model = {
    "title": "code_aster SSNL100: a cable over two pulleys, two equal spans",
    "mesh": {"nodes": nodes, "elements": [
        {"set": "spans", "type": "cable2", "connectivity": plain},
        {"set": "pulleys", "type": "sliding_cable",
         "connectivity": [[left[n - 1], P1, right[1]], [right[n - 1], P2, R2]]},
        {"set": "suspension", "type": "cable2", "connectivity": [[C, P1]]}]},
    "materials": {"line": {"type": "cable", "E": EA / area, "density": w / (area * g)},
                  "hanger": {"type": "cable", "E": EA / area, "density": 1.0e-6}},
    "sections": [{"elements": "spans", "material": "line", "area": area},
                 {"elements": "pulleys", "material": "line", "area": area},
                 {"elements": "suspension", "material": "hanger", "area": area}],
    "boundary": [{"nodes": [1, C, P2, R2], "fix": ["x", "y", "z"]},
                 {"nodes": [i for i in range(2, C) if i != P2], "fix": ["y"]}],
    "loads": [{"type": "gravity", "acceleration": [0, 0, -g]}],
    "analysis": {"type": "static", "time": {"end": 1.0, "step": 0.25}},
    "output": {"interval": 1.0, "history": [
        {"name": "zl", "quantity": "position", "node": left[n // 2], "component": "z"},
        {"name": "zr", "quantity": "position", "node": right[n // 2], "component": "z"},
        {"name": "xp", "quantity": "position", "node": P1, "component": "x"}]},
}
path = os.path.join(out, "ssnl100.yaml")
open(path, "w").write(json.dumps(model))
subprocess.run([velum, "run", path, "-o", os.path.join(out, "run"), "--threads", "1", "--quiet"],
               check=True)
last = {k.strip(): float(v) for k, v in
        list(csv.DictReader(open(os.path.join(out, "run", "history.csv"))))[-1].items()}
published, elastic = 13.930, 13.939193
errs = [abs(-last[k] - published) / published for k in ("zl", "zr")]
errs_el = [abs(-last[k] - elastic) / elastic for k in ("zl", "zr")]
print(f"SSNL100: sags {-last['zl']:.4f} m, {-last['zr']:.4f} m; against the published 13.930: "
      f"{errs[0]:.2e}, {errs[1]:.2e}; against the elastic catenary 13.939: {errs_el[0]:.2e}, "
      f"{errs_el[1]:.2e}; P1 moved {last['xp'] - span:.2e} m")
sys.exit(0 if max(errs) < 2e-3 and max(errs_el) < 1e-3 else 1)
