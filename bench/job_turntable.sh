#!/bin/sh
# bench/job_turntable.sh - frames per minute of a batch turntable job on a running
# refractd, through the refract CLI: submit a FRAMES-frame turntable of SCENE at WxH, wait
# for it, and divide the frames by the wall time from submit to done (which includes the
# scene's GPU build before the first frame; run it twice to see the warm number).
#
#     build/refractd --data-dir /tmp/bench-jobs --port 8750 &
#     bench/job_turntable.sh http://127.0.0.1:8750 proto/examples/glass_sphere.json 320 240 36
set -eu
URL=${1:?URL} SCENE_FILE=${2:?scene file} W=${3:-320} H=${4:-240} FRAMES=${5:-36}
CLI=${REFRACT_CLI:-build/refract}
SCENE=$($CLI --url "$URL" scene create "$SCENE_FILE")
for run in cold warm; do
    start=$(date +%s.%N)
    JOB=$(printf '{"scene": "%s", "width": %d, "height": %d, "turntable": {"frames": %d}}' \
        "$SCENE" "$W" "$H" "$FRAMES" | $CLI --url "$URL" job submit -)
    $CLI --url "$URL" job wait "$JOB" 2>/dev/null
    end=$(date +%s.%N)
    echo "$run: $FRAMES frames of ${W}x${H} in $(echo "$end - $start" | bc) s:" \
        "$(echo "scale=1; $FRAMES * 60 / ($end - $start)" | bc) frames per minute"
done
