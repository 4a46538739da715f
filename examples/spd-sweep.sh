#!/usr/bin/env bash
# How a tracer's cost grows with an SPD database's size: for each size,
# generate the database with `spd`, render it with the SPD's procedure
# (`render --spd-stats`: 513x513 eye rays, depth 5) and print the primitive
# count, the accelerator's build time and the render time.
#
#   examples/spd-sweep.sh mount 2 4 6 8
#
# Needs `spd` and `render` on PATH (cargo build --release puts them in
# target/release). Extra render options go in RENDER_OPTS, e.g.
# RENDER_OPTS="--accel grid".
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: $0 DATABASE SIZE... (see spd --list)" >&2
    exit 2
fi
db=$1
shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-10s %5s %12s %10s %10s %12s\n' database size primitives build_ms render_s Mrays/s
for size in "$@"; do
    spd "$db" --size "$size" -o "$out/scene.nff"
    # shellcheck disable=SC2086 # RENDER_OPTS is a list of options
    report=$(render "$out/scene.nff" --spd-stats -o "$out/image.png" ${RENDER_OPTS:-} 2>&1)
    primitives=$(sed -n 's/^scene .*: \([0-9]*\) primitives in the file.*/\1/p' <<<"$report")
    build=$(sed -n 's/.* built in \([0-9.]*\) ms.*/\1/p' <<<"$report")
    render_s=$(sed -n 's/.* render \([0-9.]*\) s (\([0-9.]*\) Mrays\/s).*/\1/p' <<<"$report")
    rate=$(sed -n 's/.* render [0-9.]* s (\([0-9.]*\) Mrays\/s).*/\1/p' <<<"$report")
    printf '%-10s %5s %12s %10s %10s %12s\n' "$db" "$size" "$primitives" "$build" "$render_s" "$rate"
done
