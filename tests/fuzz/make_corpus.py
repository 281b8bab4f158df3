#!/usr/bin/env python3
"""make_corpus.py - writes the seed corpora of tests/fuzz/corpus/<target>/ that are not
copies (the scene seeds are proto/examples/*.json; the EXR seeds come from
fuzz_exr_seeds, which writes them with the server's own EXR encoder). Small, valid files
of every variant a reader accepts, and a few that it refuses, so that libFuzzer starts
from inside the formats. Deterministic: run it again and nothing changes.

    python3 tests/fuzz/make_corpus.py
"""
import gzip
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")


def put(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def scene_seeds():
    src = os.path.join(HERE, "..", "..", "proto", "examples")
    for n in sorted(os.listdir(src)):
        if n.endswith(".json"):
            with open(os.path.join(src, n), "rb") as f:
                put("scene", n, f.read())


# ---- meshes: a tetrahedron (closed, consistently wound) ------------------------------
TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def obj_seeds():
    v = "".join("v %g %g %g\n" % p for p in TET_V)
    put("obj", "tetra.obj", "# tetrahedron\no tet\n" + v + "".join(
        "f %d %d %d\n" % tuple(i + 1 for i in f) for f in TET_F))
    # slashes, negative indices, a quad split into two triangles, ignored statements
    put("obj", "quad_slashes.obj",
        "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
        "g quad\nusemtl m\ns off\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\n")
    put("obj", "crlf_continuation.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 \\\r\n0\r\nf 1 2 3\r\n")
    put("obj", "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")


def ply_header(fmt, nv, nf, extra=""):
    return ("ply\nformat %s 1.0\ncomment seed\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\n%selement face %d\n"
            "property list uchar int vertex_indices\nend_header\n" % (fmt, nv, extra, nf))


def ply_seeds():
    body = "".join("%g %g %g\n" % p for p in TET_V) + "".join(
        "3 %d %d %d\n" % f for f in TET_F)
    put("ply", "tetra_ascii.ply", ply_header("ascii", 4, 4) + body)
    for endian, fmt in (("<", "binary_little_endian"), (">", "binary_big_endian")):
        b = ply_header(fmt, 4, 4).encode()
        b += b"".join(struct.pack(endian + "3f", *p) for p in TET_V)
        b += b"".join(struct.pack(endian + "B3i", 3, *f) for f in TET_F)
        put("ply", "tetra_%s.ply" % fmt, b)
    # a double-typed vertex with an extra property, and a quad with ushort indices
    h = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
         "property double z\nproperty uchar red\nelement face 1\n"
         "property list uchar ushort vertex_indices\nend_header\n")
    put("ply", "quad_double.ply", h + "0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n4 0 1 2 3\n")


# ---- volumes -------------------------------------------------------------------------
def nrrd(fields, data):
    return ("NRRD0004\n# seed\n" + "".join("%s: %s\n" % kv for kv in fields) + "\n").encode() + data


def nrrd_seeds():
    f32 = struct.pack("<8f", *[0.5 * i for i in range(8)])
    put("nrrd", "float_raw.nrrd", nrrd([("type", "float"), ("dimension", "3"),
                                        ("sizes", "2 2 2"), ("endian", "little"),
                                        ("encoding", "raw"), ("spacings", "1 1 1")], f32))
    put("nrrd", "uchar_gzip.nrrd", nrrd([("type", "uchar"), ("dimension", "3"),
                                         ("sizes", "3 2 2"), ("encoding", "gzip")],
                                        gzip.compress(bytes(range(12)), mtime=0)))
    be = struct.pack(">12H", *range(0, 1200, 100))
    put("nrrd", "rgb_ushort_big.nrrd", nrrd([("type", "unsigned short"), ("dimension", "4"),
                                             ("sizes", "3 2 2 1"), ("endian", "big"),
                                             ("encoding", "raw"), ("kinds", "RGB-color space domain domain"),
                                             ("space", "right-anterior-superior"),
                                             ("key", "=value")], be))
    put("nrrd", "double_gz.nrrd", nrrd([("type", "double"), ("dimension", "3"),
                                        ("sizes", "1 1 2"), ("endian", "little"),
                                        ("encoding", "gz")],
                                       gzip.compress(struct.pack("<2d", 1.5, -2.0), mtime=0)))
    put("nrrd", "detached.nrrd", nrrd([("type", "float"), ("dimension", "3"),
                                       ("sizes", "1 1 1"), ("data file", "x.raw"),
                                       ("encoding", "raw")], b""))


def raw_seeds():
    # 4 bytes of query (fuzz_raw.c): type|components|scale bits, dims x y z; then samples
    put("raw", "float32_2x2x2", bytes([0, 2, 2, 2]) + struct.pack("<8f", *range(8)))
    put("raw", "float16_rgb_2x1x1", bytes([1 | 8, 2, 1, 1]) + struct.pack("<6H", *[0x3c00] * 6))
    put("raw", "uint8_scaled_4x2x1", bytes([2 | 32, 4, 2, 1]) + bytes(range(8)))
    put("raw", "uint16_3x1x1", bytes([3, 3, 1, 1]) + struct.pack("<3H", 1, 300, 65535))
    put("raw", "nan_1x1x1", bytes([0, 1, 1, 1]) + struct.pack("<f", float("nan")))


# ---- librefract's stream parsers -----------------------------------------------------
def multipart_seeds():
    ct = "multipart/x-mixed-replace; boundary=refract-frame\n"

    def part(body, seq, extra=""):
        return ("--refract-frame\r\nContent-Type: image/jpeg\r\nContent-Length: %d\r\n"
                "X-Frame-Seq: %d\r\nX-Frame-Kind: full\r\nX-Render-Time-Ms: 12.5\r\n"
                "X-Refract-Irradiance: ready\r\n%s\r\n" % (len(body), seq, extra)).encode() + body + b"\r\n"

    two = part(b"\xff\xd8jpeg-one\xff\xd9", 1) + part(b"\xff\xd8two\xff\xd9", 2, "X-Frame-Repeat: 1\r\n")
    put("multipart", "two_frames", b"\x07" + ct.encode() + two + b"--refract-frame--\r\n")
    put("multipart", "split_by_one", b"\x00" + ct.encode() + two)
    # no Content-Length: the body ends at the next delimiter; LF-only headers; a preamble
    put("multipart", "scan_lf", b"\x10" + b'multipart/x-mixed-replace;boundary="b"\n' +
        b"preamble\r\n--b\nContent-Type: text/plain\n\nhello\r\n--b\n\nworld\r\n--b--\r\nepilogue")
    put("multipart", "lying_length", b"\x03" + ct.encode() +
        b"--refract-frame\r\nContent-Length: 2\r\n\r\nabc\r\n--refract-frame\r\n")


def sse_seeds():
    # byte 0: chunk size - 1; byte 1: max_bytes / 64 - 1 (fuzz_sse.c)
    put("sse", "events", b"\x05\x10" + b": keep-alive\n\nid: 7\nevent: scene.updated\n"
        b"data: {\"id\":\"abc\"}\n\nretry: 1000\ndata: a\ndata: b\n\n")
    put("sse", "bom_crlf_cr", b"\x00\x01" + b"\xef\xbb\xbfdata:x\r\n\r\nevent:e\rdata: y\r\rid\nfield\n\n")
    put("sse", "long_line", b"\xff\x00" + b"data: " + b"z" * 200 + b"\n\n")
    put("sse", "partial", b"\x02\x03" + b"id: 1\x002\ndata: unfinished\n")


def router_seeds():
    # byte 0 also sizes the Allow buffer (fuzz_router.c): 'G' gives 8 bytes, 'P' 17
    lines = ["GET /", "GET /viewer/abc", "GET /assets/viewer.js", "GET /v1/health",
             "GET /metrics", "POST /v1/scenes", "GET /v1/scenes/s1", "DELETE /v1/scenes/s1",
             "PUT /v1/scenes/s1/volumes/density", "PUT /v1/scenes/s1/environment",
             "POST /v1/scenes/s1/meshes", "POST /v1/scenes/s1/render",
             "PUT /v1/scenes/s1/lights/sun", "GET /v1/scenes/s1/irradiance/sun.exr",
             "GET /v1/scenes/s1/irradiance/.exr", "PATCH /v1/views/v1",
             "GET /v1/views/v1/stream", "GET /v1/jobs/j1/frames/3", "GET /v1/jobs/j1/archive",
             "GET /v1/events", "POST /v1/health", "GET /v1/scenes//render", "GET /v1/nope"]
    for i, line in enumerate(lines):
        put("router", "line%02d" % i, line)


if __name__ == "__main__":
    scene_seeds()
    obj_seeds()
    ply_seeds()
    nrrd_seeds()
    raw_seeds()
    multipart_seeds()
    sse_seeds()
    router_seeds()
