"""docs/garment-format.schema.json agrees with the code and accepts the catalogue.

jsonschema is not a dependency: a small validator for the keywords the schema uses."""

import json
from pathlib import Path

import pytest

from catwalk.catalogue.garments import catalogue_files
from catwalk.garment.model import BODY_PARTS, GARMENT_TYPES, PANEL_TYPES, SIDES

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "docs" / "garment-format.schema.json").read_text())


def _resolve(node):
    while "$ref" in node:
        node = SCHEMA["$defs"][node["$ref"].split("/")[-1]]
    return node


def validate(value, node, path="$"):
    node = _resolve(node)
    errors = []
    types = {"object": dict, "array": list, "string": str, "boolean": bool, "integer": int,
             "number": (int, float)}
    t = node.get("type")
    if t and (not isinstance(value, types[t]) or (t in ("integer", "number")
                                                   and isinstance(value, bool))):
        return [f"{path}: expected {t}"]
    if "const" in node and value != node["const"]:
        errors.append(f"{path}: expected {node['const']!r}")
    if "enum" in node and value not in node["enum"]:
        errors.append(f"{path}: {value!r} not in enum")
    if "oneOf" in node:
        ok = [b for b in node["oneOf"] if not validate(value, b, path)]
        if len(ok) != 1:
            errors.append(f"{path}: matches {len(ok)} of oneOf")
    if isinstance(value, dict):
        for k in node.get("required", []):
            if k not in value:
                errors.append(f"{path}: missing {k}")
        props = node.get("properties", {})
        for k, v in value.items():
            if k in props:
                errors += validate(v, props[k], f"{path}.{k}")
            elif node.get("additionalProperties") is False:
                errors.append(f"{path}: unexpected {k}")
            elif isinstance(node.get("additionalProperties"), dict):
                errors += validate(v, node["additionalProperties"], f"{path}.{k}")
    if isinstance(value, list):
        if len(value) < node.get("minItems", 0):
            errors.append(f"{path}: too few items")
        if "maxItems" in node and len(value) > node["maxItems"]:
            errors.append(f"{path}: too many items")
        if "items" in node:
            for i, v in enumerate(value):
                errors += validate(v, node["items"], f"{path}[{i}]")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if "minimum" in node and value < node["minimum"]:
            errors.append(f"{path}: below minimum")
        if "exclusiveMinimum" in node and value <= node["exclusiveMinimum"]:
            errors.append(f"{path}: not above {node['exclusiveMinimum']}")
    return errors


def test_schema_enums_match_code():
    d = SCHEMA["$defs"]
    assert SCHEMA["properties"]["type"]["enum"] == list(GARMENT_TYPES)
    assert d["panel"]["properties"]["type"]["enum"] == list(PANEL_TYPES)
    assert d["placement"]["properties"]["part"]["enum"] == list(BODY_PARTS)
    assert d["placement"]["properties"]["side"]["enum"] == list(SIDES)


@pytest.mark.parametrize("path", catalogue_files(ROOT / "garments"), ids=lambda p: p.name)
def test_catalogue_files_match_schema(path):
    assert validate(json.loads(path.read_text()), SCHEMA) == []


def test_schema_rejects_bad_files():
    good = json.loads((ROOT / "garments" / "tshirt.json").read_text())
    bad = dict(good, type="cape")
    assert any("not in enum" in e for e in validate(bad, SCHEMA))
    bad = json.loads(json.dumps(good))
    bad["seams"][0]["a"].pop("end")
    assert any("missing end" in e for e in validate(bad, SCHEMA))
