#!/usr/bin/env bash
# install-deps.sh - installs the Debian 12 packages that refractd's build and tests need,
# and the browser test's npm package (playwright-core, pinned by
# tests/browser/package-lock.json) into tests/browser/node_modules.
# Idempotent: packages already installed are left alone, and nothing is fetched when
# everything is present. Uses sudo when not run as root.
#
#   deploy/install-deps.sh            # build + test dependencies
#   deploy/install-deps.sh --check    # only report what is missing (exit 1 if anything)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)

PACKAGES=(
    # toolchain
    build-essential cmake pkg-config
    # EGL and OpenGL headers and loaders through glvnd (no X11/GLX needed)
    libegl-dev libopengl-dev libgl-dev libglvnd-dev
    # Mesa's software EGL device (llvmpipe): the GPU of last resort
    libegl-mesa0 libgl1-mesa-dri
    # HTTP server, JSON, HTTP client
    libmicrohttpd-dev libcjson-dev libcurl4-openssl-dev
    # images: OpenImageIO (PNG, JPEG, HDR) and OpenEXR's C API
    libopenimageio-dev libopenexr-dev
    # the web viewer's browser test (tests/browser): headless Chromium, driven by
    # playwright-core from npm with this system browser (no browser download)
    chromium
    # data directory metadata (SQLite, WAL) and NRRD gzip volumes (zlib)
    libsqlite3-dev zlib1g-dev
    # the TLS test makes a self-signed certificate (tests/integration/test_tls.c)
    openssl
    # batch jobs as Slurm job arrays (docs/slurm.md): the Slurm test starts its own
    # single-node Slurm, slurmctld + slurmd with munge authentication
    # (tests/slurm/test_slurm_array.sh); no service is configured or started here
    slurm-wlm munge
    # the fuzz harnesses (tests/fuzz, docs/fuzzing.md): clang, and its compiler-rt with
    # libFuzzer and the sanitizer runtimes (only recommended by clang, and recommends
    # are not installed here)
    clang libclang-rt-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

# Node.js and npm may come from Debian (nodejs, npm) or from elsewhere (a nodejs package
# that bundles npm): what counts is that the commands exist. Debian 12's Node.js 18 is
# new enough for the pinned playwright-core.
if ! command -v node >/dev/null 2>&1; then
    missing+=(nodejs)
fi
if ! command -v npm >/dev/null 2>&1; then
    missing+=(npm)
fi

BROWSER_DIR=$ROOT/tests/browser
browser_modules_present() {
    [ -f "$BROWSER_DIR/node_modules/playwright-core/package.json" ]
}

install_browser_modules() {
    if browser_modules_present; then
        return 0
    fi
    echo "install-deps: npm ci in tests/browser (playwright-core, pinned by package-lock.json)"
    (cd "$BROWSER_DIR" && npm ci --no-audit --no-fund --loglevel=error)
}

if [ "${#missing[@]}" -eq 0 ]; then
    echo "install-deps: all ${#PACKAGES[@]} packages present, and node and npm"
    if [ "${1:-}" = "--check" ]; then
        browser_modules_present && exit 0
        echo "install-deps: missing: tests/browser/node_modules (npm ci)"
        exit 1
    fi
    install_browser_modules
    exit 0
fi
if [ "${1:-}" = "--check" ]; then
    browser_modules_present || missing+=("tests/browser/node_modules (npm ci)")
    echo "install-deps: missing: ${missing[*]}"
    exit 1
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then
        SUDO="sudo"
    else
        echo "install-deps: need root to install: ${missing[*]}" >&2
        echo "To fix this issue run as root: apt-get install ${missing[*]}" >&2
        exit 1
    fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_browser_modules
echo "install-deps: done"
