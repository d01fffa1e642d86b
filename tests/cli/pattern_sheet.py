#!/usr/bin/env python3
"""Issue 45: velum pattern draws PDIR/patterns.png, a sheet of every flat panel with its areas,
through Debian's /usr/bin/python3 and matplotlib. Checks that it is written, a non-empty PNG,
where matplotlib is there; and that without matplotlib (a stand-in package on PYTHONPATH that
fails to import) the patterns are still written, exit 0, and a note says why the PNG is not.
Usage: pattern_sheet.py VELUM WORKDIR."""
import os
import subprocess
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pattern_roundtrip import model  # noqa: E402  (the hypar in four strip panels)


def has_matplotlib():
    return subprocess.run(["/usr/bin/python3", "-c", "import matplotlib"],
                          capture_output=True).returncode == 0


def main():
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, "hypar.yaml")
    with open(path, "w") as f:
        f.write(model())
    failures = []

    def pattern(out, env=None):
        p = subprocess.run([exe, "pattern", path, "-o", out], capture_output=True, text=True,
                           timeout=120, env=env)
        print(f"{out}: exit {p.returncode}; {p.stderr.strip()}")
        return p

    out = os.path.join(work, "with")
    p = pattern(out)
    png = os.path.join(out, "patterns.png")
    if has_matplotlib():
        if p.returncode != 0:
            failures.append(f"velum pattern: exit {p.returncode}: {p.stderr}")
        elif not os.path.isfile(png) or os.path.getsize(png) < 1000:
            failures.append(f"{png}: not written or empty")
        elif open(png, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
            failures.append(f"{png}: not a PNG")
        else:
            print(f"{png}: {os.path.getsize(png)} bytes")
    else:
        print("matplotlib is missing in /usr/bin/python3: only the note is checked")
        if p.returncode != 0 or "patterns.png not written" not in p.stderr:
            failures.append(f"without matplotlib: exit {p.returncode}, {p.stderr!r}")

    # matplotlib that fails to import: the note, the cutting files, exit 0.
    fake = os.path.join(work, "fake")
    os.makedirs(os.path.join(fake, "matplotlib"), exist_ok=True)
    with open(os.path.join(fake, "matplotlib", "__init__.py"), "w") as f:
        f.write('raise ImportError("No module named matplotlib", name="matplotlib")\n')
    out = os.path.join(work, "without")
    p = pattern(out, dict(os.environ, PYTHONPATH=fake))
    if p.returncode != 0 or "matplotlib is missing, patterns.png not written" not in p.stderr:
        failures.append(f"without matplotlib: exit {p.returncode}, {p.stderr!r}")
    if os.path.exists(os.path.join(out, "patterns.png")):
        failures.append("without matplotlib: patterns.png written")
    if not os.path.isfile(os.path.join(out, "panel_1.dxf")):
        failures.append("without matplotlib: the DXF files are missing")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
