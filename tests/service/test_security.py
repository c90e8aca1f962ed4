"""Security checks, each as an attacker would try it against the API in-process (the embedded
default) or against the reader the API hands an upload to: file names that climb out of the
storage, guessed ids, files whose headers lie about their size, uploads far over the limit.
A merchant's routes take no file name with a NUL byte and no version number beyond the
database's; an unexpected error keeps the connection open (a real server: tests/service/
test_faults.py)."""

from __future__ import annotations

import json
import secrets
import struct
import time

import pytest
from fastapi.testclient import TestClient

from .helpers import MEASURES, REPO, make_config, service_env, storage_files

LIMIT = 3_000_000


@pytest.fixture(scope="module")
def storage(tmp_path_factory):
    return tmp_path_factory.mktemp("sec") / "storage"


@pytest.fixture(scope="module")
def client(storage, catalogue_dir):
    from catwalk.service.api.app import create_app

    config = make_config(service_env(storage, catalogue_dir, upload_max_bytes=LIMIT))
    with TestClient(create_app(config), raise_server_exceptions=False) as c:
        yield c


def _refused(r, *statuses):
    assert r.status_code in statuses, (r.status_code, r.text[:300])
    assert r.headers["content-type"].startswith("application/json")
    assert "Traceback" not in r.text
    return r.json()["error"]


def _scan_obj() -> bytes:
    from catwalk.body.rig import measured_base_body

    body = measured_base_body(0.0)
    lines = [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in body.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in body.faces]
    return "\n".join(lines).encode()


@pytest.mark.parametrize("name", ["../../../escape.obj", "..\\..\\escape.obj",
                                  "/etc/escape.obj", "a/../../escape.obj", "%2e%2e/escape.obj"])
def test_upload_file_names_cannot_climb_out_of_the_storage(client, storage, name, mpfb2,
                                                          tmp_path_factory):
    # every folder a climbing name could reach from the storage's (pytest's whole tree)
    outside = tmp_path_factory.getbasetemp().parent

    def beside():
        return {p for p in outside.rglob("*escape*") if storage not in p.parents}

    before = beside()
    r = client.post("/api/bodies", files={"scan": (name, _scan_obj(), "text/plain")})
    assert r.status_code == 201, r.text[:300]
    assert beside() == before, beside() - before       # nothing written by that name
    assert not any("escape" in p.name for p in storage_files(storage))   # names not used
    assert "escape" not in r.text


@pytest.mark.parametrize("path,answer", [
    # a slash in an id does not reach a route
    ("/api/garments/..%2F..%2Fpyproject.toml", "no such route"),
    ("/api/bodies/..%2F..%2Fcatwalk.sqlite3/body.glb", "no such route"),
    ("/api/tryons/..%2F..%2Fresults/result.glb", "no such route"),
    # ".." as the id itself reaches the route: an unknown id, never a path
    ("/api/garments/%2e%2e/thumbnail.png", "no garment with id '..'"),
    ("/api/garments/%2e%2e/pattern.png", "no garment with id '..'"),
    ("/api/bodies/%2e%2e/body.glb", "no body"),
    ("/api/tryons/%2e%2e/result.glb", "no try-on"),
])
def test_ids_in_paths_cannot_name_files(client, path, answer):
    err = _refused(client.get(path), 404)
    assert err["code"] == "not_found" and answer in err["message"], err


def test_a_size_cannot_name_a_file(client):
    err = _refused(client.get("/api/garments/pencil-skirt/pattern.png",
                              params={"size": "../../../pyproject.toml"}), 422)
    assert err["field"] == "size", err


def test_a_body_id_cannot_be_guessed_or_listed(client):
    made = client.post("/api/bodies", json=MEASURES)
    assert made.status_code == 201
    real = made.json()["id"]
    assert len(real) == 32 and real.replace("-", "").replace("_", "").isalnum()
    # 192 random bits: neighbours of a real id, random ids and short ids are all unknown
    near = [real[:-1] + c for c in "AaZz09-_" if c != real[-1]]
    guesses = near + [secrets.token_urlsafe(24) for _ in range(50)] + ["1", "0" * 32, "*", "%"]
    for guess in guesses:
        _refused(client.get(f"/api/bodies/{guess}"), 404)
        _refused(client.get(f"/api/bodies/{guess}/body.glb"), 404)
    # no route lists bodies
    _refused(client.get("/api/bodies"), 404, 405)
    assert client.get(f"/api/bodies/{real}").status_code == 200


def _glb(doc: dict, blob: bytes = b"") -> bytes:
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob += b"\0" * (-len(blob) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js
    if blob:
        body += struct.pack("<I4s", len(blob), b"BIN\0") + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def test_a_glb_claiming_a_4gb_buffer_is_refused_at_once(client, storage):
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4 * 1024 ** 3}],
           "bufferViews": [{"buffer": 0, "byteLength": 4 * 1024 ** 3}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 357_913_941,
                          "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]},
                         {"bufferView": 0, "componentType": 5125, "count": 1_000_000_000,
                          "type": "SCALAR"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    before = set(storage_files(storage))
    t0 = time.monotonic()
    err = _refused(client.post("/api/bodies", files={"scan": ("huge.glb", _glb(doc, b"\0" * 64),
                                                              "model/gltf-binary")}), 422)
    assert time.monotonic() - t0 < 5
    assert err["field"] == "scan" and "4,294,967,296 bytes" in err["message"], err
    assert set(storage_files(storage)) == before


def test_a_dxf_claiming_a_billion_point_polyline_is_read_for_what_it_holds(tmp_path):
    """The vertex count an LWPOLYLINE declares (group 90) is not trusted: a billion claimed,
    four held, four read, at once; a billion *held* is refused by the size limits
    (tests/fuzz and docs/garment-format.md, 'Limits')."""
    import ezdxf

    from catwalk.exchange.dxf import read_dxf

    doc = ezdxf.new("R2010")   # a plain DXF: one closed LWPOLYLINE, a panel 0.5 × 0.6 m
    doc.header["$INSUNITS"] = 6
    doc.modelspace().add_lwpolyline([(0, 0), (0.5, 0), (0.5, 0.6), (0, 0.6)], close=True)
    path = tmp_path / "plain.dxf"
    doc.saveas(path)
    lines = path.read_bytes().split(b"\n")
    counts = [k for k in range(len(lines) - 1) if lines[k].strip() == b"90"]
    assert counts, "an LWPOLYLINE has its vertex count"
    for k in counts:
        lines[k + 1] = b"1000000000"
    t0 = time.monotonic()
    pieces = read_dxf(b"\n".join(lines), units="m")[0]
    assert time.monotonic() - t0 < 5
    assert [p.summary()["area_m2"] for p in pieces] == [pytest.approx(0.3)]


def test_an_upload_ten_times_over_the_limit_is_refused_unread(client, storage):
    before = set(storage_files(storage))
    t0 = time.monotonic()
    err = _refused(client.post("/api/bodies", files={"scan": ("big.stl", b"\0" * (10 * LIMIT))}),
                   413)
    assert err["code"] == "too_large" and f"{LIMIT:,}" in err["message"]
    assert time.monotonic() - t0 < 5
    assert set(storage_files(storage)) == before


def test_a_merchants_paths_take_no_nul_and_no_huge_version(client):
    from catwalk.service import merchants

    key = merchants.create(client.app.state.config, "prober")
    auth = {"Authorization": f"Bearer {key}"}
    skirt = json.loads((REPO / "garments" / "pencil-skirt.json").read_text())
    for panel in skirt["panels"]:
        panel.pop("texture", None)
    r = client.post("/api/merchant/garments", headers=auth, files=[
        ("garment", ("garment.json", json.dumps(skirt).encode(), "application/json"))])
    assert r.status_code == 201, r.text
    gid = r.json()["id"]
    base = f"/api/merchant/garments/{gid}/versions"
    assert client.get(f"{base}/1/files/garment.json", headers=auth).status_code == 200
    for name in ("garment.json%00.png", "garment.json%00", "%00", "a%01b.png"):
        _refused(client.get(f"{base}/1/files/{name}", headers=auth), 404)
    for version in ("99999999999999999999999", str(2 ** 31), "0", "-1"):
        err = _refused(client.get(f"{base}/{version}/dressed/M.glb", headers=auth), 422)
        assert err["field"] == "version", err
    for body in ({"version": 1, "nope": 2}, {"version": True}, {"version": "1"},
                 {"version": 2 ** 40}):
        err = _refused(client.post(f"/api/merchant/garments/{gid}/publish", headers=auth,
                                   json=body), 422)
        assert err["field"] in ("nope", "version"), err
    _refused(client.post(f"/api/merchant/garments/{gid}/publish", headers={
        **auth, "content-type": "application/json"}, content=b"[" * 50_000), 400)


def test_a_deleted_bodys_measurements_leave_no_readable_trace(client, storage):
    """As a probe would: after DELETE, read every file of the storage folder (the embedded
    database, its write-ahead log and shared memory, every blob) byte by byte for the
    measurements sent — as text (the JSON column) and as SQLite's big-endian doubles; and no
    file or folder of it is readable by another user."""
    values = {"sex": "female", "height": 1.6789, "bust": 0.9123, "waist": 0.7345, "hips": 0.9876}
    made = client.post("/api/bodies", json=values)
    assert made.status_code == 201, made.text
    needles = [repr(v).encode() for k, v in values.items() if k != "sex"]
    needles += [struct.pack(">d", v) for k, v in values.items() if k != "sex"]
    files = [p for p in storage.rglob("*") if p.is_file()]
    assert any(n in p.read_bytes() for p in files for n in needles), "the probe finds nothing"
    assert storage.stat().st_mode & 0o077 == 0, oct(storage.stat().st_mode)
    for p in files:
        if p.name.startswith("catwalk.sqlite3"):
            assert p.stat().st_mode & 0o077 == 0, (p.name, oct(p.stat().st_mode))
    body_id = made.json()["id"]
    assert client.delete(f"/api/bodies/{body_id}").status_code == 204
    assert not storage.joinpath("bodies", body_id).exists()
    others = storage / "bodies"   # the other tests' bodies: scans whose digits may match
    for p in (p for p in storage.rglob("*") if p.is_file() and others not in p.parents):
        data = p.read_bytes()
        found = [n for n in needles if n in data]
        assert not found, (p.relative_to(storage), found)
