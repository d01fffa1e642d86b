"""Reefed canopy (issue 44, examples/reefed-canopy) on a coarse C9 quarter (6 x 1 quad9 per
gore): the reefing line through the 8 seam rings of the skirt is drawn in to 0.4 of its flat
length while the canopy inflates, held, then let out. Reefed, the rings sit on the circle
the line allows: radius g R0 lambda (lambda the line's stretch from its force), so pi d is the
line's length times pi / (n sin(pi / n)) for n rings round the full skirt (the polygon);
disreefed, the line goes slack and the skirt opens past 1.5 times the reefed radius."""
import csv
import math
import os
import subprocess
import sys

velum, example, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
model = os.path.join(out, "coarse.yaml")
subprocess.run([sys.executable, os.path.join(example, "make_model.py"), model, "--along", "6",
                "--across", "1"], check=True)
subprocess.run([velum, "run", model, "-o", os.path.join(out, "run"), "--threads", "1", "--quiet"],
               check=True)
rows = [{k.strip(): float(v) for k, v in r.items()}
        for r in csv.DictReader(open(os.path.join(out, "run", "history.csv")))]
R0, g, EA, n = 14.0, 0.4, 1.8e7 * 1.0e-4, 28
worst, reefed = 0.0, []
for r in rows:
    if 1.0 <= r["time"] <= 1.5:
        # The line's true force T = E A (lambda^2 - 1) / 2 * lambda: its stretch lambda.
        lo, hi = 1.0, 1.5
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if EA * 0.5 * (mid * mid - 1) * mid < r["line_force"] else (lo, mid)
        expected = g * R0 * 0.5 * (lo + hi)
        for radius in (r["ring_first_x"], r["ring_last_y"]):
            worst = max(worst, abs(radius - expected) / expected)
            reefed.append(radius)
line = n * 2 * R0 * math.sin(math.pi / n) * g
d = 2 * sum(reefed) / len(reefed)
opened = [max(r["ring_first_x"], r["ring_last_y"]) for r in rows if r["time"] >= 2.5]
slack = max(r["line_force"] for r in rows if r["time"] >= 2.5)
print(f"reefed: skirt diameter {d:.4f} ft, pi d {math.pi * d:.4f} ft against the line's "
      f"material length {line:.4f} ft (ratio {math.pi * d / line:.4f}; the polygon's "
      f"{math.pi / (n * math.sin(math.pi / n)):.4f} times its stretch); radius against "
      f"g R0 lambda within {worst:.2e}")
print(f"disreefed: skirt diameter {2 * min(opened):.3f} to {2 * max(opened):.3f} ft "
      f"(t >= 2.5 s), line force {slack:.3g} lbf")
sys.exit(0 if worst < 1e-3 and min(opened) > 1.5 * max(reefed) and slack == 0.0 else 1)
