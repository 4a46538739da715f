#!/usr/bin/env bash
# Renders the six faces of the cube map in sky/ with nffkit's own renderer:
# a checkered ground under a blue sky, with a ring of coloured pillars, seen
# from 1.5 above the ground through six 90-degree P3F cameras. A P3F angle
# spans the image edge to edge, so the six views meet exactly; each looks
# along its face's axis with the up the course's cube-map lookup implies
# (docs/p3f.md), so the faces join without seams.
#
#   scenes/p3f/make-sky.sh [SIZE]     (RENDER=path/to/render to choose one)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
render=${RENDER:-render}
size=${1:-256}

world() {
    echo "bclr 0.45 0.62 0.92"
    echo "l 40 80 -30 1 0.97 0.9"
    for i in $(seq -12 11); do
        for j in $(seq -12 11); do
            if (((i + j) % 2 == 0)); then c="0.86 0.84 0.78"; else c="0.22 0.27 0.33"; fi
            x0=$((i * 5)) x1=$((i * 5 + 5)) z0=$((j * 5)) z1=$((j * 5 + 5))
            printf 'f %s 0.9 1 1 1 0 1 0 1\np 4\n%s 0 %s\n%s 0 %s\n%s 0 %s\n%s 0 %s\n' \
                "$c" $x0 $z0 $x0 $z1 $x1 $z1 $x1 $z0
        done
    done
    # Pillars: red at +x, green at -x, yellow at +z, blue at -z, grey between.
    echo "f 0.85 0.2 0.15 0.9 1 1 1 0.1 20 0 1"
    echo "c 25 0 0 2 25 12 0 2"
    echo "f 0.2 0.7 0.25 0.9 1 1 1 0.1 20 0 1"
    echo "c -25 0 0 2 -25 12 0 2"
    echo "f 0.9 0.8 0.2 0.9 1 1 1 0.1 20 0 1"
    echo "c 0 0 25 2 0 12 25 2"
    echo "f 0.2 0.35 0.85 0.9 1 1 1 0.1 20 0 1"
    echo "c 0 0 -25 2 0 12 -25 2"
    echo "f 0.7 0.7 0.7 0.9 1 1 1 0.1 20 0 1"
    for p in "18 18" "-18 18" "18 -18" "-18 -18"; do
        set -- $p
        echo "s $1 3 $2 3"
    done
}

view() { # DIRECTION UP
    printf 'v\nfrom 0 1.5 0\nat %s\nup %s\nangle 90\nhither 0.01\nresolution %s %s\naperture 0\nfocal 1\n' \
        "$1" "$2" "$size" "$size"
}

mkdir -p "$here/sky"
# The course's faces: +x is `left`, -x `right`, +y `top`, -y `bottom`,
# +z `front`, -z `back`; `top` looks up with -z up, `bottom` with +z.
while read -r face ax ay az ux uy uz; do
    { view "$ax $ay $az" "$ux $uy $uz"; world; } | "$render" - --dialect p3f --spp 16 -q -o "$here/sky/$face.png"
done <<'FACES'
right -1 1.5 0 0 1 0
left 1 1.5 0 0 1 0
top 0 2.5 0 0 0 -1
bottom 0 0.5 0 0 0 1
front 0 1.5 1 0 1 0
back 0 1.5 -1 0 1 0
FACES
echo "wrote $here/sky/{right,left,top,bottom,front,back}.png"
