#!/usr/bin/env bash
# Make sure the servers the tests talk to are up: Redis and PostgreSQL at
# CATWALK_TEST_REDIS_URL / CATWALK_TEST_DATABASE_URL (default: the local servers). A server
# that does not answer is started here; if it is not installed, Debian's package is installed
# first (apt-get; run as root). Only local (127.0.0.1 / localhost) servers are started: a
# remote URL that does not answer is an error. Prints the URLs it checked.
set -euo pipefail

REDIS_URL="${CATWALK_TEST_REDIS_URL:-redis://127.0.0.1:6379/15}"
DB_URL="${CATWALK_TEST_DATABASE_URL:-postgresql+psycopg://postgres@127.0.0.1:5432/postgres}"

say() { echo "services: $*" >&2; }

host_port() {   # URL default_port -> "host port"
  python3 - "$1" "$2" <<'PY'
import sys
from urllib.parse import urlsplit
u = urlsplit(sys.argv[1].replace("+psycopg", ""))
print(u.hostname or "127.0.0.1", u.port or int(sys.argv[2]))
PY
}

answers() {   # host port -> 0 if something listens there
  timeout 2 bash -c "exec 3<>/dev/tcp/$1/$2" 2>/dev/null
}

is_local() { [[ "$1" == "127.0.0.1" || "$1" == "localhost" || "$1" == "::1" ]]; }

apt_install() {
  if [ "$(id -u)" != 0 ]; then say "cannot install $* (not root)"; return 1; fi
  say "installing $* (Debian packages)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null 2>&1 || {
    apt-get update -q >/dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null; }
}

wait_for() {   # host port seconds
  for _ in $(seq 1 "$3"); do answers "$1" "$2" && return 0; sleep 1; done
  return 1
}

read -r RH RP < <(host_port "$REDIS_URL" 6379)
if ! answers "$RH" "$RP"; then
  is_local "$RH" || { say "Redis at $REDIS_URL does not answer"; exit 1; }
  command -v redis-server >/dev/null || apt_install redis-server
  mkdir -p /var/lib/redis /var/log/redis
  say "starting Redis on $RH:$RP"
  redis-server --daemonize yes --bind 127.0.0.1 -::1 --port "$RP" --save "" --appendonly no \
    --dir /var/lib/redis --logfile /var/log/redis/catwalk-test.log
  wait_for "$RH" "$RP" 20 || { say "Redis did not start"; exit 1; }
fi
say "Redis answers at $REDIS_URL"

read -r PH PP < <(host_port "$DB_URL" 5432)
if ! answers "$PH" "$PP"; then
  is_local "$PH" || { say "PostgreSQL at $DB_URL does not answer"; exit 1; }
  if ! ls /etc/postgresql/*/main >/dev/null 2>&1; then apt_install postgresql; fi
  ver="$(ls /etc/postgresql | sort -V | tail -1)"
  conf="/etc/postgresql/$ver/main/pg_hba.conf"
  # the tests connect as postgres over TCP from this machine only: trust it there
  if ! grep -q "catwalk-test" "$conf"; then
    sed -i '1i host all all 127.0.0.1/32 trust # catwalk-test\nhost all all ::1/128 trust # catwalk-test' "$conf"
  fi
  say "starting PostgreSQL $ver on $PH:$PP"
  pg_ctlcluster --skip-systemctl-redirect "$ver" main start || pg_ctlcluster "$ver" main start
  wait_for "$PH" "$PP" 30 || { say "PostgreSQL did not start"; exit 1; }
fi
say "PostgreSQL answers at $DB_URL"
