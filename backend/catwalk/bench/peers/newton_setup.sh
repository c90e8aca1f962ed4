#!/usr/bin/env bash
# Make the virtual environment that runs the Newton peer (newton_run.py), with pinned versions.
#
#   bash newton_setup.sh [VENV_DIR]        (default: .peers/newton)
#   VENV_DIR/bin/python newton_run.py SCENE.npz OUT.npz [--substeps N] [--iterations K]
#
# Idempotent: a stamp file records the pins; a venv whose stamp matches is left alone.
# Newton needs only warp-lang (which needs numpy) for this use: no USD, viewer or GPU packages.
# Warp compiles its CPU kernels at first use with its bundled Clang (no compiler needed) and
# caches them under ~/.cache/warp.
set -euo pipefail

VENV="${1:-.peers/newton}"
PINS=(newton==1.8.0 warp-lang==1.19.0 numpy==2.4.6)
STAMP="$VENV/.catwalk-peer-stamp"
WANT="${PINS[*]}"

if [[ -x "$VENV/bin/python" && -f "$STAMP" && "$(cat "$STAMP")" == "$WANT" ]]; then
    echo "newton peer venv up to date: $VENV"
    exit 0
fi

PY="${PYTHON:-python3}"
"$PY" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check "${PINS[@]}"
"$VENV/bin/python" - <<'EOF'
import newton, numpy, warp
print("newton", newton.__version__, "warp", warp.config.version, "numpy", numpy.__version__)
EOF
echo "$WANT" > "$STAMP"
echo "newton peer venv ready: $VENV"
