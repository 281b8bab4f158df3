#!/usr/bin/env bash
# install-deps.sh - installs the Debian 12 packages that refractd's build and tests need.
# Idempotent: packages already installed are left alone, and nothing is fetched when
# everything is present. Uses sudo when not run as root.
#
#   deploy/install-deps.sh            # build + test dependencies
#   deploy/install-deps.sh --check    # only report what is missing (exit 1 if anything)
set -euo pipefail

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
    # data directory metadata (SQLite, WAL) and NRRD gzip volumes (zlib)
    libsqlite3-dev zlib1g-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if [ "${#missing[@]}" -eq 0 ]; then
    echo "install-deps: all ${#PACKAGES[@]} packages present"
    exit 0
fi
if [ "${1:-}" = "--check" ]; then
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
echo "install-deps: done"
