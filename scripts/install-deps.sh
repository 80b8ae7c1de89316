#!/usr/bin/env bash
# Installs every Debian package cgamesh needs to build, test and benchmark, and the npm
# packages of the test-only JavaScript oracles. Idempotent: safe to run again.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"

packages=(
  build-essential cmake pkg-config
  libeigen3-dev
  libgtest-dev libgmock-dev libbenchmark-dev libbullet-dev
  libcli11-dev nlohmann-json3-dev
  libassimp-dev assimp-testmodels
  libtinygltf-dev
  libcgal-dev
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev libstb-dev libjpeg62-turbo-dev libwebp-dev
  xvfb xauth
  mono-mcs mono-runtime
  python3-dev python3-venv python3-pip python3-setuptools python3-wheel pybind11-dev python3-numpy python3-pytest
)

if [ "$(id -u)" -eq 0 ]; then sudo_cmd=(); else sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node runs the test oracles; a machine that already has it (any vendor) keeps its own.
command -v node >/dev/null 2>&1 || missing+=(nodejs)
command -v npm >/dev/null 2>&1 || missing+=(npm)

if [ "${#missing[@]}" -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Test-only JavaScript oracles (ganja.js; three.js and the Khronos glTF validator), pinned by
# their package-lock.json files.
for oracle in "$root/tests/oracle" "$root/tests/oracle/js"; do
  if [ -f "$oracle/package-lock.json" ] && { [ ! -f "$oracle/node_modules/.package-lock.json" ] || [ "$oracle/package-lock.json" -nt "$oracle/node_modules/.package-lock.json" ]; }; then
    echo "install-deps: npm ci in ${oracle#"$root"/}"
    (cd "$oracle" && npm ci --no-audit --no-fund --loglevel=error)
  fi
done
echo "install-deps: all dependencies present"
