#!/usr/bin/env bash
# test.sh - README command 2: install what is missing, build, and run every test with
# ctest in a normal build (build/), and again, but for the tests labelled gpu, in an
# AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/). GL runs on Mesa's
# software EGL device when there is no GPU.
# Warnings are errors in both (REFRACT_WERROR=ON); a packager's plain Release build
# leaves them warnings (CMakeLists.txt).
#
#   ./deploy/test.sh            # both builds and the fuzz run
#   ./deploy/test.sh --quick    # the normal build only
#   ./deploy/test.sh --fuzz     # the fuzz run only
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=$(nproc)

./deploy/install-deps.sh

mkdir -p out
run_suite() {
    local dir=$1; shift
    local select=()
    if [ "$1" = "--no-gpu-label" ]; then
        # The sanitizer build skips the tests labelled gpu: they compare GLSL kernels,
        # which run inside Mesa (not instrumented), with CPU twins that the unit and
        # integration tests already run sanitized; on a fresh machine's empty shader cache
        # they were most of this suite's time.
        select=(-LE '^gpu$')
        shift
    fi
    echo "==> configure and build $dir ($*), log in out/$dir.log"
    if ! { cmake -S . -B "$dir" "$@" && cmake --build "$dir" -j"$JOBS"; } > "out/$dir.log" 2>&1; then
        tail -60 "out/$dir.log"
        echo "test.sh: the build in $dir failed (full log: out/$dir.log)" >&2
        exit 1
    fi
    echo "==> ctest in $dir"
    ctest --test-dir "$dir" --output-on-failure -j2 "${select[@]}"
}

# What a packager's Release build (-O3) warns about and the -O2 builds below do not (GCC's
# -Warray-bounds and -Wformat-truncation need -O3's inlining): the client and CLI, and the
# unit test that includes the CLI's files, compiled (not linked) at -O3 with -Werror. A
# few seconds, instead of a third full build.
release_warnings() {
    echo "==> -O3 -Werror compile of the client, the CLI and tests/unit/test_cli_args.c"
    local flags=(-std=c11 -D_DEFAULT_SOURCE -DREFRACT_VERSION='"check"' -O3 -DNDEBUG -Wall
                 -Wextra -Wpedantic -Wshadow -Wvla -Wstrict-prototypes -Werror
                 -Iclient -Iproto -Itests $(pkg-config --cflags libcurl libcjson))
    local f
    for f in client/*.c client/cli/*.c tests/unit/test_cli_args.c; do
        cc "${flags[@]}" -c "$f" -o /dev/null || {
            echo "test.sh: $f warns at -O3 (a Release build would show it)" >&2
            exit 1
        }
    done
}
# Each libFuzzer harness of tests/fuzz for REFRACT_FUZZ_SECONDS (10) on its seed corpus, two
# at a time: about 2-3 minutes with the build. Only the harnesses and the libraries they
# link are built (not the tests: they run in the two builds above).
run_fuzz() {
    local dir=build-fuzz
    local targets=(fuzz_scene fuzz_obj fuzz_ply fuzz_nrrd fuzz_raw fuzz_exr fuzz_multipart
                   fuzz_sse fuzz_router)
    echo "==> configure and build $dir (clang, libFuzzer, ASan+UBSan), log in out/$dir.log"
    if ! { CC=clang CXX=clang++ cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
               -DREFRACT_FUZZ=ON -DREFRACT_WERROR=ON &&
           cmake --build "$dir" -j"$JOBS" --target "${targets[@]}"; } > "out/$dir.log" 2>&1; then
        tail -60 "out/$dir.log"
        echo "test.sh: the build in $dir failed (full log: out/$dir.log)" >&2
        exit 1
    fi
    echo "==> ctest -L fuzz in $dir"
    ctest --test-dir "$dir" -L fuzz --output-on-failure -j2
}

if [ "${1:-}" = "--fuzz" ]; then
    run_fuzz
    exit 0
fi

release_warnings

run_suite build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DREFRACT_WERROR=ON
if [ "${1:-}" != "--quick" ]; then
    run_suite build-asan --no-gpu-label -DCMAKE_BUILD_TYPE=Debug -DREFRACT_SANITIZE=ON -DREFRACT_WERROR=ON
    run_fuzz
fi
