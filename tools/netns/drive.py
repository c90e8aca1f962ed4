"""The client side of ``two_hosts.sh``: try-ons through the API, then who ran them.

``drive.py --api URL --database URL --jobs N --host NAME=NETNS --host NAME=NETNS``

1. waits for the API's ``/readyz``;
2. makes one body from measurements and asks for N fast 0.5 s try-ons of the pencil skirt,
   each a different content key (its sizes × fabrics), so none is answered from the cache or
   merged with another;
3. waits until every one has ended;
4. reads the ``worker`` column (``hostname:pid``) of their rows in the database and tells
   which namespace each ran in: the pid must be one of ``ip netns pids NETNS`` and the hostname
   the one that namespace's worker was given;
5. downloads each host's first result through the API (the files a worker in a namespace wrote
   into the shared storage, served by the API in the main namespace).

Prints a line per job, a line per host and one ``TWO_HOSTS_RESULT {json}`` line; exits 0 only
if every job is done and every host ran at least one.
"""

from __future__ import annotations

import argparse
import itertools
import json
import subprocess
import sys
import time

import httpx

MEASURES = {"sex": "female", "height": 1.68, "bust": 0.9, "waist": 0.72, "hips": 0.98}
GARMENT = "pencil-skirt"
ENDED = ("done", "failed", "cancelled")


def say(msg: str) -> None:
    print(f"two_hosts: {msg}", flush=True)


def wait_ready(client: httpx.Client, timeout: float) -> None:
    t0 = time.monotonic()
    last = None
    while time.monotonic() - t0 < timeout:
        try:
            r = client.get("/readyz")
            if r.status_code == 200:
                return
            last = r.text
        except httpx.HTTPError as exc:
            last = repr(exc)
        time.sleep(0.5)
    sys.exit(f"two_hosts: error: the API was not ready in {timeout:g} s ({last})")


def netns_pids(netns: str) -> set[int]:
    out = subprocess.run(["ip", "netns", "pids", netns], capture_output=True, text=True,
                         check=True).stdout
    return {int(p) for p in out.split()}


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--api", required=True)
    ap.add_argument("--database", required=True, help="the database (SQLAlchemy URL)")
    ap.add_argument("--jobs", type=int, default=6)
    ap.add_argument("--seconds", type=float, default=0.5)
    ap.add_argument("--host", action="append", required=True, help="NAME=NETNS")
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args()
    hosts = dict(h.split("=", 1) for h in args.host)

    client = httpx.Client(base_url=args.api, timeout=60.0)
    wait_ready(client, 60.0)
    t_body = time.monotonic()
    r = client.post("/api/bodies", json=MEASURES)
    if r.status_code != 201:
        sys.exit(f"two_hosts: error: POST /api/bodies answered {r.status_code}: {r.text}")
    body_id = r.json()["id"]
    say(f"body {body_id} made in {time.monotonic() - t_body:.1f} s")

    garment = client.get(f"/api/garments/{GARMENT}").json()
    sizes = [garment["default_size"]] + [s for s in garment["sizes"]
                                         if s != garment["default_size"]]
    combos = list(itertools.islice(itertools.product(sizes, garment["fabrics"]), args.jobs))
    if len(combos) < args.jobs:
        sys.exit(f"two_hosts: error: only {len(combos)} distinct try-ons of {GARMENT}")

    t0 = time.monotonic()
    ids = []
    for size, fabric in combos:
        r = client.post("/api/tryons", json={"body_id": body_id, "garment_id": GARMENT,
                                             "preset": "fast", "seconds": args.seconds,
                                             "size": size, "fabric": fabric})
        if r.status_code != 202:
            sys.exit(f"two_hosts: error: POST /api/tryons answered {r.status_code}: {r.text}")
        ids.append(r.json()["id"])
    say(f"{len(ids)} try-ons queued ({GARMENT}, fast, {args.seconds:g} s; "
        f"sizes × fabrics: {', '.join(f'{s}/{f}' for s, f in combos)})")

    status: dict[str, dict] = {}
    while True:
        for i in ids:
            if i not in status or status[i]["status"] not in ENDED:
                status[i] = client.get(f"/api/tryons/{i}").json()
        if all(s["status"] in ENDED for s in status.values()):
            break
        if time.monotonic() - t0 > args.timeout:
            late = {i: s["status"] for i, s in status.items() if s["status"] not in ENDED}
            sys.exit(f"two_hosts: error: not ended in {args.timeout:g} s: {late}")
        time.sleep(0.25)
    wall = time.monotonic() - t0

    # who ran them: the rows' worker column, against the namespaces' processes
    import psycopg

    pids = {name: netns_pids(ns) for name, ns in hosts.items()}
    with psycopg.connect(args.database.replace("+psycopg", "")) as conn:
        rows = conn.execute(
            "SELECT id, worker, status, attempts, started_at, finished_at FROM tryons "
            "WHERE id = ANY(%s)", (ids,)).fetchall()
    per_host = {name: 0 for name in hosts}
    problems = []
    first_of: dict[str, str] = {}
    for job_id, worker, st, attempts, started, finished in sorted(rows, key=lambda r: r[4]):
        hostname, _, pid = (worker or "?:0").rpartition(":")
        where = [name for name, ps in pids.items() if int(pid) in ps]
        host = where[0] if len(where) == 1 else None
        if host is None:
            problems.append(f"job {job_id}: worker {worker} is in no namespace's processes")
        elif hostname != host:
            problems.append(f"job {job_id}: worker {worker} runs in {hosts[host]} but its "
                            f"hostname is not {host!r}")
        else:
            per_host[host] += 1
            first_of.setdefault(host, job_id)
        if st != "done":
            problems.append(f"job {job_id} ended {st}: {status[job_id].get('error')}")
        took = (finished - started).total_seconds() if started and finished else float("nan")
        say(f"job {job_id[:8]} {st:<9} worker {worker:<20} netns {hosts.get(host, '?')} "
            f"attempts {attempts} ran {took:.2f} s")

    # the shared storage: each host's first result, written in its namespace, served here
    downloads = {}
    for host, job_id in first_of.items():
        r = client.get(f"/api/tryons/{job_id}/result.glb")
        ok = r.status_code == 200 and r.content[:4] == b"glTF"
        downloads[host] = {"job": job_id, "status": r.status_code, "bytes": len(r.content)}
        if not ok:
            problems.append(f"result of {job_id} (ran on {host}) not served: {r.status_code}")
    for host, n in per_host.items():
        say(f"host {host} (netns {hosts[host]}): {n} job(s)")
        if n == 0:
            problems.append(f"host {host} ran no job")
    say(f"{len(ids)} try-ons ended in {wall:.1f} s after the first was queued")
    result = {"jobs": len(ids), "done": sum(r[2] == "done" for r in rows),
              "per_host": per_host, "netns": hosts, "seconds": round(wall, 2),
              "downloads": downloads, "problems": problems}
    print("TWO_HOSTS_RESULT " + json.dumps(result), flush=True)
    for p in problems:
        say(f"problem: {p}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
