"""``catwalk loadtest`` against a real ``catwalk serve`` (one worker): a few shoppers for a few
seconds; the JSON summary has the documented keys, every route of the mix was asked, nothing
failed, and the try-ons asked for were simulated."""

from __future__ import annotations

import json
import subprocess
import sys

from .helpers import free_port, service_env


def test_loadtest_reports_every_route_of_the_mix(tmp_path, catalogue_dir, procs):
    env = service_env(tmp_path / "storage", catalogue_dir)
    port = free_port()
    serve = procs(["serve", f"--port={port}", "--workers=1"], env, "serve")
    serve.wait_for('"api_ready"', timeout=120)
    url = f"http://127.0.0.1:{port}"
    run = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "loadtest", "--url", url,
                          "--users", "4", "--seconds", "8", "--garment", "pencil-skirt",
                          "--json"], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    r = json.loads(run.stdout)
    assert {"requests", "failures", "per_route", "tryons_done", "tryons_per_minute"} <= set(r)
    assert r["failures"] == 0, r.get("errors")
    assert r["requests"] >= 50, r
    for route in ("GET /api/garments", "GET /api/garments/{id}",
                  "GET /api/garments/{id}/thumbnail.png", "GET /api/tryons/{id}",
                  "POST /api/tryons (cached)", "GET /api/tryons/{id}/result.glb"):
        s = r["per_route"][route]
        assert s["requests"] > 0 and 0 < s["p50_ms"] <= s["p95_ms"] <= s["p99_ms"], (route, s)
        assert s["rps"] > 0
    assert sum(s["requests"] for s in r["per_route"].values()) == r["requests"]


def test_loadtest_refuses_a_service_that_is_not_there(tmp_path):
    run = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "loadtest", "--url",
                          f"http://127.0.0.1:{free_port()}", "--users", "2", "--seconds", "2"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    assert "does not answer as ready" in run.stderr and "Traceback" not in run.stderr


def test_the_loadtest_json_has_the_timeline_and_the_5xx_the_chaos_run_reads(tmp_path,
                                                                           catalogue_dir, procs):
    """What ``--chaos`` reads of a run: the ids of the try-ons asked, a timeline (second,
    requests, p99) and the 5xx by status (none here)."""
    env = service_env(tmp_path / "storage", catalogue_dir)
    port = free_port()
    serve = procs(["serve", f"--port={port}", "--workers=1"], env, "serve")
    serve.wait_for('"api_ready"', timeout=120)
    run = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "loadtest", "--url",
                          f"http://127.0.0.1:{port}", "--users", "3", "--seconds", "5",
                          "--mix", "api", "--json"], env=env, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    r = json.loads(run.stdout)
    assert r["server_errors"] == {} and len(r["asked_ids"]) == r["tryons_asked"]
    seconds = [row[0] for row in r["timeline"]]
    assert seconds == sorted(seconds) and sum(row[1] for row in r["timeline"]) == r["requests"]
    assert all(row[2] > 0 for row in r["timeline"])


def test_the_chaos_schedule_and_windows():
    from catwalk.loadtest.chaos import _faults, _report, _window

    faults = _faults(180, 20)
    kills = [t for t, f in faults if f == "kill_worker"]
    assert kills == [20, 40, 60, 80, 100, 120, 140, 160]
    assert [f for _, f in faults].count("restart_redis") == 1
    assert [f for _, f in faults].count("restart_postgres") == 1
    timeline = [[s, 10 + s, 100.0 + s] for s in range(30)]
    w = _window(timeline, 10, 20)
    assert w["rps"] == sum(10 + s for s in range(10, 20)) / 10 and w["p99_ms"] == 119.0
    load = {"timeline": timeline, "requests": 1, "rps": 1.0,
            "server_errors": {"503 Retry-After GET /x": 3, "500 GET /y": 1}}
    outcomes = {"asked": 2, "done": 2, "failed": 0, "failed_reasons": {}, "cancelled": 0,
                "lost": [], "done_twice": []}
    r = _report(2, 30, load, [{"at_s": 12.0, "fault": "kill_worker", "detail": ""}], outcomes)
    assert r["unexpected_5xx"] == 1 and not r["ok"]     # a 500 is never expected
    load["server_errors"] = {"503 Retry-After GET /x": 3}
    assert _report(2, 30, load, [], outcomes)["ok"]


def test_chaos_refuses_a_url_and_a_short_run(tmp_path):
    for extra in (["--url", "http://127.0.0.1:1"], ["--seconds", "30"], ["--kill-every", "1"]):
        run = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "loadtest", "--chaos",
                              *extra], capture_output=True, text=True, timeout=120)
        assert run.returncode == 2 and "Traceback" not in run.stderr, (extra, run.stderr)
    run = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "loadtest"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "--url" in run.stderr
