"""Readers for the deployment files: compose.yaml (PyYAML), the Dockerfile and its
.dockerignore."""

from __future__ import annotations

import json
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOCKER = REPO / "docker"


def load_yaml(path: Path):
    import yaml  # pyyaml, pinned in the dev dependencies

    return yaml.safe_load(path.read_text())


_INTERP = re.compile(r"\$\{([A-Za-z_][A-Za-z0-9_]*)(?::?-([^}]*))?\}")


def interpolate(value: str, env: dict[str, str] | None = None) -> str:
    """Compose's ``${VAR}`` / ``${VAR:-default}`` with ``env`` (default: none set)."""
    env = env or {}
    return _INTERP.sub(lambda m: env.get(m.group(1)) or (m.group(2) or ""), value)


def environment(service: dict) -> dict[str, str]:
    """A service's ``environment`` (a mapping or a list of ``K=V``), interpolated."""
    env = service.get("environment") or {}
    if isinstance(env, list):
        env = dict(e.split("=", 1) if "=" in e else (e, "") for e in env)
    return {k: interpolate(str(v)) for k, v in env.items()}


def command(service: dict) -> list[str]:
    cmd = service.get("command")
    return shlex.split(cmd) if isinstance(cmd, str) else [str(c) for c in cmd or []]


# ------------------------------------------------------------------------------ Dockerfile

@dataclass
class Instruction:
    keyword: str     # upper case
    flags: dict      # --from=…, --chown=…
    args: list[str]  # the rest, shell-split (JSON form decoded)
    raw: str


@dataclass
class Stage:
    image: str
    name: str | None
    instructions: list[Instruction] = field(default_factory=list)

    def all(self, keyword: str) -> list[Instruction]:
        return [i for i in self.instructions if i.keyword == keyword]

    def env(self) -> dict[str, str]:
        out = {}
        for ins in self.all("ENV"):
            for a in ins.args:
                if "=" not in a:
                    raise AssertionError(f"ENV in the old 'KEY value' form: {ins.raw!r}")
                k, v = a.split("=", 1)
                out[k] = v
        return out


def dockerfile(path: Path) -> list[Stage]:
    """The Dockerfile's stages and their instructions (continuations joined, comments and
    parser directives dropped)."""
    logical, cur = [], ""
    for raw in path.read_text().splitlines():
        s = raw.strip()
        if not cur and (not s or s.startswith("#")):
            continue
        if cur and s.startswith("#"):   # a comment inside a continued instruction
            continue
        if s.endswith("\\"):
            cur += s[:-1] + " "
            continue
        logical.append(cur + s)
        cur = ""
    assert not cur, "the Dockerfile ends inside a continued line"
    stages: list[Stage] = []
    for line in logical:
        keyword, _, rest = line.partition(" ")
        keyword = keyword.upper()
        rest = rest.strip()
        if keyword in ("RUN", "CMD", "ENTRYPOINT") and rest.startswith("["):
            args = json.loads(rest)
            flags = {}
        else:
            words = shlex.split(rest, posix=True) if keyword != "RUN" else rest.split()
            flags = {}
            while words and words[0].startswith("--"):
                k, _, v = words.pop(0)[2:].partition("=")
                flags[k] = v
            args = words
            if keyword in ("COPY", "ADD") and rest.lstrip().endswith("]"):
                json_part = rest[rest.index("["):]
                args = json.loads(json_part)
        ins = Instruction(keyword, flags, args, line)
        if keyword == "FROM":
            name = args[2] if len(args) == 3 and args[1].upper() == "AS" else None
            stages.append(Stage(args[0], name))
        else:
            assert stages, f"{line!r} before the first FROM"
            stages[-1].instructions.append(ins)
    return stages


# ------------------------------------------------------------------------------ .dockerignore

def _pattern(p: str) -> re.Pattern:
    p = p.strip().lstrip("/").rstrip("/")
    out, i = "", 0
    while i < len(p):
        if p.startswith("**/", i):
            out += "(?:.*/)?"
            i += 3
        elif p.startswith("**", i):
            out += ".*"
            i += 2
        elif p[i] == "*":
            out += "[^/]*"
            i += 1
        elif p[i] == "?":
            out += "[^/]"
            i += 1
        else:
            out += re.escape(p[i])
            i += 1
    return re.compile(out + r"\Z")


def ignore_rules(path: Path) -> list[tuple[bool, re.Pattern]]:
    rules = []
    for line in path.read_text().splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        negate = s.startswith("!")
        rules.append((negate, _pattern(s[1:] if negate else s)))
    return rules


def ignored(rel: str, rules) -> bool:
    """Whether the context path ``rel`` is left out (it or a folder above it matches; the
    last matching rule wins, ``!`` keeps)."""
    parts = rel.strip("/").split("/")
    out = False
    for negate, rx in rules:
        for n in range(1, len(parts) + 1):
            if rx.match("/".join(parts[:n])):
                out = not negate
                break
    return out
