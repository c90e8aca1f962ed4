#!/usr/bin/env bash
# Blender for `catwalk bench peers` (Debian's package, pinned; its Python needs numpy).
# Not installed by `make test`: only the benchmark runs it. Needs root (apt-get).
set -euo pipefail
BLENDER_VERSION=3.4.1+dfsg-2+b1
NUMPY_VERSION=1:1.24.2-1+deb12u1
have() { dpkg-query -W -f='${Version}' "$1" 2>/dev/null; }
if [[ "$(have blender)" == "$BLENDER_VERSION" && "$(have python3-numpy)" == "$NUMPY_VERSION" ]]; then
  exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "blender_setup.sh: installing Blender needs root (apt-get install blender=$BLENDER_VERSION)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq || true
apt-get install -y -qq --no-install-recommends "blender=$BLENDER_VERSION" \
  "python3-numpy=$NUMPY_VERSION" >/dev/null
