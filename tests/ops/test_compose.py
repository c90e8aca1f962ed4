"""docker/compose.yaml and docker/Dockerfile, checked without Docker (this machine has only
the client): every command is one ``catwalk`` parses, every ``CATWALK_*`` variable is one the
settings read, the API and the workers share one storage volume, one database and one broker,
and the Dockerfile's stages exist and copy files the repository has (and its .dockerignore
does not leave out)."""

from __future__ import annotations

from pathlib import PurePosixPath
from urllib.parse import urlsplit

import pytest

from catwalk.cli.main import build_parser
from catwalk.config import Config

from .helpers import (
    DOCKER,
    REPO,
    command,
    dockerfile,
    environment,
    ignore_rules,
    ignored,
    interpolate,
    load_yaml,
)

COMPOSE = DOCKER / "compose.yaml"
DOCKERFILE = DOCKER / "Dockerfile"
IGNORE = DOCKER / "Dockerfile.dockerignore"


def setting_names() -> set[str]:
    """The environment variables the settings read (their names and aliases)."""
    names = set()
    for name, f in Config.model_fields.items():
        alias = f.validation_alias
        if alias is None:
            names.add(f"CATWALK_{name.upper()}")
        elif isinstance(alias, str):
            names.add(alias)
        else:
            names.update(a for a in alias.choices if isinstance(a, str))
    return names


@pytest.fixture(scope="module")
def compose() -> dict:
    return load_yaml(COMPOSE)


@pytest.fixture(scope="module")
def stages():
    return dockerfile(DOCKERFILE)


@pytest.fixture(scope="module")
def image_env(stages) -> dict[str, str]:
    return stages[-1].env()


def effective_env(service: dict, image_env: dict[str, str]) -> dict[str, str]:
    """What a container of the service sees: the image's ENV, then the service's own."""
    return {**image_env, **environment(service)}


# ------------------------------------------------------------------------------ compose

def test_the_services_are_there(compose):
    assert {"api", "worker", "redis", "postgres"} <= set(compose["services"])


def test_api_runs_catwalk_serve_without_local_workers(compose):
    cmd = command(compose["services"]["api"])
    assert cmd[0] == "catwalk", cmd
    args = build_parser().parse_args(cmd[1:])
    assert args.command == "serve"
    assert (args.host, args.port, args.workers) == ("0.0.0.0", 8000, 0)


def test_worker_runs_catwalk_worker_one_job_at_a_time(compose):
    cmd = command(compose["services"]["worker"])
    assert cmd[0] == "catwalk", cmd
    args = build_parser().parse_args(cmd[1:])
    assert args.command == "worker"
    assert args.concurrency == 1


def test_worker_can_be_scaled(compose):
    """``docker compose up --scale worker=N``: nothing in the worker may be one of a kind."""
    worker = compose["services"]["worker"]
    assert "container_name" not in worker
    assert not worker.get("ports"), "published ports would clash between workers"
    assert worker.get("deploy", {}).get("replicas") in (None, 1)


def test_every_catwalk_variable_is_a_setting(compose, image_env):
    known = setting_names()
    for name, service in compose["services"].items():
        for var in environment(service):
            if var.startswith("CATWALK_"):
                assert var in known, f"{name}: {var} is not read by catwalk.config.Config"
    for var in image_env:
        if var.startswith("CATWALK_"):
            assert var in known, f"Dockerfile: {var} is not read by catwalk.config.Config"


def test_the_settings_read_the_services_environment(compose, image_env, monkeypatch):
    """The API's and the workers' environment, given to Config: PostgreSQL and Redis."""
    for name in ("api", "worker"):
        env = effective_env(compose["services"][name], image_env)
        for var in setting_names():
            monkeypatch.delenv(var, raising=False)
        for k, v in env.items():
            monkeypatch.setenv(k, v)
        config = Config()
        assert not config.embedded
        assert config.database_url.startswith("postgresql+psycopg://"), config.database_url
        assert config.broker_url == "redis://redis:6379/0"
        assert str(config.storage_dir) == env["CATWALK_STORAGE_DIR"]


def test_api_and_worker_share_database_broker_and_storage(compose, image_env):
    api, worker = compose["services"]["api"], compose["services"]["worker"]
    a, w = effective_env(api, image_env), effective_env(worker, image_env)
    for var in ("CATWALK_DATABASE_URL", "CATWALK_BROKER_URL", "CATWALK_STORAGE_DIR",
                "CATWALK_QUEUE", "CATWALK_CATALOGUE_DIR"):
        assert a.get(var) == w.get(var), var
    assert a["CATWALK_DATABASE_URL"] and a["CATWALK_BROKER_URL"]
    # the one storage volume: a named volume, mounted where the settings put the storage
    named = set(compose.get("volumes") or {})
    mounts = {}
    for name, service in (("api", api), ("worker", worker)):
        got = []
        for v in service.get("volumes") or []:
            source, _, target = str(v).partition(":")
            target = target.split(":")[0]
            if source in named and target == effective_env(service, image_env)[
                    "CATWALK_STORAGE_DIR"]:
                got.append(source)
        assert len(got) == 1, f"{name}: no named volume at CATWALK_STORAGE_DIR"
        mounts[name] = got[0]
    assert mounts["api"] == mounts["worker"]


def test_urls_name_the_services(compose, image_env):
    services = compose["services"]
    env = effective_env(services["api"], image_env)
    db = urlsplit(env["CATWALK_DATABASE_URL"])
    assert db.hostname in services and "postgres" in services[db.hostname]["image"]
    pg = environment(services["postgres"])
    assert db.username == pg["POSTGRES_USER"]
    assert db.password == pg["POSTGRES_PASSWORD"]
    assert db.path.lstrip("/") == pg.get("POSTGRES_DB", pg["POSTGRES_USER"])
    broker = urlsplit(env["CATWALK_BROKER_URL"])
    assert broker.scheme == "redis"
    assert broker.hostname in services and "redis" in services[broker.hostname]["image"]


def test_postgres_has_a_healthcheck_the_service_waits_for(compose):
    services = compose["services"]
    check = services["postgres"].get("healthcheck", {}).get("test")
    assert check and "pg_isready" in " ".join(check if isinstance(check, list) else [check])
    for name in ("api", "worker"):
        deps = services[name].get("depends_on") or {}
        assert isinstance(deps, dict), f"{name}: depends_on without conditions"
        assert deps.get("postgres", {}).get("condition") == "service_healthy", name
        assert "redis" in deps, name


def test_api_and_worker_are_built_from_the_dockerfile(compose):
    for name in ("api", "worker"):
        build = compose["services"][name]["build"]
        context = (COMPOSE.parent / build["context"]).resolve()
        assert context == REPO, f"{name}: the build context is not the repository's root"
        assert (context / build["dockerfile"]).resolve() == DOCKERFILE
    assert compose["services"]["api"]["image"] == compose["services"]["worker"]["image"]


def test_interpolation_defaults():
    assert interpolate("a${X:-b}c") == "abc"
    assert interpolate("a${X:-b}c", {"X": "y"}) == "ayc"
    assert interpolate("${X}") == ""


# ------------------------------------------------------------------------------ Dockerfile

def test_the_stages(stages):
    assert len(stages) == 2
    node, runtime = stages
    assert node.image.startswith("node:20") and node.name
    assert runtime.image.startswith("python:3.11-slim")
    assert "bookworm" in runtime.image, "Debian bookworm, as named in the image's tag"
    runs = [" ".join(i.args) for i in node.all("RUN")]
    workdirs = [i.args[0] for i in node.all("WORKDIR")]
    assert any(w.endswith("/frontend") for w in workdirs)
    assert any(w.endswith("/tools/node") for w in workdirs)
    assert sum("npm ci" in r for r in runs) == 2, runs
    assert any("npm run build" in r for r in runs), runs


def test_every_copy_source_is_in_the_repository_and_the_context(stages):
    rules = ignore_rules(IGNORE)
    names = {s.name for s in stages if s.name}
    copies = 0
    for stage in stages:
        for ins in stage.all("COPY") + stage.all("ADD"):
            assert ins.keyword == "COPY", f"ADD fetches or unpacks: use COPY ({ins.raw})"
            *sources, dest = ins.args
            assert sources and dest, ins.raw
            if "from" in ins.flags:
                assert ins.flags["from"] in names, f"no stage {ins.flags['from']!r}: {ins.raw}"
                continue
            for src in sources:
                path = REPO / src
                assert path.exists(), f"COPY {src}: not in the repository"
                assert not ignored(src, rules), f"COPY {src}: left out by {IGNORE.name}"
                copies += 1
    assert copies >= 6


def test_copies_from_the_node_stage_are_what_it_made(stages):
    """What the runtime copies from the node stage lies in a folder that stage worked in,
    and that folder mirrors one of the repository's (/src/frontend ← frontend/)."""
    node, runtime = stages
    src_root = PurePosixPath("/src")
    workdirs = [PurePosixPath(i.args[0]) for i in node.all("WORKDIR")]
    for w in workdirs:
        assert src_root in w.parents and (REPO / w.relative_to(src_root)).is_dir(), w
    copied = 0
    for ins in runtime.all("COPY"):
        if ins.flags.get("from") != node.name:
            continue
        src = PurePosixPath(ins.args[0])
        if str(src) == "/usr/local/bin/node":   # the image's own binary
            continue
        assert any(src == w or w in src.parents for w in workdirs), \
            f"{ins.raw}: not made in the {node.name} stage"
        copied += 1
    assert copied == 2   # the built pages, the Node tools


def test_the_context_leaves_out_what_the_image_does_not_need():
    rules = ignore_rules(IGNORE)
    for rel in (".git", ".venv", "frontend/node_modules", "tools/node/node_modules",
                "garments/freesewing/node_modules", "frontend/dist", "bodies/generated",
                "backend/catwalk/__pycache__", "tests"):
        assert ignored(rel, rules), rel
    for rel in ("backend/catwalk/config.py", "garments/pencil-skirt.json",
                "garments/textures/denim-twill.png", "frontend/src/main.js",
                "tools/node/package-lock.json", "pyproject.toml"):
        assert not ignored(rel, rules), rel


def test_the_image_sets_the_paths_to_what_it_copies(stages, image_env):
    node, runtime = stages
    dests = {}
    for ins in runtime.all("COPY"):
        src, dest = ins.args[0].rstrip("/"), ins.args[-1].rstrip("/")
        dests[src] = dest
    assert image_env["CATWALK_CATALOGUE_DIR"] == dests["garments"]
    assert image_env["CATWALK_BODIES_DIR"] == dests["bodies"]
    assert image_env["CATWALK_NODE_TOOLS_DIR"] == dests["/src/tools/node"]
    assert image_env["CATWALK_FRONTEND_DIR"] == dests["/src/frontend/dist"]
    assert (REPO / "bodies" / "recipes.json").is_file()
    assert (REPO / "garments" / "pencil-skirt.json").is_file()
    for var in ("CATWALK_DATA_DIR", "CATWALK_STORAGE_DIR"):
        assert image_env[var].startswith("/"), var


def test_the_image_installs_the_package_fetches_the_assets_and_runs_as_a_user(stages,
                                                                               image_env):
    runtime = stages[-1]
    runs = [" ".join(i.args) for i in runtime.all("RUN")]
    assert any("pip install" in r and "catwalk-src" in r for r in runs), runs
    assets_at = next(n for n, i in enumerate(runtime.instructions)
                     if i.keyword == "RUN" and "catwalk assets" in " ".join(i.args))
    env_at = next(n for n, i in enumerate(runtime.instructions)
                  if i.keyword == "ENV" and any(a.startswith("CATWALK_DATA_DIR=")
                                               for a in i.args))
    assert env_at < assets_at, "the assets are fetched into CATWALK_DATA_DIR, set before"
    assert any(i.flags.get("from") == stages[0].name and i.args[0] == "/usr/local/bin/node"
               for i in runtime.all("COPY")), "node 20 for gltfpack and the validator"
    users = runtime.all("USER")
    assert users and users[-1].args[0] not in ("root", "0"), "runs as a user, not root"
    cmd = runtime.all("CMD")[-1].args
    assert cmd[0] == "catwalk"
    assert build_parser().parse_args(cmd[1:]).command == "serve"


def test_the_compose_storage_path_is_the_images(compose, image_env):
    for name in ("api", "worker"):
        env = environment(compose["services"][name])
        assert env.get("CATWALK_STORAGE_DIR", image_env["CATWALK_STORAGE_DIR"]) == \
            image_env["CATWALK_STORAGE_DIR"], name
