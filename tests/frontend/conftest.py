"""Fixtures for the pages' end-to-end tests: the built frontend, a real ``catwalk serve`` with
a one-garment catalogue serving it, and headless Chromium (Debian's, through Playwright)."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

# tests/ is on sys.path (pytest inserts the first folder above a package: tests/service, this)
from service.helpers import REPO, Proc, free_port, service_env
from service.helpers import one_garment_catalogue as catalogue_of_one

FRONTEND = REPO / "frontend"
CHROMIUM = os.environ.get("CATWALK_TEST_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]
DESKTOP = {"width": 1440, "height": 900}
PHONE = {"width": 390, "height": 844}


def _run(cmd: list[str]) -> None:
    r = subprocess.run(cmd, cwd=FRONTEND, capture_output=True, text=True)
    if r.returncode != 0:
        pytest.fail(f"`{' '.join(cmd)}` in frontend/ failed ({r.returncode}):\n"
                    f"{(r.stdout + r.stderr)[-3000:]}", pytrace=False)


@pytest.fixture(scope="session")
def frontend_dist() -> Path:
    """frontend/dist, built (npm ci, npm run build) when it is missing, or older than a source
    file of the pages, or without the shops' component (dist/embed)."""
    dist = FRONTEND / "dist"
    index = dist / "index.html"
    sources = [p for d in ("src", "public") for p in (FRONTEND / d).rglob("*") if p.is_file()]
    sources.append(FRONTEND / "index.html")
    stale = index.is_file() and max(p.stat().st_mtime for p in sources if p.exists()) > \
        index.stat().st_mtime
    if not index.is_file() or stale or not (dist / "embed" / "v1" / "catwalk.js").is_file():
        if shutil.which("npm") is None:
            pytest.fail("frontend/dist is not built and npm is not installed", pytrace=False)
        if not (FRONTEND / "node_modules" / ".package-lock.json").is_file():
            _run(["npm", "ci", "--no-audit", "--no-fund", "--loglevel=error"])
        _run(["npm", "run", "build"])
    return dist


@pytest.fixture(scope="session")
def one_garment_catalogue(tmp_path_factory) -> Path:
    """The pencil skirt and its textures (as tests/service's ``catalogue_dir``)."""
    return catalogue_of_one(tmp_path_factory.mktemp("catalogue"))


@pytest.fixture(scope="module")
def site(tmp_path_factory, one_garment_catalogue, frontend_dist) -> str:
    """``catwalk serve`` (one local worker) serving the built pages; its base URL."""
    tmp = tmp_path_factory.mktemp("site")
    env = service_env(tmp / "storage", one_garment_catalogue, frontend_dir=frontend_dist)
    port = free_port()
    proc = Proc(["serve", f"--port={port}", "--workers=1"], env, tmp / "serve.log")
    try:
        proc.wait_for('"api_ready"', timeout=180)
        yield f"http://127.0.0.1:{port}"
    finally:
        proc.stop()


@pytest.fixture(scope="session")
def browser():
    if not Path(CHROMIUM).is_file():
        pytest.fail(f"no Chromium at {CHROMIUM} (Debian: apt-get install chromium; or set "
                    "CATWALK_TEST_CHROMIUM)", pytrace=False)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        yield b
        b.close()


class ConsoleLog:
    """Every console message and uncaught error of a page."""

    def __init__(self, page):
        self.messages: list[tuple[str, str]] = []
        page.on("console", lambda m: self.messages.append((m.type, m.text)))
        page.on("pageerror", lambda e: self.messages.append(("pageerror", str(e))))

    @property
    def errors(self) -> list[str]:
        return [f"{kind}: {text}" for kind, text in self.messages
                if kind in ("error", "pageerror")]


@pytest.fixture
def page_factory(browser):
    """``page_factory(viewport) -> (page, console)``; every page is closed at the end."""
    contexts = []

    def make(viewport=DESKTOP):
        ctx = browser.new_context(viewport=viewport, device_scale_factor=1,
                                  has_touch=viewport["width"] < 600)
        contexts.append(ctx)
        page = ctx.new_page()
        page.set_default_timeout(60_000)
        return page, ConsoleLog(page)

    yield make
    for c in contexts:
        c.close()
