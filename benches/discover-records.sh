#!/bin/sh
# The records of the `discover` benchmark (benches/benches/fit.rs, `record`) as files, for timing
# and profiling the CLI (issue 33, item 6): a TMMF release hiding its tip adhesion (A1 1.3e5 N/m,
# lambda 0.6 um, jerk 6000 m/s^3 to 3 mm/s), 200 kHz, 1 ms before the trigger, seed 3, with
# 2 000 and 400 000 samples. Usage: benches/discover-records.sh [GEODESIC] [DIR]; then
#   geodesic discover DIR/tmmf-2000.yaml --effects needle_contact,tip_contact --progress
set -eu
B=${1:-target/release/geodesic}
D=${2:-target/discover-records}
mkdir -p "$D"
for n in 2000 400000; do
  post=$(awk "BEGIN { printf \"%.9g\", ($n - 1) / 2e5 - 1e-3 }")
  "$B" synth --scenario tmmf-release --effects needle_contact,tip_contact,tip_adhesion \
    --param tip_adhesion.A1=1.3e5 --param tip_adhesion.lambda=6e-7 --jerk 6000 --v 3e-3 \
    --pre 1e-3 --post "$post" --seed 3 --out "$D/tmmf-$n.yaml"
done
