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
