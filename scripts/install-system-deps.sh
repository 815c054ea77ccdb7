#!/usr/bin/env bash
# Installs the real components nightcrew's tests run against, only when missing.
# Needs root (as on CI); on a developer machine without root it says what is missing and goes on,
# and the tests that need a missing component skip (never when CI=true).
set -euo pipefail
packages=()
for pkg in "$@"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || packages+=("$pkg")
done
[ ${#packages[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
    echo "install-system-deps: not root; missing: ${packages[*]}" >&2
    [ "${CI:-}" = "true" ] && exit 1
    exit 0
fi
echo "install-system-deps: installing ${packages[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
