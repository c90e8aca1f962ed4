"""The API in-process (FastAPI's TestClient, the embedded default: SQLite and the filesystem
broker in a temporary storage folder): the catalogue, bodies, and every bad input answered
with its 4xx and a JSON error naming what is wrong — never a 500, never a traceback."""

from __future__ import annotations

import io

import numpy as np
import pytest
from fastapi.testclient import TestClient

from .helpers import MEASURES, make_config, service_env, storage_files


@pytest.fixture(scope="module")
def storage(tmp_path_factory):
    return tmp_path_factory.mktemp("storage")


@pytest.fixture(scope="module")
def client(storage, catalogue_dir):
    from catwalk.service.api.app import create_app

    config = make_config(service_env(storage, catalogue_dir, upload_max_bytes=3_000_000))
    with TestClient(create_app(config), raise_server_exceptions=False) as c:
        yield c


@pytest.fixture(scope="module")
def body(client):
    r = client.post("/api/bodies", json=MEASURES)
    assert r.status_code == 201, r.text
    return r.json()


def _error(r, status, field=None, code=None):
    assert r.status_code == status, (r.status_code, r.text)
    assert r.headers["content-type"].startswith("application/json")
    err = r.json()["error"]
    assert err["message"] and "Traceback" not in err["message"]
    if field is not None:
        assert err.get("field") == field, err
    if code is not None:
        assert err["code"] == code, err
    return err


def test_health_ready_and_openapi(client):
    assert client.get("/healthz").json() == {"status": "ok"}
    ready = client.get("/readyz")
    assert ready.status_code == 200, ready.text
    assert all(c["ok"] for c in ready.json()["checks"].values())
    spec = client.get("/openapi.json").json()
    for path in ("/api/garments", "/api/garments/{garment_id}", "/api/bodies",
                 "/api/bodies/{body_id}", "/api/tryons", "/api/tryons/{job_id}",
                 "/api/tryons/{job_id}/events", "/api/tryons/{job_id}/result.glb"):
        assert path in spec["paths"], path
    assert "multipart/form-data" in \
        spec["paths"]["/api/bodies"]["post"]["requestBody"]["content"]
    assert client.get("/docs").status_code == 200


def test_catalogue(client):
    garments = client.get("/api/garments").json()["garments"]
    assert [g["id"] for g in garments] == ["pencil-skirt"]
    g = garments[0]
    for key in ("id", "name", "type", "sizes", "default_size", "fabric", "fabrics",
                "thumbnail_url"):
        assert key in g, key
    assert g["fabric"] in g["fabrics"] and g["default_size"] in g["sizes"]
    assert client.get("/api/garments", params={"type": "dress"}).json()["garments"] == []
    one = client.get("/api/garments/pencil-skirt").json()
    assert one["panels"] and one["version"] == g["version"]
    png = client.get(g["thumbnail_url"])
    assert png.status_code == 200 and png.content[:8] == b"\x89PNG\r\n\x1a\n"
    if png.headers.get("etag"):
        again = client.get(g["thumbnail_url"], headers={"If-None-Match": png.headers["etag"]})
        assert again.status_code == 304
    dressed = client.get("/api/garments/pencil-skirt/dressed.glb")   # made with the thumbnail
    assert dressed.status_code == 200 and dressed.content[:4] == b"glTF"
    assert b"EXT_meshopt_compression" in dressed.content[:4000]
    pattern = client.get("/api/garments/pencil-skirt/pattern.png", params={"size": "S"})
    assert pattern.status_code == 200 and pattern.content[:4] == b"\x89PNG"
    _error(client.get("/api/garments/ballgown"), 404, "garment_id")
    _error(client.get("/api/garments/pencil-skirt/pattern.png", params={"size": "XXL"}),
           422, "size")


def test_body_from_measurements(client, body, storage):
    assert body["source"] == "measurements" and body["fit"] == "measurements"
    assert len(body["id"]) >= 32                       # unguessable
    assert body["measurements"]["bust"] == MEASURES["bust"]
    made = body["model_measurements"]
    for k in ("height", "bust", "waist", "hips"):
        assert abs(made[k] - MEASURES[k]) < 0.01, (k, made[k])
    again = client.get(f"/api/bodies/{body['id']}").json()
    assert again["model_measurements"] == made
    glb = client.get(body["body_url"])
    assert glb.status_code == 200 and glb.content[:4] == b"glTF"
    assert "scan" not in again
    head = client.head(body["body_url"])
    assert head.status_code == 200 and int(head.headers["content-length"]) == len(glb.content)
    assert client.get(body["body_url"], headers={"If-None-Match": glb.headers["etag"]}
                      ).status_code == 304
    # bodies are never listed
    assert client.get("/api/bodies").status_code == 405


@pytest.mark.parametrize("payload, status, field", [
    ({**MEASURES, "height": 3.0}, 422, "height"),
    ({**MEASURES, "bust": -1}, 422, "bust"),
    ({**MEASURES, "sex": "other"}, 422, "sex"),
    ({k: v for k, v in MEASURES.items() if k != "hips"}, 422, "hips"),
    ({**MEASURES, "shoe": 42}, 422, "shoe"),
    ({**MEASURES, "waist": 1.20, "bust": 0.80}, 422, "waist"),   # not a body the model makes
])
def test_bad_measurements(client, payload, status, field):
    _error(client.post("/api/bodies", json=payload), status, field)


def test_bad_body_requests(client):
    _error(client.post("/api/bodies", content=b"{not json",
                       headers={"content-type": "application/json"}), 400)
    _error(client.post("/api/bodies", content=b"sex=female",
                       headers={"content-type": "text/plain"}), 415)
    _error(client.post("/api/bodies", files={"other": ("x.obj", b"v 0 0 0\n")}), 422, "scan")
    _error(client.post("/api/bodies", files={"scan": ("body.fbx", b"Kaydara FBX")}), 415,
           "scan")
    _error(client.post("/api/bodies", files={"scan": ("body.obj", b"")}), 422, "scan")
    _error(client.post("/api/bodies", files={"scan": ("body.obj", b"v 1 2 3\nv oops\n")}),
           422, "scan")
    _error(client.post("/api/bodies", files={"scan": ("body.obj", b"v 0 0 0\n")},
                       data={"sex": "robot"}), 422, "sex")
    _error(client.get("/api/bodies/nope"), 404, "body_id")
    _error(client.delete("/api/bodies/nope"), 404, "body_id")
    _error(client.get("/api/bodies/nope/body.glb"), 404)


def test_a_scan_that_is_not_a_person_says_so(client):
    import trimesh

    box = trimesh.creation.box((0.5, 1.8, 0.3))
    err = _error(client.post("/api/bodies", files={"scan": ("box.stl",
                                                            box.export(file_type="stl"))}),
                 422, "scan")
    assert "body" in err["message"] or "human" in err["message"], err


def test_a_front_only_scan_is_a_422_naming_the_scan(client):
    """The hostile probe's scan: the body cut to its faces in front of a plane 5 cm behind its
    centre (it answered 500: NaN in the neck's measuring box)."""
    import trimesh

    from catwalk.body.rig import measured_base_body

    body = measured_base_body(0.0)
    v, f = np.asarray(body.vertices), np.asarray(body.faces)
    keep = v[f].mean(axis=1)[:, 2] > v[:, 2].mean() - 0.05
    obj = trimesh.Trimesh(v, f[keep], process=False).export(file_type="obj").encode()
    err = _error(client.post("/api/bodies", files={"scan": ("front.obj", obj)}), 422, "scan")
    assert "partial scan" in err["message"], err


def test_an_upload_over_the_limit_is_refused_unread(client, storage):
    before = set(storage_files(storage))
    big = b"v 0 0 0\n" * 500_000            # 4 MB, the limit is 3 MB
    err = _error(client.post("/api/bodies", files={"scan": ("big.obj", big)}), 413,
                 code="too_large")
    assert "limit" in err["message"]

    def chunks():                             # no Content-Length: refused as it arrives
        for _ in range(100):
            yield b"x" * 100_000

    r = client.post("/api/bodies", content=chunks(),
                    headers={"content-type": "multipart/form-data; boundary=zz"})
    _error(r, 413)
    r = client.post("/api/tryons", content=chunks(), headers={"content-type":
                                                              "application/json"})
    _error(r, 413)
    assert set(storage_files(storage)) == before   # nothing written


def test_scan_upload_units_and_axes_detected(client, storage):
    """A MakeHuman body exported in millimetres, Z up, facing -Y, as binary PLY."""
    import trimesh

    from catwalk.body.rig import measured_base_body

    b = measured_base_body(0.0)
    v = b.vertices * 1000.0
    v = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)      # glTF (Y up, +Z) -> Z up, -Y
    data = trimesh.Trimesh(v, b.faces, process=False).export(file_type="ply")
    r = client.post("/api/bodies", files={"scan": ("scan.ply", io.BytesIO(data))})
    assert r.status_code == 201, r.text
    out = r.json()
    assert out["source"] == "scan" and out["fit"] == "surface"
    assert out["scan"]["units"] == "mm" and out["scan"]["up_axis"] == "+Z"
    # the template registered to the scan's own surface: within a millimetre both ways
    dist = out["scan"]["surface_distance_mm"]
    assert dist["scan_to_body"]["mean"] < 1.0 and dist["body_to_scan"]["mean"] < 1.0, dist
    assert out["sex"] == "female" and out["sex_inferred"] is True
    assert client.get(f"/api/bodies/{out['id']}").json()["scan"] == out["scan"]
    assert abs(out["measurements"]["height"] - b.vertices[:, 1].max()) < 0.01
    for k in ("bust", "waist", "hips"):
        assert abs(out["model_measurements"][k] - out["measurements"][k]) < 0.015, k
    # the scan is stored for its body only, and goes with it
    assert (storage / "bodies" / out["id"] / "scan.ply").is_file()
    assert client.delete(f"/api/bodies/{out['id']}").status_code == 204
    assert not (storage / "bodies" / out["id"]).exists()
    _error(client.get(f"/api/bodies/{out['id']}"), 404)


@pytest.mark.parametrize("change, status, field", [
    ({"garment_id": "ballgown"}, 404, "garment_id"),
    ({"size": "XXXL"}, 422, "size"),
    ({"seconds": 0.1}, 422, "seconds"),
    ({"seconds": 11}, 422, "seconds"),
    ({"preset": "turbo"}, 422, "preset"),
    ({"fabric": "cardboard"}, 422, "fabric"),
    ({"colour": "red"}, 422, "colour"),
])
def test_bad_tryon_requests(client, body, change, status, field):
    req = {"body_id": body["id"], "garment_id": "pencil-skirt", **change}
    _error(client.post("/api/tryons", json=req), status, field)


def test_unknown_ids_and_states(client, body):
    _error(client.post("/api/tryons", json={"body_id": "nope", "garment_id": "pencil-skirt"}),
           404, "body_id")
    _error(client.post("/api/tryons", content=b"[", headers={"content-type":
                                                             "application/json"}), 400)
    _error(client.post("/api/tryons", json=[1, 2]), 422)
    _error(client.post("/api/tryons", content=b"body_id=x", headers={"content-type":
                                                                     "text/plain"}), 415)
    for path in ("", "/events", "/result.glb", "/preview.png"):
        _error(client.get(f"/api/tryons/nope{path}"), 404)
    _error(client.delete("/api/tryons/nope"), 404)
    _error(client.get("/api/no/such/route"), 404)
    # queued, no worker in this module: no result yet, and it can be cancelled
    job = client.post("/api/tryons", json={"body_id": body["id"], "garment_id":
                                           "pencil-skirt", "preset": "fast", "seconds": 0.5})
    assert job.status_code == 202, job.text
    jid = job.json()["id"]
    _error(client.get(f"/api/tryons/{jid}/result.glb"), 409, code="not_done")
    c = client.delete(f"/api/tryons/{jid}")
    assert c.status_code == 202 and c.json()["status"] == "cancelled"
    _error(client.delete(f"/api/tryons/{jid}"), 409)


def test_the_pages_are_served_with_a_history_fallback(tmp_path, catalogue_dir):
    from catwalk.service.api.app import create_app

    dist = tmp_path / "dist"
    (dist / "assets").mkdir(parents=True)
    (dist / "index.html").write_text("<!doctype html><title>catwalk</title>")
    (dist / "assets" / "app-1234.js").write_text("console.log(1)")
    (tmp_path / "secret.txt").write_text("not a page")
    config = make_config(service_env(tmp_path / "storage", catalogue_dir))
    with TestClient(create_app(config, recovery=False, frontend=dist)) as c:
        for path in ("/", "/body", "/garments/pencil-skirt", "/tryon/abc", "/compare?a=1&b=2"):
            r = c.get(path)
            assert r.status_code == 200 and "<title>catwalk</title>" in r.text, path
            assert r.headers["cache-control"] == "no-cache"
        js = c.get("/assets/app-1234.js")
        assert js.text == "console.log(1)" and "immutable" in js.headers["cache-control"]
        assert "not a page" not in c.get("/../secret.txt").text
        assert "not a page" not in c.get("/%2e%2e/secret.txt").text
        _error(c.get("/api/nope"), 404)
        # only the pages' GET fallback matches these: the API's 404, not a 405 allowing nothing
        _error(c.post("/api/nope", json={}), 404)
        _error(c.delete("/garments/x"), 404)
        r = c.delete("/api/garments")                          # a real route, another method
        assert r.status_code == 405 and r.headers["allow"] == "GET", r.headers
        # a GET where only another method is routed: 405 naming it, not the pages' 404
        for path in ("/api/bodies", "/api/tryons"):
            r = c.get(path)
            assert r.status_code == 405 and r.headers["allow"] == "POST", (path, r.text)
            _error(r, 405, code="method_not_allowed")
        assert c.get("/api/garments").json()["garments"]        # the API still answers
        assert c.get("/openapi.json").json()["paths"]
        sizes = c.get("/api/garments/pencil-skirt/sizes", params={"body_id": "x" * 32})
        _error(sizes, 404, "body_id")


def test_size_advice(client, body):
    r = client.get("/api/garments/pencil-skirt/sizes", params={"body_id": body["id"]})
    assert r.status_code == 200, r.text
    advice = r.json()
    rows = {row["size"]: row for row in advice["sizes"]}
    assert set(rows) == {"S", "M", "L"}
    # the body is the female S sample body's measurements: S fits exactly, L is roomy
    assert rows["S"]["ease"] == {"waist": 0.0, "hips": 0.0}   # a skirt: no bust
    assert rows["S"]["fits"] and rows["L"]["ease"]["hips"] > 0.1
    assert advice["recommended"] == "S"
    _error(client.get("/api/garments/pencil-skirt/sizes"), 422, "body_id")


def _scrape(client) -> dict[str, float]:
    r = client.get("/metrics")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/plain")
    out = {}
    for line in r.text.splitlines():
        if line and not line.startswith("#"):
            name, _, value = line.rpartition(" ")
            out[name] = float(value)
    return out


def test_metrics(client, body):
    before = _scrape(client)
    job = client.post("/api/tryons", json={"body_id": body["id"], "garment_id": "pencil-skirt",
                                           "preset": "fast", "seconds": 0.7}).json()
    client.delete(f"/api/tryons/{job['id']}")
    client.post("/api/bodies", files={"scan": ("x.fbx", b"Kaydara")})
    client.post("/api/bodies", content=b"x" * 4_000_000,
                headers={"content-type": "multipart/form-data; boundary=z"})
    after = _scrape(client)

    def grew(name, by=1.0):
        assert after.get(name, 0.0) - before.get(name, 0.0) == by, (name, before.get(name),
                                                                     after.get(name))

    grew('catwalk_jobs{state="cancelled"}')
    grew('catwalk_tryon_cache_total{result="miss"}')
    grew('catwalk_uploads_refused_total{reason="too_large"}')
    grew('catwalk_uploads_refused_total{reason="unsupported_type"}')
    grew('catwalk_http_request_seconds_count{code="202",method="POST",route="/api/tryons"}')
    assert after["catwalk_workers_alive"] == 0.0 and after['catwalk_jobs{state="running"}'] == 0
    assert "catwalk_queue_messages" in after
    text = client.get("/metrics").text
    assert body["id"] not in text and job["id"] not in text   # routes by template: no ids


@pytest.mark.parametrize("payload", [
    b"[" * 100_000 + b"]" * 100_000,                   # 100,000 nested arrays
    b'{"a":' * 50_000 + b"1" + b"}" * 50_000,          # 50,000 nested objects
])
def test_deeply_nested_json_is_a_400_not_a_500(client, payload):
    for route in ("/api/bodies", "/api/tryons"):
        _error(client.post(route, content=payload, headers={"content-type":
                                                            "application/json"}), 400)


@pytest.mark.parametrize("route, payload, field", [
    ("/api/bodies", {**MEASURES, "height": "1.68"}, "height"),      # a string is not a number
    ("/api/bodies", {**MEASURES, "bust": True}, "bust"),            # nor is true
    ("/api/tryons", {"garment_id": "pencil-skirt", "seconds": True}, "seconds"),
    ("/api/tryons", {"garment_id": "pencil-skirt", "seconds": "2"}, "seconds"),
    ("/api/tryons", {"garment_id": 7}, "garment_id"),
])
def test_numbers_are_numbers(client, body, route, payload, field):
    if route == "/api/tryons":
        payload = {"body_id": body["id"], **payload}
    _error(client.post(route, json=payload), 422, field)


def test_a_long_path_or_query_is_a_json_414(client):
    _error(client.get("/api/garments/" + "a" * 5000), 414, code="uri_too_long")
    _error(client.get("/api/garments", params={"q": "a" * 20_000}), 414, code="uri_too_long")
    assert client.get("/api/garments", params={"type": "dress"}).status_code == 200
