"""The cores each process tree used while a command ran (``cores.py CMD ARGS…``): the load
generator (the command and its children), ``catwalk serve`` (its main process, and its children:
the body pool), ``catwalk worker`` (its main process, and its pool), PostgreSQL, Redis. Printed
as JSON on stderr: ``{"wall_s", "cores_used": {tree: cores}}``. psutil (installed with
Locust)."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time

import psutil

TREES = ("locust", "catwalk.cli.main worker", "catwalk serve", "postgres", "redis")
SPLIT = ("catwalk serve", "catwalk.cli.main worker")   # reported as (main) and (children)


def _tree(cmd: str) -> str | None:
    return next((t for t in TREES if t in cmd), None)


def snapshot() -> tuple[dict[int, float], dict[int, str | None]]:
    """CPU seconds by pid, and the tree each pid belongs to (its nearest named ancestor)."""
    seconds, parent, cmds = {}, {}, {}
    for p in psutil.process_iter(["pid", "ppid", "cmdline", "cpu_times"]):
        try:
            cmds[p.info["pid"]] = " ".join(p.info["cmdline"] or [])
            parent[p.info["pid"]] = p.info["ppid"]
            t = p.info["cpu_times"]
            seconds[p.info["pid"]] = t.user + t.system
        except (psutil.Error, TypeError):
            continue
    trees = {}
    for pid in seconds:
        q, tree, at = pid, None, pid
        while q and tree is None:
            tree, at, q = _tree(cmds.get(q, "")), q, parent.get(q)
        if tree in SPLIT:
            main = at == pid and _tree(cmds.get(parent.get(pid), "")) != tree
            tree += " (main)" if main else " (children)"
        trees[pid] = tree
    return seconds, trees


def main(argv: list[str]) -> int:
    before, _ = snapshot()
    t0 = time.monotonic()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    code = subprocess.run(argv).returncode
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    after, trees = snapshot()
    wall = time.monotonic() - t0
    used = {"load generator": (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)}
    for pid, t in after.items():
        tree = trees[pid]
        if tree is not None and tree != "locust":   # the generator's own: counted above
            used[tree] = used.get(tree, 0.0) + t - before.get(pid, 0.0)
    print(json.dumps({"wall_s": round(wall, 1),
                      "cores_used": {k: round(v / wall, 2) for k, v in used.items()}}),
          file=sys.stderr)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
