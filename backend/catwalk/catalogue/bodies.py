"""The sample bodies: recipes in ``$CATWALK_BODIES_DIR/recipes.json`` (``female-M`` …), each
made once from its measurements and kept as a .glb in ``generated/`` beside the recipes."""

from __future__ import annotations

import json
from pathlib import Path

from catwalk.body.make import make_body
from catwalk.body.rig import SKIN_RECIPE
from catwalk.config import get_config
from catwalk.errors import InputError
from catwalk.exchange.gltf import read_body, write_glb


def recipes_path() -> Path:
    return get_config().bodies_dir / "recipes.json"


def load_recipes(path: Path | None = None) -> list[dict]:
    path = path or recipes_path()
    try:
        data = json.loads(Path(path).read_text())
        return list(data["bodies"])
    except (OSError, ValueError, KeyError) as exc:
        raise InputError(f"{path}: not a readable recipe file ({exc})") from exc


def sample_body(name: str, out_dir: Path | None = None):
    """The sample body ``name`` (a recipe in bodies/recipes.json, e.g. ``female-M``), made once
    and kept in ``bodies/generated/`` (git-ignored) for the next call; made again where the
    kept one's skin weights were made another way (its meta's ``"skin"``)."""
    out = Path(out_dir) if out_dir is not None else recipes_path().parent / "generated"
    path = out / f"{name}.glb"
    if path.is_file():
        kept = read_body(path)
        if kept.meta.get("skin") == SKIN_RECIPE:
            return kept
    recipe = next((r for r in load_recipes() if r["name"] == name), None)
    if recipe is None:
        raise InputError(f"no sample body named {name!r} in {recipes_path()}")
    body = make_body(sex=recipe["sex"], height=recipe["height"], bust=recipe.get("bust"),
                     waist=recipe.get("waist"), hips=recipe.get("hips"),
                     underbust=recipe.get("underbust"))
    write_glb(path, body)
    return read_body(path)
