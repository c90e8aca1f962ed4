"""Shops' pages calling the API (docs/embed.md), in-process against the embedded default: a
merchant's publishable key (``catwalk merchant publishable-key``) opens only the shoppers'
routes, only from the origins the merchant allows (``catwalk merchant origins``, ``PUT
/api/merchant/origins``), with CORS answered for exactly those; a body made on one shop is
its shopper's there and reachable from nowhere else; a try-on is of the merchant's published
garments only; a secret key sent from a page is refused; the rate limits per key and per
shopper; the component's files are served to any page."""

from __future__ import annotations

import subprocess
import sys

import pytest
from fastapi.testclient import TestClient

from .helpers import (
    MEASURES,
    REPO,
    bearer,
    make_config,
    service_env,
    skirt_json,
    textures,
    upload_json,
)

SHOP_A, SHOP_B, ELSEWHERE = "https://shop-a.example", "http://127.0.0.1:8123", "https://evil.example"
ANNA, BEN = "anna-0123456789abcdef", "ben-0123456789abcdef0"


def _app(storage, catalogue, frontend=None, **settings):
    from catwalk.service.api.app import create_app

    config = make_config(service_env(storage, catalogue, **settings))
    return config, create_app(config, recovery=False, frontend=frontend)


def _shop(config, name: str, origin: str) -> dict:
    from catwalk.service import merchants

    key = merchants.create(config, name)
    merchants.origins(config, name, replace=[origin])
    return {"key": key, "pk": merchants.publishable_key(config, name), "origin": origin}


def _as(shop: dict, shopper: str | None = None, origin: str | None = None) -> dict:
    """The headers a shop's page sends (its origin, the shopper's id)."""
    h = {"Origin": origin or shop["origin"]}
    if shopper:
        h["X-Catwalk-Shopper"] = shopper
    return h


def _publish(client, shop: dict, name: str) -> str:
    g = skirt_json(name=name)
    r = upload_json(client, shop["key"], g, textures(g))
    assert r.status_code == 201, r.text
    gid = r.json()["id"]
    assert client.post(f"/api/merchant/garments/{gid}/publish",
                       headers=bearer(shop["key"])).status_code == 200
    return gid


@pytest.fixture(scope="module")
def world(tmp_path_factory, catalogue_dir):
    """The API, two merchants with a published garment each (and one draft)."""
    config, app = _app(tmp_path_factory.mktemp("embed") / "storage", catalogue_dir)
    with TestClient(app, raise_server_exceptions=False) as c:
        a, b = _shop(config, "shop-a", SHOP_A), _shop(config, "shop-b", SHOP_B)
        a["garment"] = _publish(c, a, "Skirt of shop A")
        b["garment"] = _publish(c, b, "Skirt of shop B")
        g = skirt_json(name="A's draft")
        a["draft"] = upload_json(c, a["key"], g, textures(g)).json()["id"]
        yield c, a, b, config


def _body(c, shop, shopper) -> dict:
    r = c.post(f"/api/bodies?key={shop['pk']}", json=MEASURES, headers=_as(shop, shopper))
    assert r.status_code == 201, r.text
    assert r.headers["access-control-allow-origin"] == shop["origin"]
    assert "Origin" in r.headers["vary"]
    return r.json()


def _refusal(r, status: int, code: str) -> str:
    assert r.status_code == status, (r.status_code, r.text[:300])
    assert r.json()["error"]["code"] == code, r.text
    return r.json()["error"]["message"]


def test_preflight_is_answered_for_the_merchants_origins_only(world):
    c, a, _, _ = world
    ask = {"Access-Control-Request-Method": "POST",
           "Access-Control-Request-Headers": "content-type,x-catwalk-shopper"}
    r = c.options(f"/api/bodies?key={a['pk']}", headers={"Origin": SHOP_A, **ask})
    assert r.status_code == 204
    assert r.headers["access-control-allow-origin"] == SHOP_A          # exactly, never *
    assert "x-catwalk-shopper" in r.headers["access-control-allow-headers"].lower()
    assert "POST" in r.headers["access-control-allow-methods"]
    assert "access-control-allow-credentials" not in r.headers
    r = c.options(f"/api/bodies?key={a['pk']}", headers={"Origin": ELSEWHERE, **ask})
    assert r.status_code == 403 and r.json()["error"]["code"] == "origin_not_allowed"
    assert "access-control-allow-origin" not in r.headers
    # another shop's allowed origin is not this shop's
    r = c.options(f"/api/bodies?key={a['pk']}", headers={"Origin": SHOP_B, **ask})
    assert r.status_code == 403
    # a merchant's route is never opened to a page
    r = c.options(f"/api/merchant/me?key={a['pk']}",
                  headers={"Origin": SHOP_A, "Access-Control-Request-Method": "GET"})
    assert r.status_code == 403 and "access-control-allow-methods" not in r.headers


def test_a_body_made_on_a_shop_is_its_shoppers_there_only(world):
    c, a, b, _ = world
    body = _body(c, a, ANNA)
    url = f"/api/bodies/{body['id']}"
    assert c.get(f"{url}?key={a['pk']}", headers=_as(a, ANNA)).json()["id"] == body["id"]
    assert c.get(f"{url}/body.glb?key={a['pk']}", headers=_as(a, ANNA)).status_code == 200
    # another shopper on the same shop, another shop, catwalk's own pages: an unknown body
    for r in (c.get(f"{url}?key={a['pk']}", headers=_as(a, BEN)),
              c.get(f"{url}?key={b['pk']}", headers=_as(b, ANNA)),
              c.get(f"{url}/body.glb?key={b['pk']}", headers=_as(b, ANNA)),
              c.get(url), c.get(f"{url}/body.glb"), c.delete(url),
              c.delete(f"{url}?key={a['pk']}", headers=_as(a, BEN))):
        assert _refusal(r, 404, "not_found") == f"no body with id {body['id']!r}"
    # the page of an origin the merchant does not allow is told why (and nothing else)
    r = c.get(f"{url}?key={a['pk']}", headers=_as(a, ANNA, origin=ELSEWHERE))
    message = _refusal(r, 403, "origin_not_allowed")
    assert ELSEWHERE in message and "catwalk merchant origins" in message
    assert r.headers["access-control-allow-origin"] == ELSEWHERE
    assert "measurements" not in r.text
    # no shopper named, or a malformed one
    r = c.get(f"{url}?key={a['pk']}", headers=_as(a))
    assert "X-Catwalk-Shopper" in _refusal(r, 422, "invalid")
    assert _refusal(c.get(f"{url}?key={a['pk']}", headers=_as(a, "x")), 422, "invalid")
    # a body of catwalk's own pages is not reached from a shop
    own = c.post("/api/bodies", json=MEASURES).json()
    _refusal(c.get(f"/api/bodies/{own['id']}?key={a['pk']}", headers=_as(a, ANNA)), 404,
             "not_found")
    # the shopper deletes it
    assert c.delete(f"{url}?key={a['pk']}", headers=_as(a, ANNA)).status_code == 204
    _refusal(c.get(f"{url}?key={a['pk']}", headers=_as(a, ANNA)), 404, "not_found")


def test_try_ons_of_the_merchants_published_garments_only(world):
    c, a, b, _ = world
    body = _body(c, a, ANNA)
    ask = {"body_id": body["id"], "garment_id": a["garment"], "preset": "fast", "seconds": 1.0}
    r = c.post(f"/api/tryons?key={a['pk']}", json=ask, headers=_as(a, ANNA))
    assert r.status_code == 202, r.text
    assert r.headers["access-control-allow-origin"] == SHOP_A
    job = r.json()["id"]
    got = c.get(f"/api/tryons/{job}?key={a['pk']}", headers=_as(a))
    assert got.status_code == 200 and got.json()["garment_id"] == a["garment"]
    # reached through shop A only
    for r in (c.get(f"/api/tryons/{job}"), c.get(f"/api/tryons/{job}/events"),
              c.get(f"/api/tryons/{job}?key={b['pk']}", headers=_as(b)),
              c.get(f"/api/tryons/{job}/result.glb?key={b['pk']}", headers=_as(b))):
        _refusal(r, 404, "not_found")
    # the catalogue's own garment, shop B's, shop A's draft: not this shop's
    for garment in ("pencil-skirt", b["garment"], a["draft"]):
        r = c.post(f"/api/tryons?key={a['pk']}", json={**ask, "garment_id": garment},
                   headers=_as(a, ANNA))
        assert _refusal(r, 404, "not_found") == f"no garment with id {garment!r}"
        _refusal(c.get(f"/api/garments/{garment}?key={a['pk']}", headers=_as(a)), 404,
                 "not_found")
    assert c.get(f"/api/garments/{a['garment']}?key={a['pk']}",
                 headers=_as(a)).json()["name"] == "Skirt of shop A"
    # another shopper's body
    r = c.post(f"/api/tryons?key={a['pk']}", json=ask, headers=_as(a, BEN))
    assert _refusal(r, 404, "not_found") == f"no body with id {body['id']!r}"
    # size advice for the shopper's own body
    r = c.get(f"/api/garments/{a['garment']}/sizes?body_id={body['id']}&key={a['pk']}",
              headers=_as(a, ANNA))
    assert r.status_code == 200 and r.json()["recommended"] in ("S", "M", "L")
    r = c.get(f"/api/garments/{a['garment']}/sizes?body_id={body['id']}&key={a['pk']}",
              headers=_as(a, BEN))
    _refusal(r, 404, "not_found")


def test_a_publishable_key_never_reaches_the_merchants_routes(world):
    c, a, _, _ = world
    r = c.get("/api/merchant/me", headers=bearer(a["pk"]))
    assert "publishable key" in _refusal(r, 401, "unauthorized")
    r = c.get(f"/api/merchant/me?key={a['pk']}", headers=_as(a))
    assert "only the shoppers' routes" in _refusal(r, 403, "key_not_allowed")
    for path in ("/api/garments", "/openapi.json", "/metrics", "/api/merchant/garments"):
        _refusal(c.get(f"{path}?key={a['pk']}", headers=_as(a)), 403, "key_not_allowed")
    r = c.get("/api/garments?key=pk_not-a-key-at-all", headers=_as(a))
    _refusal(r, 401, "unauthorized")
    assert r.headers["access-control-allow-origin"] == SHOP_A          # the page may read why


def test_a_secret_key_from_a_page_is_refused(world):
    c, a, _, _ = world
    r = c.get(f"/api/garments/{a['garment']}?key={a['key']}", headers=_as(a))
    message = _refusal(r, 403, "secret_key_exposed")
    assert "never be in a web page" in message and "publishable key" in message
    assert r.headers["access-control-allow-origin"] == SHOP_A
    page = {"Origin": SHOP_A, "Sec-Fetch-Site": "cross-site", **bearer(a["key"])}
    _refusal(c.get("/api/merchant/me", headers=page), 403, "secret_key_exposed")
    # without Sec-Fetch-Site (an older browser): the Origin against the service's host
    _refusal(c.get("/api/merchant/me", headers={"Origin": SHOP_A, **bearer(a["key"])}), 403,
             "secret_key_exposed")
    # the merchant's editor, on the service's own origin, and a script (no Origin): as before
    own = {"Origin": "http://testserver", "Sec-Fetch-Site": "same-origin", **bearer(a["key"])}
    assert c.get("/api/merchant/me", headers=own).status_code == 200
    assert c.get("/api/merchant/me", headers={"Origin": "http://testserver",
                                              **bearer(a["key"])}).status_code == 200
    me = c.get("/api/merchant/me", headers=bearer(a["key"])).json()
    assert me["publishable_key"] == a["pk"] and me["origins"] == [SHOP_A]


def test_origins_over_the_api(world):
    c, a, _, _ = world
    r = c.put("/api/merchant/origins", headers=bearer(a["key"]),
              json={"origins": [SHOP_A, "HTTPS://Shop-A.example:443/", "http://[::1]:8080"]})
    assert r.status_code == 200, r.text
    assert r.json()["origins"] == [SHOP_A, "http://[::1]:8080"]
    for bad, why in (("https://shop.example/products", "no path"), ("*", "never allowed"),
                     ("ftp://shop.example", "https://"), ("shop.example", "https://")):
        r = c.put("/api/merchant/origins", headers=bearer(a["key"]), json={"origins": [bad]})
        assert why in _refusal(r, 422, "invalid"), bad
        assert r.json()["error"]["field"] == "origins"
    _refusal(c.put("/api/merchant/origins", headers=bearer(a["key"]), json=[SHOP_A]), 422,
             "invalid")
    r = c.put("/api/merchant/origins", headers=bearer(a["key"]), json={"origins": [SHOP_A]})
    assert r.json()["origins"] == [SHOP_A]


def test_rate_limits_per_shopper_and_per_key(tmp_path, catalogue_dir):
    config, app = _app(tmp_path / "storage", catalogue_dir, rate_shopper_per_minute=4,
                       rate_shopper_jobs_per_hour=2, rate_key_per_minute=9)
    with TestClient(app) as c:
        a = _shop(config, "limited", SHOP_A)
        body = _body(c, a, ANNA)                                       # 1 made, 1 request
        _body(c, a, ANNA)                                              # 2 made
        r = c.post(f"/api/bodies?key={a['pk']}", json=MEASURES, headers=_as(a, ANNA))
        assert "2 bodies and try-ons an hour" in _refusal(r, 429, "rate_limited")
        assert 1 <= int(r.headers["retry-after"]) <= 3600
        assert r.headers["access-control-allow-origin"] == SHOP_A
        r = c.get(f"/api/bodies/{body['id']}?key={a['pk']}", headers=_as(a, ANNA))
        assert r.status_code == 200                                    # 4 requests
        r = c.get(f"/api/bodies/{body['id']}?key={a['pk']}", headers=_as(a, ANNA))
        assert "4 requests a minute" in _refusal(r, 429, "rate_limited")
        assert 1 <= int(r.headers["retry-after"]) <= 60
        # another shopper still may, until the shop's key reaches its own limit
        assert [_body(c, a, BEN)["id"] for _ in range(2)]
        codes = [c.get(f"/api/bodies/{body['id']}?key={a['pk']}",
                       headers=_as(a, BEN)).status_code for _ in range(3)]
        assert codes[-1] == 429, codes
        r = c.get(f"/api/bodies/{body['id']}?key={a['pk']}", headers=_as(a, BEN))
        assert "this shop's limit of 9 requests a minute" in r.json()["error"]["message"]


def test_rate_limits_are_shared_through_redis(redis_url):
    """With a Redis broker, two API processes count together (here two limiters)."""
    import asyncio
    import uuid
    from concurrent.futures import ThreadPoolExecutor

    from catwalk.config import Config
    from catwalk.service.ratelimit import RateLimits

    name = f"test-{uuid.uuid4().hex}"
    one, two = (RateLimits(Config(broker_url=redis_url)) for _ in range(2))

    async def hits():
        return [await lim.hit(name, 3, 60) for lim in (one, two, one, two)]

    # a loop of its own (a Playwright test in the same session may hold this thread's)
    with ThreadPoolExecutor(1) as pool:
        waits = pool.submit(asyncio.run, hits()).result()
    assert waits[:3] == [None, None, None] and 55 < waits[3] <= 60, waits


def test_the_cli_prints_the_publishable_key_and_sets_origins(tmp_path, catalogue_dir):
    env = service_env(tmp_path / "storage", catalogue_dir)

    def cli(*args):
        return subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", *args],
                              env=env, capture_output=True, text=True, timeout=120, cwd=REPO)

    assert cli("create", "atelier").returncode == 0
    out = cli("publishable-key", "atelier")
    assert out.returncode == 0, out.stderr
    pk = out.stdout.strip().splitlines()[-1]
    assert pk.startswith("pk_") and len(pk) > 30
    assert cli("publishable-key", "atelier").stdout.strip().splitlines()[-1] == pk
    out = cli("origins", "atelier", "https://Shop.example/", "http://127.0.0.1:8080")
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-2:] == ["https://shop.example",
                                                    "http://127.0.0.1:8080"]
    out = cli("origins", "atelier", "https://shop.example/cart")
    assert out.returncode == 2 and "no path" in out.stderr
    assert cli("origins", "nobody").returncode == 2
    out = cli("origins", "atelier", "--remove", "https://shop.example", "--json")
    assert out.stdout.strip() == '["http://127.0.0.1:8080"]'
    new = cli("publishable-key", "atelier", "--new").stdout.strip().splitlines()[-1]
    assert new.startswith("pk_") and new != pk


def test_the_component_is_served_to_any_page(tmp_path, catalogue_dir):
    dist = tmp_path / "dist"
    (dist / "embed" / "v1" / "chunks").mkdir(parents=True)
    (dist / "index.html").write_text("<!doctype html><title>catwalk</title>")
    (dist / "embed" / "v1" / "catwalk.js").write_text("export {};\n")
    (dist / "embed" / "v1" / "chunks" / "player-abc123.js").write_text("export {};\n")
    _, app = _app(tmp_path / "storage", catalogue_dir, frontend=dist)
    with TestClient(app) as c:
        r = c.get("/embed/v1/catwalk.js", headers={"Origin": ELSEWHERE})
        assert r.status_code == 200 and r.headers["access-control-allow-origin"] == "*"
        assert r.headers["content-type"].startswith("text/javascript")
        assert r.headers["cache-control"] == "public, max-age=300"
        r = c.get("/embed/v1/chunks/player-abc123.js")
        assert "immutable" in r.headers["cache-control"]
        _refusal(c.get("/embed/v1/nothing.js"), 404, "not_found")
        _refusal(c.get("/embed/v1/%2e%2e/%2e%2e/index.html"), 404, "not_found")
