"""Workers on two hosts, for real: ``tools/netns/two_hosts.sh`` makes two network namespaces,
runs a ``catwalk worker`` in each against Redis and PostgreSQL of the main namespace (through
forwarders on the veths' main-side addresses) and a shared storage folder, sends fast try-ons
through an API in the main namespace, and shows both hosts ran some. It needs root and
iproute2; where it cannot run the test fails with the reason (it is never skipped)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from .helpers import REPO

SCRIPT = REPO / "tools" / "netns" / "two_hosts.sh"
TIMEOUT_S = 170


def _cannot_run() -> str | None:
    if os.geteuid() != 0:
        return "it creates network namespaces: run the tests as root"
    for tool in ("ip", "unshare", "setsid"):
        if shutil.which(tool) is None:
            return f"'{tool}' is not installed (iproute2 / util-linux)"
    if not (Path(sys.prefix) / "bin" / "catwalk").is_file():
        return f"no catwalk command in {sys.prefix}/bin: run make install"
    return None


@pytest.mark.slow
def test_two_hosts_share_the_try_ons():
    reason = _cannot_run()
    if reason:
        pytest.fail(f"tools/netns/two_hosts.sh cannot run here: {reason}", pytrace=False)
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("CATWALK_") or k in ("CATWALK_DATA_DIR", "CATWALK_DATA")}
    env.update(CATWALK_VENV=sys.prefix, TWO_HOSTS_JOBS="6")
    try:
        res = subprocess.run(["bash", str(SCRIPT)], env=env, capture_output=True, text=True,
                             timeout=TIMEOUT_S, cwd=REPO)
    except subprocess.TimeoutExpired as exc:
        out = (exc.stdout or b"").decode(errors="replace") if isinstance(exc.stdout, bytes) \
            else exc.stdout or ""
        err = (exc.stderr or b"").decode(errors="replace") if isinstance(exc.stderr, bytes) \
            else exc.stderr or ""
        pytest.fail(f"two_hosts.sh ran past {TIMEOUT_S} s:\n{out[-3000:]}\n{err[-3000:]}",
                    pytrace=False)
    output = res.stdout + res.stderr
    assert res.returncode == 0, f"two_hosts.sh exited {res.returncode}:\n{output[-6000:]}"

    line = next(x for x in res.stdout.splitlines() if x.startswith("TWO_HOSTS_RESULT "))
    result = json.loads(line.split(" ", 1)[1])
    assert result["problems"] == []
    assert result["done"] == result["jobs"] == 6
    assert set(result["per_host"]) == {"host-a", "host-b"}
    assert all(n >= 1 for n in result["per_host"].values()), result["per_host"]
    assert sum(result["per_host"].values()) == 6
    for host, got in result["downloads"].items():   # written there, served from here
        assert got["status"] == 200 and got["bytes"] > 10_000, (host, got)

    # and nothing of it is left: namespaces, veths, database
    run = re.search(r"two_hosts: run ([0-9a-f]{6}):", res.stderr).group(1)
    assert f"catwalk-{run}-" not in subprocess.run(["ip", "netns", "list"], capture_output=True,
                                                   text=True).stdout
    links = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True).stdout
    assert f"cw{run}" not in links
    import psycopg

    with psycopg.connect("postgresql://postgres@127.0.0.1:5432/postgres") as c:
        assert c.execute("SELECT 1 FROM pg_database WHERE datname = %s",
                         (f"catwalk_netns_{run}",)).fetchone() is None
