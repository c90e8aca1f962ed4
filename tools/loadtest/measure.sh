#!/bin/bash
# One load-test figure of docs/operations.md ("Load"), on this machine:
#   tools/loadtest/measure.sh WORKERS USERS SECONDS MIX [OUT_DIR]
# A fresh PostgreSQL database (catwalk_load) and Redis database 5 on 127.0.0.1, a fresh storage
# folder; `catwalk serve --workers WORKERS` on port 8100 once its thumbnails are made; then
# `catwalk loadtest --mix MIX --json` under tools/loadtest/cores.py (the cores each process
# tree used). Writes OUT_DIR/loadtest.json, cores.json and serve.log; prints both summaries.
set -euo pipefail
W=$1; U=$2; S=$3; MIX=$4; OUT=${5:-$(mktemp -d /tmp/catwalk-load-XXXXXX)}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
mkdir -p "$OUT"
psql -q -h 127.0.0.1 -U postgres -c "DROP DATABASE IF EXISTS catwalk_load" \
     -c "CREATE DATABASE catwalk_load" >/dev/null
redis-cli -n 5 flushdb >/dev/null
export CATWALK_DATABASE_URL=postgresql+psycopg://postgres@127.0.0.1:5432/catwalk_load
export CATWALK_BROKER_URL=redis://127.0.0.1:6379/5
export CATWALK_STORAGE_DIR="$OUT/storage"
rm -rf "$CATWALK_STORAGE_DIR"
.venv/bin/catwalk serve --port 8100 --workers "$W" > "$OUT/serve.log" 2>&1 &
SERVE=$!
trap 'kill -INT $SERVE 2>/dev/null; wait $SERVE 2>/dev/null || true' EXIT
GARMENTS=$(ls garments/*.json | wc -l)
for _ in $(seq 1 600); do   # the catalogue's thumbnails are made at start: wait for them
  [ "$(grep -c '"event": "thumbnail"' "$OUT/serve.log" || true)" -ge "$GARMENTS" ] && break
  sleep 1
done
.venv/bin/python tools/loadtest/cores.py .venv/bin/catwalk loadtest --url http://127.0.0.1:8100 \
  --users "$U" --seconds "$S" --mix "$MIX" --json > "$OUT/loadtest.json" 2> "$OUT/cores.json"
cat "$OUT/cores.json"
.venv/bin/python -c "
import json, sys
r = json.load(open(sys.argv[1]))
from catwalk.loadtest.run import format_table
print(format_table(r))" "$OUT/loadtest.json"
echo "in $OUT"
