#!/usr/bin/env python3
"""Packs .gltf files with an external .bin (and external images) into self-contained .glb files, for
the fuzz_gltf seed corpus (the fuzzer feeds one file's bytes, so nothing external resolves).

  scripts/gltf_seeds.py OUT_DIR FILE.gltf...
  e.g. after `ctest -R scene_gltf` (its files stay in build/tests/scene/prw-test-tmp-<pid>/):
  scripts/gltf_seeds.py tests/fuzz/corpus/gltf build/tests/scene/prw-test-tmp-*/strip.gltf
"""
import base64, json, os, struct, sys


def pack(path):
    d = json.load(open(path))
    base = os.path.dirname(path)
    binary = b""
    if d.get("buffers"):
        uri = d["buffers"][0].get("uri")
        if uri and not uri.startswith("data:"):
            binary = open(os.path.join(base, uri), "rb").read()
            del d["buffers"][0]["uri"]
            d["buffers"][0]["byteLength"] = len(binary)
    for img in d.get("images", []):
        uri = img.get("uri")
        if uri and not uri.startswith("data:"):
            data = open(os.path.join(base, uri), "rb").read()
            img["uri"] = "data:image/png;base64," + base64.b64encode(data).decode()
    j = json.dumps(d, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(j), 0x4E4F534A) + j
    if binary:
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    out = sys.argv[1]
    for f in sys.argv[2:]:
        name = os.path.splitext(os.path.basename(f))[0] + ".glb"
        open(os.path.join(out, name), "wb").write(pack(f))
        print(os.path.join(out, name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
