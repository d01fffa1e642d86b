#!/usr/bin/env python3
"""Issue 44: the example hypar roof (examples/hypar-roof, sleeve_model.py) with its edge cables
in sleeves (one sliding_cable chain per edge through the fabric's edge nodes), form-found with
the 40 kN prescribed force, checked under its prestress, then under 0.5 kN/m² snow; beside it
the same steps with friction 0.2 in the sleeves and with the fixed edge cables. Checks:
- form finding gives the same edges in sleeves and fixed (the arcs of the isotropic prestress),
  every cable at 40 kN, and the found shape stays put under its prestress alone;
- under snow the sleeve's force is one value along each edge (all four alike by symmetry),
  the fixed cable's varies along the edge (by over 30 %), the sleeve's lies within its range;
- the sleeve lets the edge and the roof move more: deflection and edge sag in sleeves above
  those with friction, above those fixed; the material slips through the sleeve points, less
  with friction.
Usage: hypar_sleeve.py VELUM WORKDIR."""
import os
import subprocess
import sys

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                       "hypar-roof")


def run(args):
    p = subprocess.run(args, capture_output=True, text=True, timeout=240)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(args)}: exit {p.returncode}: {p.stderr}")
    return p.stdout


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    run([sys.executable, os.path.join(EXAMPLE, "sleeve_model.py"), work])
    sys.dont_write_bytecode = True  # no __pycache__ in the example folder
    sys.path.insert(0, EXAMPLE)
    from sleeve_model import VARIANTS
    from sleeve_numbers import report, variant
    for name, _, _ in VARIANTS:
        run([exe, "run", os.path.join(work, f"hypar-{name}.yaml"), "-q"])
    v = {name: variant(work, name) for name, _, _ in VARIANTS}
    for x in v.values():
        report(x)
    sleeve, friction, fixed = v["sleeve"], v["sleeve-friction"], v["fixed"]
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    for x in v.values():
        check(x["status"] == "converged", f"{x['name']}: {x['status']}")
        found = x["force"]["found"]
        check(abs(found.min() / 40e3 - 1) < 1e-9 and abs(found.max() / 40e3 - 1) < 1e-9,
              f"{x['name']}: found cable force {found.min()} .. {found.max()} N, not 40 kN")
        check(x["prestress_moved"] < 1e-4,
              f"{x['name']}: the found shape moves {x['prestress_moved']} m under its prestress")
        for e, (plan, _) in x["sag_found"].items():
            check(abs(plan - fixed["sag_found"][e][0]) < 2e-3,
                  f"{x['name']}: found {e} edge sag {plan} m, fixed cables' "
                  f"{fixed['sag_found'][e][0]} m")
    for x in (sleeve, friction):
        f = x["force"]["snow"]
        check(f.max() - f.min() < 1e-9 * f.max(),
              f"{x['name']}: the chains' forces under snow differ: {f.min()} .. {f.max()} N")
    ff = fixed["force"]["snow"]
    check(all(ff[i].max() - ff[i].min() > 0.3 * ff[i].max() for i in range(4)),
          f"fixed: the cable force along an edge varies by less than 30 %: {ff.min()} .. "
          f"{ff.max()} N")
    t = sleeve["force"]["snow"][0][0]
    check(ff.min() < t <= 1.01 * ff.max(),
          f"sleeve force {t} N outside the fixed cable's range {ff.min()} .. {ff.max()} N")
    check(sleeve["deflection"] > friction["deflection"] > fixed["deflection"],
          f"deflections sleeve {sleeve['deflection']}, with friction {friction['deflection']}, "
          f"fixed {fixed['deflection']}: not in this order")
    check(sleeve["drop"] > friction["drop"] > fixed["drop"],
          f"edge sags sleeve {sleeve['drop']}, with friction {friction['drop']}, fixed "
          f"{fixed['drop']}: not in this order")
    s, sf = abs(sleeve["slip"]["south"]), abs(friction["slip"]["south"])
    check(s > sf > 0.01, f"mid-edge slips {s} m in sleeves, {sf} m with friction")
    if failures:
        raise SystemExit("\n".join(failures))
    print("hypar roof in sleeves: ok")


if __name__ == "__main__":
    main()
