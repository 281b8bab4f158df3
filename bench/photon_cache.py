#!/usr/bin/env python3
"""photon_cache.py - how fast a moved light's caustic arrives through refractd's photon cache
(docs/photons.md "The cache"; BENCHMARKS.md "Caustic photons", "The cache").

Starts refractd (the binary given) on a free loopback port with a temporary data directory,
creates peer scene A (proto/examples/peer_scene_a.json) with "caustics": "photons" and N
photons per light, and measures through the HTTP API, polling the status every 5 ms:

  - after the scene is created: the time to the map's first pass (usable) and to its last;
  - after the lamp moves (PUT): the same for the new pose, and the answer's status (202);
  - after the lamp moves back to a pose seen before: the answer (200, a hit) and its time;
  - the map's host bytes and photons landed.

    bench/photon_cache.py build/refractd 1048576 4194304 16777216
"""
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def call(url, method, path, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url + path, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(req) as r:
            return r.status, json.load(r)
    except urllib.error.HTTPError as e:
        return e.code, json.load(e)


def lamp_status(url, sid):
    _, st = call(url, "GET", "/v1/scenes/%s/irradiance" % sid)
    return st["lights"][0]


def wait_passes(url, sid, key, t0):
    """Times (s after t0) of the first and last pass of the map with this key."""
    first = last = None
    while last is None:
        l = lamp_status(url, sid)
        m = l.get("photon_map", {})
        if l["key"] == key and l["state"] == "ready":
            if first is None:
                first = time.monotonic() - t0
            if not m.get("refining"):
                last = time.monotonic() - t0
                return first, last, l
        if l["state"] == "failed":
            sys.exit("failed: " + l.get("message", ""))
        time.sleep(0.005)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    refractd, counts = sys.argv[1], [int(n) for n in sys.argv[2:]]
    data = tempfile.mkdtemp(prefix="refract-photon-bench-")
    port_file = os.path.join(data, "port")
    log = open(os.path.join(data, "refractd.log"), "w")
    proc = subprocess.Popen([refractd, "--port", "0", "--port-file", port_file, "--data-dir",
                             os.path.join(data, "data")], stdout=log, stderr=log)
    try:
        for _ in range(600):
            if os.path.exists(port_file) and open(port_file).read().strip():
                break
            time.sleep(0.1)
        url = "http://127.0.0.1:" + open(port_file).read().strip()
        for _ in range(600):
            try:
                if call(url, "GET", "/v1/health")[0] == 200:
                    break
            except OSError:
                time.sleep(0.1)
        doc = json.load(open(os.path.join(ROOT, "proto/examples/peer_scene_a.json")))
        lamp = doc["lights"][0]
        print("| photons per light | first pass, s | last pass, s | moved: first pass, s | "
              "moved: last pass, s | back: answer, s | landed | host MB |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for n in counts:
            doc["receiver"]["caustics"] = "photons"
            doc["receiver"]["photons"] = n
            doc["name"] = "scene A, %d photons" % n
            t0 = time.monotonic()
            code, st = call(url, "POST", "/v1/scenes", doc)
            assert code == 201, st
            sid = st["id"]
            key0 = lamp_status(url, sid)["key"]
            first, last, l = wait_passes(url, sid, key0, t0)
            moved = dict(lamp, position=[lamp["position"][0] + 0.5] + lamp["position"][1:])
            t1 = time.monotonic()
            code, st = call(url, "PUT", "/v1/scenes/%s/lights/%s" % (sid, lamp["name"]), moved)
            assert code == 202, (code, st)
            key1 = st["lights"][0]["key"]
            mfirst, mlast, _ = wait_passes(url, sid, key1, t1)
            t2 = time.monotonic()
            code, st = call(url, "PUT", "/v1/scenes/%s/lights/%s" % (sid, lamp["name"]), lamp)
            back = time.monotonic() - t2
            assert code == 200 and st["lights"][0]["key"] == key0, (code, st)
            print("| 2^%d | %.3f | %.3f | %.3f | %.3f | %.3f (%d) | %d | %.0f |" %
                  (n.bit_length() - 1, first, last, mfirst, mlast, back, code,
                   l["photon_map"]["landed"], l["host_bytes"] / 1e6))
            sys.stdout.flush()
    finally:
        proc.terminate()
        proc.wait()
        log.close()
        print("refractd's log:", os.path.join(data, "refractd.log"))


if __name__ == "__main__":
    main()
