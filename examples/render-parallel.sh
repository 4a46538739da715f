#!/usr/bin/env bash
# Render SCENE as N tiles with GNU parallel and merge them into OUT.
#
#   examples/render-parallel.sh SCENE OUT [N] [render options...]
#
# On one machine:      examples/render-parallel.sh flake.nff flake.png 16 --spp 16
# Across machines:     SSHLOGIN=4/alice@node1,4/alice@node2 examples/render-parallel.sh ...
#   (each node needs `render` on its PATH; the scene is sent with
#   --transferfile and each part comes back with --return, then the local
#   machine merges them).
set -euo pipefail
scene=${1:?usage: render-parallel.sh SCENE OUT [N] [render options...]}
out=${2:?usage: render-parallel.sh SCENE OUT [N] [render options...]}
n=${3:-16}
shift $(( $# < 3 ? $# : 3 ))
render=${RENDER:-render}
nffmerge=${NFFMERGE:-nffmerge}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$scene" "$work/scene.nff"
cd "$work"
remote=()
if [ -n "${SSHLOGIN:-}" ]; then
  remote=(--sshlogin "$SSHLOGIN" --transferfile scene.nff --return 'part-{}.exr' --cleanup)
fi
seq 0 $((n - 1)) | parallel --halt now,fail=1 "${remote[@]}" \
  "$render" scene.nff --tile "{}/$n" -o "part-{}.exr" -q "$@"
cd - >/dev/null
"$nffmerge" "$work"/part-*.exr -o "$out"
