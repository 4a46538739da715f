#!/usr/bin/env bash
# Render SCENE as N tiles with GNU parallel and merge them into OUT.
#
#   examples/render-parallel.sh SCENE OUT [N] [render options...]
#
# On one machine:      examples/render-parallel.sh flake.nff flake.png 16 --spp 16
# Across machines:     SSHLOGIN=4/alice@node1,4/alice@node2 examples/render-parallel.sh ...
#   (each node needs `render` on its PATH; the scene is sent with
#   --transferfile into a working folder of its own per job (--workdir ...,
#   so jobs sharing a node never touch each other's files), each part comes
#   back with --return, --cleanup removes both from the node, and the local
#   machine merges them).
# N defaults to 16 (leave it out: options may follow OUT directly).
# RENDER and NFFMERGE name the binaries (default: found on PATH); relative
# paths are taken from the folder the script is started in.
# If the merge fails, the parts are kept and their folder is printed.
set -euo pipefail
usage="usage: render-parallel.sh SCENE OUT [N] [render options...]"
scene=${1:?$usage}
out=${2:?$usage}
shift 2
n=16
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then
  n=$1
  shift
fi
if [ "$n" -lt 1 ]; then
  echo "render-parallel.sh: N must be at least 1" >&2
  exit 2
fi
# Resolve the binaries before changing folder.
binary() {
  case $1 in
    */*) realpath -- "$1" ;;
    *) command -v -- "$1" || { echo "render-parallel.sh: $1 not found on PATH" >&2; exit 2; } ;;
  esac
}
render=$(binary "${RENDER:-render}")
nffmerge=$(binary "${NFFMERGE:-nffmerge}")
out=$(realpath -m -- "$out")
work=$(mktemp -d)
cp -- "$scene" "$work/scene.nff"
cd "$work"
remote=()
if [ -n "${SSHLOGIN:-}" ]; then
  remote=(--sshlogin "$SSHLOGIN" --workdir ... --transferfile scene.nff --return 'part-{}.exr' --cleanup)
  render=${RENDER:-render} # on the nodes, their own
fi
if ! seq 0 $((n - 1)) | parallel --halt now,fail=1 "${remote[@]}" \
  "$render" scene.nff --tile "{}/$n" -o "part-{}.exr" -q "$@"; then
  echo "render-parallel.sh: a tile failed; the parts so far are kept in $work" >&2
  exit 1
fi
if ! "$nffmerge" part-*.exr -o "$out"; then
  echo "render-parallel.sh: the merge failed; the parts are kept in $work" >&2
  exit 1
fi
cd / && rm -rf -- "$work"
