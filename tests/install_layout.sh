#!/bin/sh
# install_layout.sh CMAKE BUILD_DIR - `cmake --install` into a temporary prefix puts what a
# distribution expects where it expects it: bin/refractd and bin/refract (runnable),
# lib/systemd/system/refractd.service naming the installed binary and config, and
# etc/refract/refractd.conf.
set -eu
cmake=$1
build=$2
prefix=$(mktemp -d "${TMPDIR:-/tmp}/refract-install-XXXXXX")
trap 'rm -rf "$prefix"' EXIT
fail() { echo "install_layout: $*" >&2; exit 1; }

"$cmake" --install "$build" --prefix "$prefix" >/dev/null || fail "cmake --install failed"
for f in bin/refractd bin/refract; do
    [ -x "$prefix/$f" ] || fail "$f is missing or not executable under the prefix"
done
"$prefix/bin/refractd" --version | grep -q '^refractd ' || fail "bin/refractd --version"
unit="$prefix/lib/systemd/system/refractd.service"
[ -f "$unit" ] || fail "lib/systemd/system/refractd.service is missing"
grep -q "^ExecStart=$prefix/bin/refractd --config $prefix/etc/refract/refractd.conf\$" "$unit" ||
    fail "the unit's ExecStart does not name the installed paths: $(grep ExecStart= "$unit")"
[ -f "$prefix/etc/refract/refractd.conf" ] || fail "etc/refract/refractd.conf is missing"
"$prefix/bin/refractd" --config "$prefix/etc/refract/refractd.conf" --help >/dev/null ||
    fail "the installed refractd does not accept the installed config"
echo "install_layout: ok ($prefix)"
