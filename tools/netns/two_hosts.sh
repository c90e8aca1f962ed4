#!/usr/bin/env bash
# Workers on two "hosts", for real: two network namespaces, each with its own address, its own
# hostname and a `catwalk worker --concurrency 1`, against the Redis and PostgreSQL of the main
# namespace and a storage folder shared by all (the namespaces share the filesystem, as hosts
# share an NFS mount). An API (`catwalk serve --workers 0`) in the main namespace takes fast
# try-ons; the script then shows which host ran each one. Run as root:
#
#   sudo tools/netns/two_hosts.sh            # TWO_HOSTS_JOBS=6 try-ons by default
#
# What it makes, and removes again on exit (also on failure or Ctrl-C):
#   - namespaces catwalk-<run>-a and catwalk-<run>-b, each joined to the main namespace by a
#     veth pair: 10.77.1.1/30 (main) – 10.77.1.2/30 (a) and 10.77.2.1/30 – 10.77.2.2/30 (b)
#     (TWO_HOSTS_NET=10.77 picks the first two octets); it stops if those are in use;
#   - forwarders listening on 10.77.1.1 and 10.77.2.1 only (socat, or tools/netns/forward.py
#     when socat is missing) to Redis and PostgreSQL on 127.0.0.1: the servers' configuration
#     is not touched and nothing new listens on any other address;
#   - a PostgreSQL database catwalk_netns_<run> (dropped at the end), a Celery queue
#     catwalk-netns-<run> (its Redis keys deleted at the end), a temporary folder for storage,
#     a one-garment catalogue and the logs (kept with TWO_HOSTS_KEEP=1).
# Each worker runs in its own UTS namespace (unshare --uts) with the hostname host-a / host-b,
# so the `worker` column of a try-on (hostname:pid) names its host; the pid is also checked
# against `ip netns pids`.
#
# Settings (environment): TWO_HOSTS_JOBS (6), TWO_HOSTS_NET (10.77), TWO_HOSTS_KEEP (0),
# TWO_HOSTS_FORWARDER (socat | python; default socat when installed), REDIS_PORT (6379),
# REDIS_DB (15), PG_PORT (5432), PG_USER (postgres; trusted from 127.0.0.1), CATWALK_VENV
# (.venv of the repository). Exit status 0 when both hosts ran try-ons and all were done.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="${CATWALK_VENV:-$REPO/.venv}"
PY="$VENV/bin/python"
CATWALK="$VENV/bin/catwalk"
JOBS="${TWO_HOSTS_JOBS:-6}"
NET="${TWO_HOSTS_NET:-10.77}"
KEEP="${TWO_HOSTS_KEEP:-0}"
REDIS_PORT="${REDIS_PORT:-6379}"
REDIS_DB="${REDIS_DB:-15}"
PG_PORT="${PG_PORT:-5432}"
PG_USER="${PG_USER:-postgres}"

RUN="$(od -An -N3 -tx1 /dev/urandom | tr -d ' \n')"   # 6 hex digits
DB="catwalk_netns_$RUN"
QUEUE="catwalk-netns-$RUN"
HOSTS=(a b)
declare -A NS=([a]="catwalk-$RUN-a" [b]="catwalk-$RUN-b")
declare -A VETH=([a]="cw${RUN}a" [b]="cw${RUN}b")            # main side; the peer: …p
declare -A MAIN_IP=([a]="$NET.1.1" [b]="$NET.2.1")
declare -A NS_IP=([a]="$NET.1.2" [b]="$NET.2.2")
T0=$SECONDS

say() { echo "two_hosts: $*" >&2; }
die() { say "error: $*"; exit 1; }

# ------------------------------------------------------------------ what it needs
[ "$(id -u)" = 0 ] || die "run as root (it creates network namespaces)"
for c in ip unshare setsid; do
  command -v "$c" >/dev/null || die "'$c' is not installed (iproute2 / util-linux)"
done
[ -x "$CATWALK" ] || die "no $CATWALK: run make install first (or set CATWALK_VENV)"
FORWARDER="${TWO_HOSTS_FORWARDER:-$(command -v socat >/dev/null && echo socat || echo python)}"
[[ "$FORWARDER" == socat || "$FORWARDER" == python ]] || die "TWO_HOSTS_FORWARDER: socat or python"
answers() { timeout 3 bash -c "exec 3<>/dev/tcp/$1/$2" 2>/dev/null; }
answers 127.0.0.1 "$REDIS_PORT" || die "Redis does not answer on 127.0.0.1:$REDIS_PORT (tools/services/ensure.sh starts it)"
answers 127.0.0.1 "$PG_PORT" || die "PostgreSQL does not answer on 127.0.0.1:$PG_PORT (tools/services/ensure.sh starts it)"
for h in "${HOSTS[@]}"; do
  sub="${MAIN_IP[$h]%.1}.0/30"
  if ip -4 -o addr show | grep -q "inet ${MAIN_IP[$h]%.1}\." || [ -n "$(ip -4 route show "$sub")" ]; then
    die "$sub is already in use on this machine: choose other addresses with TWO_HOSTS_NET"
  fi
done

TMP="$(mktemp -d /tmp/catwalk-netns-XXXXXX)"
STORE="$TMP/storage"
CAT="$TMP/catalogue"
LOGS="$TMP/logs"
mkdir -p "$STORE" "$CAT" "$LOGS"
chmod 700 "$TMP"

# ------------------------------------------------------------------ stopping everything
declare -A PGID=()     # name -> process group id of what this script started
DRIVE=                 # the client's pid while it runs
FAILED=1

stop_group() {   # name-pattern: SIGTERM (Celery's warm shutdown, uvicorn's), 20 s, SIGKILL
  local name pg t alive
  local -a pgs=()
  for name in "${!PGID[@]}"; do [[ "$name" == $1 ]] && pgs+=("${PGID[$name]}"); done
  [ "${#pgs[@]}" = 0 ] && return 0
  for pg in "${pgs[@]}"; do kill -TERM -- "-$pg" 2>/dev/null || true; done
  for t in $(seq 1 80); do
    alive=0
    for pg in "${pgs[@]}"; do kill -0 -- "-$pg" 2>/dev/null && alive=1; done
    [ "$alive" = 0 ] && break
    sleep 0.25
  done
  for pg in "${pgs[@]}"; do kill -KILL -- "-$pg" 2>/dev/null || true; done
}

stop_all() {   # the API and the workers first, then the forwarders they talk through
  stop_group 'api'
  stop_group 'worker-*'
  stop_group 'forward-*'
}

cleanup() {
  local rc=$?
  set +e
  trap - EXIT INT TERM
  [ "$rc" != 0 ] && FAILED=1
  [ -n "$DRIVE" ] && kill -TERM "$DRIVE" 2>/dev/null
  say "stopping the API, the workers and the forwarders"
  stop_all
  for h in "${HOSTS[@]}"; do
    if ip netns list | grep -qw "${NS[$h]}"; then
      # anything left in a namespace this script made is its own (its workers' children)
      for p in $(ip netns pids "${NS[$h]}" 2>/dev/null); do kill -KILL "$p" 2>/dev/null; done
      ip netns del "${NS[$h]}"
    fi
    # (deleting the namespace deletes the pair, not always at once)
    ip link show "${VETH[$h]}" >/dev/null 2>&1 && ip link del "${VETH[$h]}" 2>/dev/null
  done
  "$PY" - "$DB" "$PG_USER" "$PG_PORT" "$QUEUE" "$REDIS_PORT" "$REDIS_DB" <<'PY'
import sys

import psycopg
import redis

db, user, port, queue, rport, rdb = sys.argv[1:]
with psycopg.connect(f"postgresql://{user}@127.0.0.1:{port}/postgres", autocommit=True) as c:
    c.execute(f'DROP DATABASE IF EXISTS "{db}" WITH (FORCE)')
r = redis.Redis(host="127.0.0.1", port=int(rport), db=int(rdb))
for key in r.scan_iter(f"*{queue}*"):
    r.delete(key)
PY
  if [ "$FAILED" != 0 ]; then
    for f in "$LOGS"/*.log; do
      [ -f "$f" ] || continue
      say "--- last lines of $(basename "$f")"
      tail -n 15 "$f" >&2
    done
  fi
  if [ "$KEEP" = 1 ]; then say "kept $TMP"; else rm -rf "$TMP"; fi
  local left
  left="$(ip netns list | grep -c "catwalk-$RUN-" || true)"
  say "removed: namespaces (${left} left), veths, database $DB, queue $QUEUE; $((SECONDS - T0)) s in all"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

start() {   # name log command... : in its own process group (setsid), logs to $LOGS/name.log
  local name="$1" log="$LOGS/$1.log"
  shift
  setsid "$@" >"$log" 2>&1 </dev/null &
  PGID[$name]=$!
}

say "run $RUN: namespaces ${NS[a]} ${NS[b]}, database $DB, queue $QUEUE, folder $TMP"

# ------------------------------------------------------------------ the database
"$PY" - "$DB" "$PG_USER" "$PG_PORT" <<'PY'
import sys

import psycopg

db, user, port = sys.argv[1:]
with psycopg.connect(f"postgresql://{user}@127.0.0.1:{port}/postgres", autocommit=True) as c:
    c.execute(f'CREATE DATABASE "{db}"')
PY

# ------------------------------------------------------------------ the two hosts
for h in "${HOSTS[@]}"; do
  ns="${NS[$h]}" v="${VETH[$h]}"
  ip netns add "$ns"
  ip link add "$v" type veth peer name "${v}p"
  ip link set "${v}p" netns "$ns"
  ip addr add "${MAIN_IP[$h]}/30" dev "$v"
  ip link set "$v" up
  ip -n "$ns" link set lo up
  ip -n "$ns" addr add "${NS_IP[$h]}/30" dev "${v}p"
  ip -n "$ns" link set "${v}p" up
  # Redis and PostgreSQL, reachable at the main side's address only
  for port in "$REDIS_PORT" "$PG_PORT"; do
    if [ "$FORWARDER" = socat ]; then
      start "forward-$h-$port" socat "TCP-LISTEN:$port,bind=${MAIN_IP[$h]},reuseaddr,fork" \
        "TCP:127.0.0.1:$port"
    else
      start "forward-$h-$port" "$PY" "$REPO/tools/netns/forward.py" \
        "${MAIN_IP[$h]}:$port" "127.0.0.1:$port"
    fi
  done
  say "host $h: netns $ns, ${NS_IP[$h]} (veth ${v}p) <-> ${MAIN_IP[$h]} (veth $v), forwarding :$REDIS_PORT and :$PG_PORT ($FORWARDER)"
done
for h in "${HOSTS[@]}"; do
  for port in "$REDIS_PORT" "$PG_PORT"; do
    ok=0
    for _ in $(seq 1 40); do
      ip netns exec "${NS[$h]}" bash -c "exec 3<>/dev/tcp/${MAIN_IP[$h]}/$port" 2>/dev/null && { ok=1; break; }
      sleep 0.25
    done
    [ "$ok" = 1 ] || die "host $h cannot reach ${MAIN_IP[$h]}:$port"
  done
done
say "both hosts reach Redis and PostgreSQL through their veths"

# ------------------------------------------------------------------ the catalogue, the env
cp "$REPO/garments/pencil-skirt.json" "$CAT/"
cp -r "$REPO/garments/textures" "$CAT/textures"

BASE_ENV=(env -i "PATH=$PATH" "HOME=$HOME" "LANG=C.UTF-8" "PYTHONUNBUFFERED=1"
          "CATWALK_STORAGE_DIR=$STORE" "CATWALK_CATALOGUE_DIR=$CAT" "CATWALK_QUEUE=$QUEUE"
          "CATWALK_LOG_LEVEL=INFO")
[ -n "${CATWALK_DATA_DIR:-}" ] && BASE_ENV+=("CATWALK_DATA_DIR=$CATWALK_DATA_DIR")
[ -n "${CATWALK_DATA:-}" ] && BASE_ENV+=("CATWALK_DATA=$CATWALK_DATA")
urls() {   # address -> the database and broker settings seen from there
  echo "CATWALK_DATABASE_URL=postgresql+psycopg://$PG_USER@$1:$PG_PORT/$DB"
  echo "CATWALK_BROKER_URL=redis://$1:$REDIS_PORT/$REDIS_DB"
}

# ------------------------------------------------------------------ the API and the workers
API_PORT="$("$PY" -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
mapfile -t API_URLS < <(urls 127.0.0.1)
start api "${BASE_ENV[@]}" "${API_URLS[@]}" "$CATWALK" serve --host 127.0.0.1 \
  --port "$API_PORT" --workers 0
for h in "${HOSTS[@]}"; do
  mapfile -t W_URLS < <(urls "${MAIN_IP[$h]}")
  start "worker-$h" ip netns exec "${NS[$h]}" unshare --uts \
    sh -c 'hostname "$0" && exec "$@"' "host-$h" \
    "${BASE_ENV[@]}" "${W_URLS[@]}" "$CATWALK" worker --concurrency 1
  say "host $h: catwalk worker --concurrency 1 (hostname host-$h, pid ${PGID[worker-$h]}) -> ${W_URLS[*]}"
done
say "API: catwalk serve --workers 0 on http://127.0.0.1:$API_PORT (pid ${PGID[api]})"

for h in "${HOSTS[@]}"; do
  for _ in $(seq 1 600); do    # Celery's "celery@… ready." comes after catwalk's warm-up
    grep -q 'ready\.' "$LOGS/worker-$h.log" 2>/dev/null && break
    kill -0 "${PGID[worker-$h]}" 2>/dev/null || die "the worker on host $h exited"
    sleep 0.25
  done
  grep -q 'ready\.' "$LOGS/worker-$h.log" || die "the worker on host $h was not ready in 150 s"
  say "host $h: worker ready after $((SECONDS - T0)) s"
done

# ------------------------------------------------------------------ the try-ons
# in the background, so that a signal stops the run at once (bash runs a trap only between
# commands; `wait` is one it interrupts)
"$PY" "$REPO/tools/netns/drive.py" --api "http://127.0.0.1:$API_PORT" \
  --database "postgresql://$PG_USER@127.0.0.1:$PG_PORT/$DB" --jobs "$JOBS" \
  --host "host-a=${NS[a]}" --host "host-b=${NS[b]}" &
DRIVE=$!
wait "$DRIVE"
DRIVE=
FAILED=0
