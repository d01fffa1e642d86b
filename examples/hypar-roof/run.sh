#!/bin/sh
# The hypar roof: form finding, then 0.5 kN/m² snow on the found shape (elastic, and with
# wrinkling), then the figures; then the same roof as one staged model (form finding,
# prestress, snow, gust as analysis steps). From this folder: ./run.sh [path/to/velum]
set -e
VELUM=${1:-../../build/release/velum}
/usr/bin/python3 make_model.py hypar-form.yaml
"$VELUM" run hypar-form.yaml -o out/form
/usr/bin/python3 snow_model.py out/form/form.yaml out
"$VELUM" run out/snow.yaml
"$VELUM" run out/snow-wrinkling.yaml
PYTHONPATH=../../build/release/python /usr/bin/python3 plot.py out
/usr/bin/python3 staged_model.py hypar-form.yaml out/hypar-staged.yaml
"$VELUM" run out/hypar-staged.yaml
PYTHONPATH=../../build/release/python /usr/bin/python3 staged_numbers.py out
# The edge cables in sleeves (one sliding_cable chain per edge), beside fixed ones: form
# finding, prestress and snow as steps of one model each (README.md, "Edge cables in sleeves").
/usr/bin/python3 sleeve_model.py out
for m in sleeve sleeve-friction fixed; do "$VELUM" run out/hypar-$m.yaml; done
/usr/bin/python3 sleeve_numbers.py out
# The same roof meshed with triangles and cut into five panels along the warp: cutting
# patterns (the DXF files kept in patterns/), then the round trip, per panel (README.md).
/usr/bin/python3 pattern_model.py hypar-pattern.yaml out/pattern-form
"$VELUM" run hypar-pattern.yaml
"$VELUM" seams out/pattern-form -o out/hypar-panels.yaml   # the geodesic seams cut in
"$VELUM" pattern out/hypar-panels.yaml -o out/patterns
mkdir -p patterns && cp out/patterns/*.dxf patterns/
"$VELUM" run out/patterns/roundtrip.yaml -o out/roundtrip
/usr/bin/python3 pattern_numbers.py out/roundtrip out/patterns --check 0.005
