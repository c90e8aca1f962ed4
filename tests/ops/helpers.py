"""Readers for the deployment files: compose.yaml, the Dockerfile and its .dockerignore.

PyYAML is not one of catwalk's dependencies, so :func:`load_yaml` falls back to a reader of
the small block-style subset ``docker/compose.yaml`` is written in (mappings, lists, plain,
quoted and flow-list scalars, comments). Anything outside that subset (anchors, aliases,
multi-line strings, flow mappings with content) is refused, never guessed; where PyYAML is
installed the tests check that both readers agree.
"""

from __future__ import annotations

import json
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOCKER = REPO / "docker"


# ------------------------------------------------------------------------------ YAML

class YamlSubsetError(ValueError):
    pass


def _strip_comment(line: str) -> str:
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch == "#" and (i == 0 or line[i - 1] in " \t"):
            return line[:i].rstrip()
    return line.rstrip()


def _split_flow(text: str) -> list[str]:
    items, cur, quote = [], "", None
    for ch in text:
        if quote:
            cur += ch
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
            cur += ch
        elif ch == ",":
            items.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        items.append(cur.strip())
    return items


def _scalar(text: str):
    text = text.strip()
    if text[:1] in ("&", "*", "|", ">", "!"):
        raise YamlSubsetError(f"not in the YAML subset read without PyYAML: {text!r}")
    if text.startswith('"'):
        if not text.endswith('"') or len(text) < 2:
            raise YamlSubsetError(f"unterminated string: {text!r}")
        return json.loads(text)
    if text.startswith("'"):
        if not text.endswith("'") or len(text) < 2:
            raise YamlSubsetError(f"unterminated string: {text!r}")
        return text[1:-1].replace("''", "'")
    if text.startswith("["):
        if not text.endswith("]"):
            raise YamlSubsetError(f"a flow list on several lines: {text!r}")
        return [_scalar(t) for t in _split_flow(text[1:-1])]
    if text.startswith("{"):
        if text.replace(" ", "") != "{}":
            raise YamlSubsetError(f"a flow mapping: {text!r}")
        return {}
    if text in ("", "~", "null", "Null", "NULL"):
        return None
    if text in ("true", "True", "TRUE"):
        return True
    if text in ("false", "False", "FALSE"):
        return False
    if re.fullmatch(r"[-+]?[0-9]+", text):
        return int(text)
    if re.fullmatch(r"[-+]?([0-9]+\.[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?", text):
        return float(text)
    return text


_KEY = re.compile(r"""^("(?:[^"\\]|\\.)*"|'[^']*'|[^\s#'"][^:]*?)\s*:(?:\s+(.*))?$""")


def _parse_block(lines: list[tuple[int, str]], i: int, indent: int):
    if lines[i][1].startswith("- ") or lines[i][1] == "-":
        out_list = []
        while i < len(lines) and lines[i][0] == indent and (
                lines[i][1].startswith("- ") or lines[i][1] == "-"):
            item = lines[i][1][2:].strip()
            if not item or _KEY.match(item) and not item.startswith(("[", '"', "'")):
                raise YamlSubsetError(f"line {i}: only scalars as list items: {lines[i][1]!r}")
            out_list.append(_scalar(item))
            i += 1
        return out_list, i
    out: dict = {}
    while i < len(lines) and lines[i][0] == indent:
        m = _KEY.match(lines[i][1])
        if not m:
            raise YamlSubsetError(f"not a 'key: value' line: {lines[i][1]!r}")
        key = _scalar(m.group(1))
        if key in out:
            raise YamlSubsetError(f"duplicate key {key!r}")
        rest = (m.group(2) or "").strip()
        i += 1
        if rest:
            out[key] = _scalar(rest)
        elif i < len(lines) and (lines[i][0] > indent or (
                lines[i][0] == indent and lines[i][1].startswith("- "))):
            out[key], i = _parse_block(lines, i, lines[i][0])
        else:
            out[key] = None
    return out, i


def mini_yaml(text: str):
    """Parse the block-style YAML subset described in the module's docstring."""
    lines = []
    for raw in text.splitlines():
        if "\t" in raw[: len(raw) - len(raw.lstrip())]:
            raise YamlSubsetError("tabs in indentation")
        line = _strip_comment(raw)
        if line.strip():
            if line.strip() in ("---", "..."):
                raise YamlSubsetError("several documents")
            lines.append((len(line) - len(line.lstrip(" ")), line.strip()))
    if not lines:
        return None
    value, i = _parse_block(lines, 0, lines[0][0])
    if i != len(lines):
        raise YamlSubsetError(f"unexpected indentation at {lines[i][1]!r}")
    return value


def load_yaml(path: Path):
    try:
        import yaml
    except ModuleNotFoundError:
        return mini_yaml(path.read_text())
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
