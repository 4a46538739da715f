# A UV sphere on a ground quad, both textured: the sphere with a coloured
# checker (16 x 8 squares), the ground with a two-tone tile; external PNGs.
import json, struct, zlib, base64, math
def png(w, h, px, path):
    raw = b"".join(b"\0" + bytes(c for p in px[y*w:(y+1)*w] for c in p) for y in range(h))
    def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
pal = [(230,57,70),(241,250,238),(69,123,157),(255,183,3),(42,157,143),(131,56,236),(251,133,0),(29,53,87)]
W, H = 64, 32
png(W, H, [pal[((x//4) + (y//4)*3) % 8] if ((x//4)+(y//4)) % 2 == 0 else (250,250,250) for y in range(H) for x in range(W)], "sphere.png")
png(8, 8, [(90,90,100) if ((x//4)+(y//4)) % 2 else (200,190,170) for y in range(8) for x in range(8)], "tiles.png")
pos, uv, nrm, idx = [], [], [], []
nu, nv = 32, 16
for j in range(nv+1):
    th = math.pi * j / nv
    for i in range(nu+1):
        ph = 2*math.pi*i/nu
        n = (math.sin(th)*math.cos(ph), math.cos(th), -math.sin(th)*math.sin(ph))
        pos.append((n[0], n[1]+1.0, n[2])); nrm.append(n); uv.append((i/nu, j/nv))
for j in range(nv):
    for i in range(nu):
        a = j*(nu+1)+i; b = a+nu+1
        idx += [a, b, a+1, a+1, b, b+1]
g0 = len(pos)
N = 12
for j in range(N+1):
    for i in range(N+1):
        pos.append((-3 + 6*i/N, 0, -3 + 6*j/N)); nrm.append((0,1,0)); uv.append((i/2, j/2))
gidx = []
for j in range(N):
    for i in range(N):
        a = g0 + j*(N+1) + i; b = a + N + 1
        gidx += [a, b, a+1, a+1, b, b+1]
def f32(v): return b"".join(struct.pack("<%df" % len(t), *t) for t in v)
blobs = [f32(pos), f32(nrm), f32(uv), struct.pack("<%dI" % len(idx), *idx), struct.pack("<%dI" % len(gidx), *gidx)]
views, off, data = [], 0, b""
for b in blobs:
    views.append({"buffer": 0, "byteOffset": off, "byteLength": len(b)}); data += b; off += len(b)
lo = [min(p[k] for p in pos) for k in range(3)]; hi = [max(p[k] for p in pos) for k in range(3)]
doc = {
 "asset": {"version": "2.0", "generator": "nffkit test scene"},
 "scene": 0, "scenes": [{"nodes": [0, 1]}],
 "nodes": [{"mesh": 0}, {"mesh": 1}],
 "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
 "bufferViews": views,
 "accessors": [
  {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
  {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
  {"bufferView": 2, "componentType": 5126, "count": len(pos), "type": "VEC2"},
  {"bufferView": 3, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
  {"bufferView": 4, "componentType": 5125, "count": len(gidx), "type": "SCALAR"}],
 "images": [{"uri": "sphere.png"}, {"uri": "tiles.png"}],
 "samplers": [{"wrapS": 10497, "wrapT": 10497}],
 "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
 "materials": [
  {"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.6}},
  {"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
 "meshes": [
  {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]},
  {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 4, "material": 1}]}]
}
open("textured.gltf", "w").write(json.dumps(doc, indent=1))
