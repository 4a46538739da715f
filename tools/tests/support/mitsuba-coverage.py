"""Renders a Mitsuba 3 scene's coverage: the albedo AOV of the scene as
exported (white matte materials give 1 where a shape is hit, 0 elsewhere),
16 samples a pixel, written as an 8-bit PGM. Run with the Python of the
virtual environment scripts/install-test-tools.sh makes (pip mitsuba).
usage: python mitsuba-coverage.py SCENE.xml OUT.pgm"""
import sys

import mitsuba as mi

mi.set_variant("scalar_rgb")
scene = mi.load_file(sys.argv[1])
image = mi.render(scene, integrator=mi.load_dict({"type": "aov", "aovs": "a:albedo"}), spp=16)
height, width, channels = image.shape
values = image.array
pixels = bytes(
    max(0, min(255, round(255 * values[i * channels]))) for i in range(width * height)
)
with open(sys.argv[2], "wb") as out:
    out.write(b"P5\n%d %d\n255\n" % (width, height))
    out.write(pixels)
