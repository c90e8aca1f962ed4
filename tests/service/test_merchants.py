"""Merchants: API keys (made by ``catwalk merchant create``), garment uploads over the API (a
garment JSON with textures, or a Gerber- or CLO-style DXF with its markup), every problem in
one 422, the dressing check per size in a real worker, publishing into the catalogue, a
try-on with the merchant's garment, and a new version leaving the old try-on's result intact.
PostgreSQL and Redis are the real servers; the worker a real ``catwalk worker`` process."""

from __future__ import annotations

import copy
import json
import subprocess
import sys

import pytest
from fastapi.testclient import TestClient

from .helpers import (
    MEASURES,
    REPO,
    bearer,
    create_merchant,
    dxf_fixtures,
    make_config,
    service_env,
    skirt_json,
    start_worker,
    textures,
    upload_json,
    wait_dressing,
    wait_job,
)

SKIRT_MARKUP, write_pattern = dxf_fixtures().SKIRT_MARKUP, dxf_fixtures().write_pattern


@pytest.fixture
def shop(tmp_path, catalogue_dir, pg_url, redis_url, queue_name):
    env = service_env(tmp_path / "storage", catalogue_dir, database_url=pg_url,
                      broker_url=redis_url, queue=queue_name)
    return env, make_config(env)


def test_keys_from_the_cli_and_who_may_see_what(shop):
    from catwalk.service.api.app import create_app

    env, config = shop
    key_a, key_b = create_merchant(env, "shop-a"), create_merchant(env, "shop-b")
    assert key_a != key_b and key_a.startswith("cwk_")
    again = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", "create",
                            "shop-a"], env=env, capture_output=True, text=True, cwd=REPO)
    assert again.returncode == 2 and "exists already" in again.stderr
    listed = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", "list",
                             "--json"], env=env, capture_output=True, text=True, cwd=REPO)
    rows = json.loads(listed.stdout)
    assert [r["name"] for r in rows] == ["shop-a", "shop-b"]
    assert key_a not in listed.stdout and key_b not in listed.stdout   # never shown again
    with TestClient(create_app(config, recovery=False)) as client:
        r = client.get("/api/merchant/garments")
        assert r.status_code == 401 and r.headers["www-authenticate"].startswith("Bearer")
        assert r.json()["error"]["code"] == "unauthorized"
        assert client.get("/api/merchant/garments",
                          headers=bearer("cwk_" + "x" * 43)).status_code == 401
        assert client.get("/api/merchant/garments",
                          headers={"Authorization": key_a}).status_code == 401
        assert client.get("/api/merchant/me", headers=bearer(key_a)).json()["name"] == "shop-a"
        skirt = skirt_json(name="A's skirt")
        r = upload_json(client, key_a, skirt, textures(skirt))
        assert r.status_code == 201, r.text
        made = r.json()
        gid = made["id"]
        assert made["version"] == 1 and made["sizes"] == skirt["sizes"]
        assert set(made["dressing"]) == set(skirt["sizes"])
        # another merchant's garment is "no such garment", for every route
        for method, path in (("GET", ""), ("DELETE", ""), ("POST", "/publish"),
                             ("GET", "/versions/1/files/garment.json")):
            r = client.request(method, f"/api/merchant/garments/{gid}{path}",
                               headers=bearer(key_b))
            assert r.status_code == 404, (method, path, r.text)
        assert upload_json(client, key_b, skirt, method="PUT", gid=gid).status_code == 404
        assert client.get("/api/merchant/garments", headers=bearer(key_b)).json() == \
            {"garments": []}
        mine = client.get("/api/merchant/garments", headers=bearer(key_a)).json()["garments"]
        assert [g["id"] for g in mine] == [gid] and mine[0]["published_version"] is None
        # a draft is not in the catalogue
        assert client.get(f"/api/garments/{gid}").status_code == 404
        # revoked: 401, and its garment stays its own
        subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", "revoke", "shop-a"],
                       env=env, check=True, capture_output=True, cwd=REPO)
        r = client.get("/api/merchant/garments", headers=bearer(key_a))
        assert r.status_code == 401 and "revoked" in r.json()["error"]["message"]


def test_a_broken_garment_is_refused_with_every_problem_and_nothing_stored(shop):
    from sqlalchemy import func, select

    from catwalk.service import merchants
    from catwalk.service.api.app import create_app
    from catwalk.service.store import db
    from catwalk.service.store.models import GarmentVersionRow, MerchantGarmentRow

    env, config = shop
    with TestClient(create_app(config, recovery=False)) as client:
        key = merchants.create(config, "broken-shop")
        g = skirt_json()
        panels = {p["name"]: p for p in g["panels"]}
        first = g["panels"][0]["name"]
        # 1. a seam between edges of different length: one side one edge longer
        seam = next(sm for sm in g["seams"] if sm["name"] == "centre back")
        seam["a"]["end"] += 1
        # 2. an unknown panel
        g["seams"].append({"name": "ghost", "a": {"panel": "no-such-panel", "start": 0,
                                                  "end": 1},
                           "b": {"panel": first, "start": 0, "end": 1}})
        # 3. an unclosed outline (another panel): edge 0 says it ends somewhere else
        last = panels["front"]
        edge0 = last["shapes"][g["sizes"][0]]["outline"][0]
        edge0["end"] = [edge0["start"][0] + 0.5, edge0["start"][1] + 0.5]
        # 4. a missing texture
        panels[first]["texture"] = {"image": "textures/not-sent.png", "size": [0.1, 0.1]}
        r = upload_json(client, key, g, textures(g))
        assert r.status_code == 422, r.text
        err = r.json()["error"]
        assert err["code"] == "invalid_garment"
        msgs = [p["message"] for p in err["problems"]]
        assert any("lengths differ" in m for m in msgs), msgs
        assert any("no panel named 'no-such-panel'" in m for m in msgs), msgs
        assert any("not closed" in m for m in msgs), msgs
        assert any("not-sent.png" in m and "not found" in m for m in msgs), msgs
        assert not any(str(config.storage_dir) in m for m in msgs), msgs   # no server paths
        by = {p["message"]: p for p in err["problems"]}
        unclosed = next(p for m, p in by.items() if "not closed" in m)
        assert unclosed["panel"] == last["name"] and unclosed["edge"] == 0
        missing = next(p for m, p in by.items() if "not-sent" in m)
        assert missing["panel"] == first
        me = merchants.authenticate(config, key).id
        with db.session(config) as s:   # (the database is the test session's)
            mine = select(MerchantGarmentRow.id).where(MerchantGarmentRow.merchant_id == me)
            assert s.scalar(select(func.count()).select_from(mine.subquery())) == 0
            assert s.scalar(select(func.count()).select_from(GarmentVersionRow)
                            .where(GarmentVersionRow.garment_id.in_(mine))) == 0
        left = [p for p in (config.storage_dir / "garments").rglob("*") if p.is_file()]
        assert left == []
        # neither a garment nor a DXF; a DXF without markup; a texture outside the garment
        r = client.post("/api/merchant/garments", files=[("units", (None, "mm"))],
                        headers=bearer(key))
        assert r.status_code == 422 and "either" in r.json()["error"]["message"]
        r = client.post("/api/merchant/garments", files=[("dxf", ("p.dxf", b"0\nEOF\n"))],
                        headers=bearer(key))
        assert r.status_code == 422 and r.json()["error"]["field"] == "markup"
        r = upload_json(client, key, skirt_json(), [("../escape.png", b"x")])
        assert r.status_code == 422 and "relative path" in r.text
        r = client.post("/api/merchant/garments", json={"x": 1}, headers=bearer(key))
        assert r.status_code == 415


@pytest.mark.parametrize("style,units", [("gerber", "ENGLISH"), ("clo", "METRIC")])
def test_dxf_import_for_the_editor(shop, tmp_path, style, units):
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    env, config = shop
    path = write_pattern(tmp_path / f"{style}.dxf", style=style, units=units)
    with TestClient(create_app(config, recovery=False)) as client:
        key = merchants.create(config, f"importer-{style}")
        r = client.post("/api/merchant/import", headers=bearer(key),
                        files=[("dxf", (path.name, path.read_bytes(), "application/dxf"))])
        assert r.status_code == 200, r.text
        out = r.json()
        assert {p["name"] for p in out["garment"]["panels"]} == {"FRONT", "BACK", "BACK (2)"}
        assert out["garment"]["sizes"] == ["S", "M", "L"] and out["garment"]["seams"] == []
        assert len(out["pieces"]) == 6
        r = client.post("/api/merchant/import", headers=bearer(key),
                        files=[("dxf", ("junk.dxf", b"not a dxf at all"))])
        assert r.status_code == 422 and r.json()["error"]["field"] == "dxf"
        assert "junk.dxf" in r.json()["error"]["message"] or "DXF" in r.json()["error"]["message"]


def test_a_dxf_of_255_blocks_in_15_sizes_imports_and_uploads(shop, tmp_path):
    """The size of real Gerber exports: 17 pieces × 15 sizes = 255 blocks."""
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    env, config = shop
    fx = dxf_fixtures()
    sizes = [str(34 + 2 * i) for i in range(15)]
    extra = [(f"P{k}_{s}", f"P{k}", s, fx._rect(5 + 0.1 * k, 8)) for k in range(15)
             for s in sizes]
    path = fx.write_pattern(tmp_path / "big.dxf", sizes=sizes, extra_pieces=extra)
    with TestClient(create_app(config, recovery=False)) as client:
        key = merchants.create(config, "big-shop")
        r = client.post("/api/merchant/import", headers=bearer(key),
                        files=[("dxf", (path.name, path.read_bytes(), "application/dxf"))])
        assert r.status_code == 200, r.text
        assert len(r.json()["pieces"]) == 255 and r.json()["garment"]["sizes"] == sizes
        # with the skirt's markup, the other pieces not sewn: refused, each named
        mk = dict(SKIRT_MARKUP, default_size="40")
        r = client.post("/api/merchant/garments", headers=bearer(key), files=[
            ("dxf", (path.name, path.read_bytes(), "application/dxf")),
            ("markup", ("markup.json", json.dumps(mk).encode(), "application/json"))])
        assert r.status_code == 422, r.text
        problems = r.json()["error"]["problems"]
        assert len(problems) == 1 and "not reachable" in problems[0]["message"]
        assert all(f"'P{k}'" in problems[0]["message"] for k in range(15))


def test_a_real_exports_repairs_and_assumptions_come_back_as_warnings(shop, tmp_path):
    """A CLO-style export with every class of issue 46 (cm under 'Units: METRIC', the sample
    size's 'Quantity: 0', a pocket of sizes M and L, repeated points, small loops): the
    editor's import and the upload (201) list each repair and assumption as an object, with the
    panel it concerns as the markup names it; the stored garment keeps them on its panels. A
    large self-crossing is refused naming the piece, the size and the place."""
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    env, config = shop
    fx = dxf_fixtures()
    path = fx.write_real_export(tmp_path / "real.dxf")
    dxf = ("dxf", (path.name, path.read_bytes(), "application/dxf"))
    markup = ("markup", ("markup.json", json.dumps(fx.real_export_markup()).encode(),
                         "application/json"))
    with TestClient(create_app(config, recovery=False)) as client:
        key = merchants.create(config, "real-exports")
        r = client.post("/api/merchant/import", headers=bearer(key), files=[dxf])
        assert r.status_code == 200, r.text
        out = r.json()
        codes = [w["code"] for w in out["warnings"]]
        assert codes.count("loop-removed") == 6 and codes.count("sample-quantity") == 3
        assert {"units", "duplicate-points", "sizes"} <= set(codes)
        units = next(w for w in out["warnings"] if w["code"] == "units")
        assert units["units"] == "cm" and "read in centimetres" in units["message"]
        pocket = next(p for p in out["garment"]["panels"] if p["name"] == "POCKET")
        assert sorted(pocket["shapes"]) == ["L", "M"]
        assert [w["code"] for w in pocket["meta"]["import_warnings"]] == ["sample-quantity",
                                                                         "sizes"]
        r = client.post("/api/merchant/garments", headers=bearer(key), files=[dxf, markup])
        assert r.status_code == 201, r.text
        made = r.json()
        assert made["sizes"] == ["S", "M", "L"]
        by_code = {}
        for w in made["warnings"]:
            by_code.setdefault(w["code"], []).append(w)
        assert {w["panel"] for w in by_code["loop-removed"]} == {"front", "back_left"}
        assert by_code["sizes"][0]["panel"] == "pocket" and by_code["sizes"][0]["piece"] == \
            "POCKET"
        assert by_code["duplicate-points"][0]["size"] == "M"
        assert all(w["message"].startswith("dxf: ") for w in by_code["loop-removed"])
        item = client.get(f"/api/merchant/garments/{made['id']}", headers=bearer(key)).json()
        assert item["versions"][0]["warnings"] == made["warnings"]
        front = next(p for p in item["garment"]["panels"] if p["name"] == "front")
        assert [w["code"] for w in front["meta"]["import_warnings"]] == [
            "loop-removed", "sample-quantity", "loop-removed", "loop-removed"]
        # a large crossing: refused with where it is
        bad = fx.write_pattern(tmp_path / "x.dxf", outline=fx.figure_eight())
        r = client.post("/api/merchant/garments", headers=bearer(key), files=[
            ("dxf", (bad.name, bad.read_bytes(), "application/dxf")), markup])
        assert r.status_code == 422
        problem = r.json()["error"]["problems"][0]
        assert problem["size"] == "L" and "piece 'BACK' (size L): the outline crosses itself " \
            "near (27.9, 30.5) cm from the piece's lower-left corner" in problem["message"]


def test_dxf_and_markup_dress_publish_tryon_and_versions(shop, procs, tmp_path):
    """Gerber- and CLO-style DXFs with their markup → dressed per size → published → a
    try-on; a new version leaves the old try-on's result in place."""
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    env, config = shop
    start_worker(procs, env)
    # an A-line skirt that stays at the waist: 74 cm there, 140 cm at the hem in size M (the
    # fixture's rectangles, 152 cm round the top, slide off a body: the check says so)
    width, taper = 9.19, 4.32   # inches
    markup = copy.deepcopy(SKIRT_MARKUP)
    markup["seams"][0]["b"]["start"] = {"point": [taper * 0.0254, 0.6096]}
    with TestClient(create_app(config)) as client:
        key = merchants.create(config, "dxf-shop")
        made = {}
        # the CLO file: size M alone, the Gerber file's M (its S on female-M is 74 cm round
        # a 72 cm waist with 4 mm of cloth: the centre back stays 7.5 cm open, as it should)
        for style, units, sizes, w in (("gerber", "ENGLISH", ("S", "M", "L"), width),
                                       ("clo", "METRIC", ("M",), width + 0.5)):
            path = write_pattern(tmp_path / f"{style}.dxf", style=style, units=units,
                                 sizes=sizes, width=w, taper=taper)
            mk = dict(markup, name=f"{style} skirt", default_size="M")
            r = client.post("/api/merchant/garments", headers=bearer(key), files=[
                ("dxf", (path.name, path.read_bytes(), "application/dxf")),
                ("markup", ("markup.json", json.dumps(mk).encode(), "application/json"))])
            assert r.status_code == 201, r.text
            out = r.json()
            assert out["sizes"] == list(sizes) and out["version"] == 1
            made[style] = out["id"]
        for style, gid in made.items():
            v = wait_dressing(client, key, gid, 1)
            for size, rep in v["dressing"].items():
                assert rep["status"] == "dressed", (style, size, rep)
                assert rep["ok"] is True and rep["sample"] == f"female-{size}"
                assert all(rep["checks"].values()) and rep["top_above_crotch_mm"] > 200
                assert rep["seam_gap_mm"] <= rep["limits"]["seam_gap_mm"]
                assert rep["max_strain"] <= rep["limits"]["strain"]
                glb = client.get(rep["glb_url"], headers=bearer(key))
                assert glb.status_code == 200 and glb.content[:4] == b"glTF"
                assert client.get(rep["glb_url"]).status_code == 401
        gid = made["gerber"]
        listing = client.get("/api/garments").json()["garments"]
        assert gid not in {g["id"] for g in listing}           # a draft
        r = client.post(f"/api/merchant/garments/{gid}/publish", headers=bearer(key))
        assert r.status_code == 200 and r.json()["published_version"] == 1
        listing = client.get("/api/garments").json()["garments"]
        assert gid in {g["id"] for g in listing}
        entry = client.get(f"/api/garments/{gid}").json()
        assert entry["name"] == "gerber skirt" and entry["sizes"] == ["S", "M", "L"]
        thumb = client.get(f"/api/garments/{gid}/thumbnail.png")
        assert thumb.status_code == 200 and thumb.headers["cache-control"].startswith("public")
        # a try-on with it
        body = client.post("/api/bodies", json=MEASURES).json()
        ask = {"body_id": body["id"], "garment_id": gid, "size": "M", "preset": "fast",
               "seconds": 0.5}
        job = wait_job(client, client.post("/api/tryons", json=ask).json()["id"])
        assert job["status"] == "done", job
        old = client.get(job["result_url"]).content
        assert old[:4] == b"glTF"
        # version 2 (a different fabric), published: the old try-on's result stays
        path = tmp_path / "gerber.dxf"
        r = client.put(f"/api/merchant/garments/{gid}", headers=bearer(key), files=[
            ("dxf", (path.name, path.read_bytes(), "application/dxf")),
            ("markup", ("markup.json", json.dumps(dict(markup, name="gerber skirt",
                                                       fabric="cotton-jersey")).encode(),
                        "application/json"))])
        assert r.status_code == 200 and r.json()["version"] == 2, r.text
        r = client.post(f"/api/merchant/garments/{gid}/publish", headers=bearer(key),
                        json={"version": 2})
        assert r.json()["published_version"] == 2
        assert client.get(f"/api/garments/{gid}").json()["version"] != job["garment_version"]
        again = client.get(f"/api/tryons/{job['id']}")
        assert again.json()["status"] == "done"
        assert client.get(job["result_url"]).content == old
        job2 = client.post("/api/tryons", json=ask).json()
        assert job2["garment_version"] != job["garment_version"] and not job2["cached"]
        # the first version asked again: answered from the cache under its version
        r = client.post(f"/api/merchant/garments/{gid}/publish", headers=bearer(key),
                        json={"version": 1})
        cached = client.post("/api/tryons", json=ask)
        assert cached.status_code == 200 and cached.json()["cached"] is True
        client.delete(f"/api/tryons/{job2['id']}")
        # deleted: out of the catalogue and the list
        assert client.delete(f"/api/merchant/garments/{gid}",
                             headers=bearer(key)).status_code == 204
        assert client.get(f"/api/garments/{gid}").status_code == 404
        ids = {g["id"] for g in client.get("/api/merchant/garments",
                                           headers=bearer(key)).json()["garments"]}
        assert ids == {made["clo"]}
        assert client.get(job["result_url"]).content == old


def test_a_garment_that_cannot_dress_is_told_per_size(shop, procs):
    """A garment whose seam cannot close on the body: its check fails with the seam named."""
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    env, config = shop
    start_worker(procs, env)
    g = skirt_json(name="Too narrow")
    for p in g["panels"]:    # three quarters of the width: the skirt cannot close round the hips
        for shape in p.get("shapes", {}).values():
            for seg in shape["outline"]:
                for k in ("start", "end"):
                    if k in seg:
                        seg[k] = [seg[k][0] * 0.75, seg[k][1]]
                if "controls" in seg:
                    seg["controls"] = [[c[0] * 0.75, c[1]] for c in seg["controls"]]
            if shape.get("grain"):
                shape["grain"] = [[c[0] * 0.75, c[1]] for c in shape["grain"]]
            if shape.get("notches"):
                shape["notches"] = [[c[0] * 0.75, c[1]] for c in shape["notches"]]
    g["sizes"], g["default_size"] = ["M"], "M"
    for p in g["panels"]:
        if "shapes" in p:
            p["shapes"] = {"M": p["shapes"]["M"]}
    g["fit"] = {"M": "female-M"}
    with TestClient(create_app(config)) as client:
        key = merchants.create(config, "narrow-shop")
        r = upload_json(client, key, g, textures(g))
        assert r.status_code == 201, r.text
        v = wait_dressing(client, key, r.json()["id"], 1)
        rep = v["dressing"]["M"]
        assert rep["status"] == "failed" and rep["ok"] is False, rep
        assert rep.get("open_seams") and rep["message"].startswith("failed: seams still"), rep
        # (measured: the centre back 17.6 cm open with the body 1.1 cm between its sides and
        # the cloth at τ; four darts at τ)
        assert all("too small" in s["reason"] for s in rep["open_seams"]), rep["open_seams"]


def test_a_check_whose_worker_died_runs_again_then_fails(shop):
    """The dressing check as a job: claimed once at a time; a stale heartbeat sends it back to
    the queue; after three attempts the sizes not checked are failed with the reason."""
    from datetime import timedelta

    from sqlalchemy import update

    from catwalk.service import merchant_garments as mg
    from catwalk.service import merchants
    from catwalk.service.store import db
    from catwalk.service.store.models import (
        GarmentVersionRow,
        MerchantGarmentRow,
        utcnow,
    )

    _, config = shop
    db.migrate(config)
    mid = merchants.authenticate(config, merchants.create(config, "crashy-shop")).id
    with db.session(config) as s:
        s.add(MerchantGarmentRow(id="crashy-skirt-0001", merchant_id=mid, name="x",
                                 type="skirt", version=1, created_at=utcnow(),
                                 updated_at=utcnow()))
        s.flush()
        s.add(GarmentVersionRow(garment_id="crashy-skirt-0001", version=1, content="c" * 32,
                                created_at=utcnow(), sizes=["S", "M"], warnings=[],
                                dressing={"S": {"status": "dressed", "ok": True},
                                          "M": {"status": "queued"}},
                                check_status="queued", check_attempts=0))

    def stale():
        with db.session(config) as s:
            s.execute(update(GarmentVersionRow)
                      .where(GarmentVersionRow.garment_id == "crashy-skirt-0001")
                      .values(check_beat_at=utcnow() - timedelta(seconds=60)))

    sent = []
    for attempt in (1, 2, 3):
        row = mg.claim_check(config, "crashy-skirt-0001", 1)
        assert row is not None and row.check_attempts == attempt
        assert mg.claim_check(config, "crashy-skirt-0001", 1) is None   # one at a time
        assert mg.recover_checks(config, lambda g, v: sent.append((g, v))) == []   # beating
        stale()
        again = mg.recover_checks(config, lambda g, v: sent.append((g, v)))
        assert again == ([("crashy-skirt-0001", 1)] if attempt < 3 else [])
    assert sent == [("crashy-skirt-0001", 1)] * 2
    with db.session(config) as s:
        v = s.get(GarmentVersionRow, ("crashy-skirt-0001", 1))
        assert v.check_status == "done"
        assert v.dressing["S"] == {"status": "dressed", "ok": True}     # kept
        assert v.dressing["M"]["status"] == "failed"
        assert "stopped 3 times" in v.dressing["M"]["message"]


def test_two_changes_at_once_one_wins_the_other_is_a_409(shop):
    """Version n + 1 is made once: a second change that finds it made (its folder or its row)
    is answered 409 and leaves nothing behind."""
    from catwalk.service import merchants
    from catwalk.service.api.app import create_app

    _, config = shop
    with TestClient(create_app(config, recovery=False)) as client:
        key = merchants.create(config, "racing-shop")
        skirt = skirt_json(name="Raced skirt")
        gid = upload_json(client, key, skirt, textures(skirt)).json()["id"]
        # another request is making version 2 right now: its folder is there
        racing = config.storage_dir / "garments" / gid / "2"
        racing.mkdir(parents=True)
        (racing / "garment.json").write_text("{}")
        r = upload_json(client, key, skirt, method="PUT", gid=gid)
        assert r.status_code == 409, r.text
        assert r.json()["error"]["code"] == "conflict" and "send it again" in r.text
        item = client.get(f"/api/merchant/garments/{gid}", headers=bearer(key)).json()
        assert item["version"] == 1 and [v["version"] for v in item["versions"]] == [1]
        hidden = [p for p in (config.storage_dir / "garments").iterdir()
                  if p.name.startswith(".")]
        assert hidden == []   # the checked upload's folder removed
