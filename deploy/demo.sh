#!/usr/bin/env bash
# demo.sh - README command 1: install what is missing, build, start refractd on
# 127.0.0.1 with the example scenes loaded, render the demo through the refract client,
# and say where the daemon listens. The daemon keeps running afterwards.
#
#   ./deploy/demo.sh                 # port 8750 (REFRACT_PORT overrides), scene wine_glass
#   REFRACT_DEMO_SCENE=luneburg_lens ./deploy/demo.sh
#
# Everything it writes goes under ./out/: the build log, the daemon's data directory and
# log, and the rendered picture out/demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
OUT=$ROOT/out
PORT=${REFRACT_PORT:-8750}
SCENE=${REFRACT_DEMO_SCENE:-wine_glass}
mkdir -p "$OUT"

echo "==> dependencies"
./deploy/install-deps.sh

echo "==> build (build/, log in out/build.log)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo > "$OUT/build.log" 2>&1 \
    || { tail -30 "$OUT/build.log"; exit 1; }
cmake --build build -j"$(nproc)" --target refractd refract >> "$OUT/build.log" 2>&1 \
    || { tail -30 "$OUT/build.log"; exit 1; }

# A demo daemon started earlier from this checkout is stopped and replaced.
if [ -f "$OUT/refractd.pid" ] && kill -0 "$(cat "$OUT/refractd.pid")" 2>/dev/null; then
    echo "==> stopping the earlier demo daemon (pid $(cat "$OUT/refractd.pid"))"
    kill "$(cat "$OUT/refractd.pid")"
    for _ in $(seq 50); do kill -0 "$(cat "$OUT/refractd.pid")" 2>/dev/null || break; sleep 0.1; done
fi

echo "==> starting refractd on 127.0.0.1:$PORT"
rm -f "$OUT/refractd.port"
nohup ./build/refractd --bind 127.0.0.1 --port "$PORT" --port-file "$OUT/refractd.port" \
    --data-dir "$OUT/data" --scene-dir proto/examples > "$OUT/refractd.log" 2>&1 &
echo $! > "$OUT/refractd.pid"
for _ in $(seq 300); do
    [ -s "$OUT/refractd.port" ] && break
    if ! kill -0 "$(cat "$OUT/refractd.pid")" 2>/dev/null; then
        echo "refractd did not start; its log:" >&2
        cat "$OUT/refractd.log" >&2
        exit 1
    fi
    sleep 0.1
done
URL="http://127.0.0.1:$(cat "$OUT/refractd.port")"

echo "==> health"
./build/refract --url "$URL" health
echo "==> scenes"
./build/refract --url "$URL" scene list

echo "==> waiting for $SCENE's irradiance volumes (the light simulation starts when refractd loads a scene with lights)"
./build/refract --url "$URL" --timeout 1800 irradiance wait "$SCENE"

echo "==> rendering $SCENE (the first render of a scene compiles its shader variant)"
./build/refract --url "$URL" render "$SCENE" -o "$OUT/demo.png"

cat <<MSG

refractd is running (pid $(cat "$OUT/refractd.pid")) and listens on $URL
  picture:   $OUT/demo.png
  viewer:    $URL/viewer/$SCENE   (open it in a browser: drag to orbit, move the light)
  log:       $OUT/refractd.log
  try:       ./build/refract --url $URL render luneburg_lens -o out/luneburg.png
             curl $URL/v1/health
  stop it:   kill \$(cat out/refractd.pid)
MSG
