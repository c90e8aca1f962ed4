#!/usr/bin/env bash
# The browser the end-to-end tests drive: Debian's chromium (Playwright launches it with
# executable_path, never downloading its own). Installed with apt-get when missing (as root).
set -euo pipefail
BROWSER="${CATWALK_TEST_CHROMIUM:-/usr/bin/chromium}"
if [ -x "$BROWSER" ]; then
  echo "browser: $("$BROWSER" --version 2>/dev/null || echo "$BROWSER")" >&2
  exit 0
fi
if [ "$(id -u)" != 0 ]; then
  echo "browser: $BROWSER is missing and this is not root: install Debian's chromium" >&2
  exit 1
fi
echo "browser: installing Debian's chromium" >&2
DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium >/dev/null 2>&1 || {
  apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium >/dev/null; }
echo "browser: $("$BROWSER" --version)" >&2
