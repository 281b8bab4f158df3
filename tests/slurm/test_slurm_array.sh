#!/usr/bin/env bash
# test_slurm_array.sh - a batch job scales out on Slurm and each frame exists exactly once
# (docs/slurm.md). ctest label "slurm"; it runs in CI (deploy/test.sh runs every label).
#
# Starts its own single-node Slurm in a temporary directory (munged, slurmctld, slurmd,
# with a generated slurm.conf on unused ports; no systemd), submits a 24-frame turntable
# as an array of 4 tasks with deploy/slurm/refract-batch.sbatch, kills task 1 mid-way with
# `scancel --signal=KILL`, requeues it, and checks that:
#   - the output directory holds frames 0..23, each once, and no temporary file;
#   - every frame is byte-identical to the same job run by one refractd daemon (POST
#     /v1/jobs through the refract CLI);
#   - the frames task 1 had finished before the kill were not written again (same inode):
#     the requeued run skipped them, and its log says so;
#   - a partial temporary frame file left in task 1's range is removed;
#   - progress.json says 24 of 24 done, and task 1's record says done after 1 restart;
#   - every task's log ends its range, with no sanitizer report (the ASan build's run).
#
# Needs root (slurmd runs jobs as their user and must be root) and deploy/install-deps.sh's
# slurm-wlm and munge. Not root: skipped (77) with a message, except under CI=1, where it
# fails. Env: REFRACTD, REFRACT_CLI, REFRACT_SOURCE_DIR (ctest sets them).
set -euo pipefail

fail() {
    echo "slurm/array_requeue: FAIL: $*" >&2
    exit 1
}
say() { echo "slurm/array_requeue: $*" >&2; }

SRC=${REFRACT_SOURCE_DIR:?run through ctest (it sets REFRACT_SOURCE_DIR, REFRACTD, REFRACT_CLI)}
REFRACTD=${REFRACTD:?}
REFRACT_CLI=${REFRACT_CLI:?}
if [ "$(id -u)" -ne 0 ]; then
    msg="needs root: slurmd must be root to start jobs. Run it as root: sudo ctest --test-dir build -L slurm --output-on-failure"
    if [ -n "${CI:-}" ]; then
        fail "$msg"
    fi
    say "SKIP: $msg"
    exit 77
fi
for cmd in munged slurmctld slurmd sbatch scancel scontrol squeue sinfo; do
    command -v "$cmd" >/dev/null 2>&1 ||
        fail "$cmd not found. To fix this issue run deploy/install-deps.sh (it installs slurm-wlm and munge)"
done

FRAMES=24
TASKS=4
W=320
H=240
T=$(mktemp -d "${TMPDIR:-/tmp}/refract-slurm.XXXXXX")
chmod 711 "$T" # munged wants its socket's directory searchable by everyone
# tmp: the tasks' private data directories (the killed one's stays until the cleanup)
mkdir -p "$T/state" "$T/spool" "$T/log" "$T/out" "$T/ref" "$T/daemon" "$T/tmp"
PIDS=()
JOB=""
export SLURM_CONF=$T/slurm.conf

cleanup() {
    local rc=$?
    if [ -n "$JOB" ]; then
        scancel "$JOB" >/dev/null 2>&1 || true
        for _ in $(seq 50); do # the tasks end before slurmd goes
            [ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ] && break
            sleep 0.1
        done
    fi
    local i
    for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do # the reverse order of starting
        kill "${PIDS[i]}" 2>/dev/null || true
        wait "${PIDS[i]}" 2>/dev/null || true
    done
    if [ "$rc" -ne 0 ]; then
        for f in "$T"/log/*; do
            echo "---- $f (last lines)" >&2
            tail -n 15 "$f" >&2 || true
        done
    fi
    rm -rf "$T"
}
trap cleanup EXIT

# Two unused TCP ports next to each other (slurmctld, slurmd), from a per-run start.
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
PORT=$((20000 + ($$ * 7 + RANDOM) % 30000))
while ! port_free "$PORT" || ! port_free $((PORT + 1)); do
    PORT=$((PORT + 2))
done
NODE=$(uname -n)
NODE=${NODE%%.*} # slurmd names itself by the short host name

# ---- munge and Slurm -------------------------------------------------------------------
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 600 "$T/munge.key"
munged -F --force -S "$T/munge.sock" --key-file="$T/munge.key" --log-file="$T/log/munged.log" \
    --pid-file="$T/munged.pid" --seed-file="$T/munged.seed" >"$T/log/munged.out" 2>&1 &
PIDS+=($!)
for _ in $(seq 100); do
    [ -S "$T/munge.sock" ] && break
    sleep 0.05
done
[ -S "$T/munge.sock" ] || fail "munged did not create its socket"

cat >"$T/slurm.conf" <<EOF
ClusterName=refracttest
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge.sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
ReturnToService=2
JobRequeue=1
MailProg=/bin/true
NodeName=$NODE NodeAddr=127.0.0.1 CPUs=$TASKS RealMemory=1000 State=UNKNOWN
PartitionName=refract Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -f "$T/slurm.conf" >"$T/log/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -f "$T/slurm.conf" >"$T/log/slurmd.out" 2>&1 &
PIDS+=($!)
for _ in $(seq 200); do
    [ "$(sinfo -h -o %T 2>/dev/null)" = "idle" ] && break
    sleep 0.1
done
[ "$(sinfo -h -o %T 2>/dev/null)" = "idle" ] || fail "the Slurm node did not become idle"
say "Slurm up on ports $PORT, $((PORT + 1)) ($SECONDS s)"

# ---- the job: an inline glass sphere, turned about y ------------------------------------
{
    printf '{"width": %d, "height": %d, "turntable": {"frames": %d, "axis": [0, 1, 0]}, "scene": ' \
        "$W" "$H" "$FRAMES"
    cat "$SRC/proto/examples/glass_sphere.json"
    printf '}\n'
} >"$T/job.json"

# ---- the reference: the same job in one refractd daemon ---------------------------------
"$REFRACTD" --port 0 --port-file "$T/daemon/port" --data-dir "$T/daemon/data" \
    >"$T/log/refractd-daemon.log" 2>&1 &
DAEMON=$!
PIDS+=("$DAEMON")
for _ in $(seq 300); do
    [ -s "$T/daemon/port" ] && break
    sleep 0.05
done
[ -s "$T/daemon/port" ] || fail "refractd did not start"
URL=http://127.0.0.1:$(cat "$T/daemon/port")
RJ=$("$REFRACT_CLI" --url "$URL" job submit "$T/job.json")
"$REFRACT_CLI" --url "$URL" job wait "$RJ" >/dev/null 2>&1 || fail "the reference job did not finish"
"$REFRACT_CLI" --url "$URL" job get "$RJ" --out "$T/ref" 2>/dev/null
kill "$DAEMON"
wait "$DAEMON" || true
refs=$(find "$T/ref" -name 'frame_*.png' | wc -l)
[ "$refs" -eq "$FRAMES" ] || fail "the reference job gave $refs frames"
say "reference: $FRAMES frames from one daemon ($SECONDS s)"

# ---- the array ------------------------------------------------------------------------
JOB=$(sbatch --parsable --array=0-$((TASKS - 1)) --output="$T/log/task-%a.log" \
    --export="ALL,REFRACT_JOB=$T/job.json,REFRACT_OUT=$T/out,REFRACTD=$REFRACTD,TMPDIR=$T/tmp" \
    "$SRC/deploy/slurm/refract-batch.sbatch")
[ -n "$JOB" ] || fail "sbatch gave no job id"
say "submitted array job $JOB"

# Task 1 has frames 6..11. Kill it once it has finished at least one and not all.
REC=$T/out/progress.d/frames_00006-00011.json
done_of() { sed -n 's/.*"frames_done":[[:space:]]*\([0-9]*\).*/\1/p' "$1" 2>/dev/null || true; }
killed=""
for _ in $(seq 1500); do
    n=$(done_of "$REC")
    if [ -n "$n" ] && [ "$n" -ge 1 ]; then
        [ "$n" -lt 6 ] || fail "task 1 finished before it could be killed (frames too fast?)"
        scancel --signal=KILL "${JOB}_1"
        killed=$n
        break
    fi
    sleep 0.02
done
[ -n "$killed" ] || fail "task 1 never finished a frame"
for _ in $(seq 200); do
    [ -z "$(squeue -h -j "${JOB}_1" 2>/dev/null)" ] && break
    sleep 0.05
done
[ -z "$(squeue -h -j "${JOB}_1" 2>/dev/null)" ] || fail "task 1 is still there after SIGKILL"
# What the killed run left: the frames it finished (their inodes), and a partial file as a
# kill during a write leaves one.
before=()
for n in $(seq 6 11); do
    f=$T/out/$(printf 'frame_%05d.png' "$n")
    [ -f "$f" ] && before+=("$f:$(stat -c %i "$f")")
done
[ "${#before[@]}" -ge "$killed" ] || fail "frames seen done before the kill are gone"
[ "${#before[@]}" -lt 6 ] || fail "task 1 finished its frames before the kill landed"
head -c 100 "$T/ref/frame_00011.png" >"$T/out/.frame_00011.png.deadhost.99999.tmp"
say "killed task 1 after ${#before[@]} of its 6 frames ($SECONDS s); requeueing it"

# Requeue; Slurm holds a requeued job for cred_expire (120 s) so that the new launch's
# credential is younger than the revocation slurmd recorded when it killed the old one.
# Revocations are kept to the second: a launch in the same second as the kill is refused
# ("Job credential revoked", seen in CI), so make it eligible 3 s from now, not now.
scontrol requeue "${JOB}_1"
scontrol update JobId="${JOB}_1" StartTime=now+3
for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ] && break
    sleep 0.1
done
[ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ] || fail "the array job did not finish in 60 s"
say "array job finished ($SECONDS s)"

# ---- checks ---------------------------------------------------------------------------
count=$(find "$T/out" -maxdepth 1 -name 'frame_*.png' | wc -l)
[ "$count" -eq "$FRAMES" ] || fail "$count frame files, expected $FRAMES"
for n in $(seq 0 $((FRAMES - 1))); do
    name=$(printf 'frame_%05d.png' "$n")
    [ -f "$T/out/$name" ] || fail "$name is missing"
    cmp -s "$T/ref/$name" "$T/out/$name" || fail "$name differs from the single-daemon run"
done
leftover=$(find "$T/out" -name '*.tmp' | wc -l)
[ "$leftover" -eq 0 ] || fail "$leftover temporary files left: $(find "$T/out" -name '*.tmp')"
# Each task removes its private data directory at exit; only the SIGKILLed run cannot.
left=$(find "$T/tmp" -mindepth 1 -maxdepth 1 -name 'refractd-batch-*' | wc -l)
[ "$left" -le 1 ] || fail "$left private data directories left in TMPDIR, expected at most 1"
for entry in "${before[@]}"; do
    f=${entry%:*}
    [ "$(stat -c %i "$f")" = "${entry##*:}" ] || fail "$f was written again after the requeue"
done
for t in $(seq 0 $((TASKS - 1))); do
    grep -q "of $FRAMES: .* rendered" "$T/log/task-$t.log" || fail "task $t did not finish its range"
    if grep -Eq 'Sanitizer|runtime error' "$T/log/task-$t.log"; then
        fail "task $t: $(grep -m 3 -E 'Sanitizer|runtime error' "$T/log/task-$t.log")"
    fi
done
summary=$(grep 'frames 6-11 of 24:' "$T/log/task-1.log" | tail -n 1)
expect="$((6 - ${#before[@]})) rendered, ${#before[@]} already there"
case "$summary" in
*"$expect"*) ;;
*) fail "task 1's requeued run says \"$summary\", expected \"$expect\"" ;;
esac
grep -Eq '"frames_done":[[:space:]]*24,' "$T/out/progress.json" ||
    fail "progress.json does not say 24 frames done: $(cat "$T/out/progress.json")"
grep -Eq '"state":[[:space:]]*"done",' "$T/out/progress.json" ||
    fail "progress.json does not say done"
grep -Eq '"slurm_restarts":[[:space:]]*1' "$REC" || fail "task 1's record lacks its restart: $(cat "$REC")"
grep -Eq '"state":[[:space:]]*"done"' "$REC" || fail "task 1's record does not say done"
say "PASS: $FRAMES frames, each once, byte-identical; task 1 killed after ${#before[@]} frames and requeued ($SECONDS s)"
