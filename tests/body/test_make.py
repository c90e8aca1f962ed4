"""Bodies from measurements: requested girths within 1 cm, height within 0.5 cm."""

import json
import subprocess
import sys

import numpy as np
import pytest

from catwalk.body.make import make_body
from catwalk.body.measure import measure_body
from catwalk.catalogue.bodies import load_recipes
from catwalk.errors import InputError
from catwalk.exchange import gltf

RECIPES = {r["name"]: r for r in load_recipes()}
CASES = ["female-XS", "female-M", "female-XXL", "male-XS", "male-M", "male-XXL"]


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    out = {}
    d = tmp_path_factory.mktemp("bodies")
    for name in CASES:
        r = RECIPES[name]
        body = make_body(sex=r["sex"], height=r["height"], bust=r["bust"], waist=r["waist"],
                         hips=r["hips"])
        path = d / f"{name}.glb"
        gltf.write_glb(path, body)
        out[name] = (r, body, path)
    return out


@pytest.mark.parametrize("name", CASES)
def test_made_body_remeasures_as_requested(made, name):
    r, body, path = made[name]
    back = gltf.read_body(path)  # measure what the file holds, not the in-memory body
    m = measure_body(back.vertices, back.faces, sex=r["sex"])
    assert abs(m["height"] - r["height"]) <= 0.005
    for key in ("bust", "waist", "hips"):
        assert abs(m[key] - r[key]) <= 0.01, (key, m[key], r[key])


def test_made_bodies_are_rigged_with_parts_and_validate(made):
    r, body, path = made["female-M"]
    back = gltf.read_body(path)
    assert back.skeleton is not None and len(back.skeleton.names) >= 20
    assert back.vertices.shape == (13380, 3) and back.faces.shape == (26756, 3)
    assert set(np.unique(back.parts)) == {0, 1, 2, 3, 4}
    # the body's own left (+X) arm is part 1
    assert back.vertices[back.parts == 1, 0].mean() > 0.15
    assert back.vertices[back.parts == 2, 0].mean() < -0.15
    for key in ("waist", "hips", "crotch", "neck_base"):
        assert key in back.landmarks
    assert abs(back.vertices[:, 1].min()) < 1e-6  # feet on the floor
    reports = gltf.validate([p for _, _, p in made.values()])
    assert all(rep["numErrors"] == 0 for rep in reports), reports


def test_bigger_sizes_are_bigger(made):
    for sex in ("female", "male"):
        small = made[f"{sex}-XS"][1].meta["measured"]
        big = made[f"{sex}-XXL"][1].meta["measured"]
        assert big["waist"] - small["waist"] > 0.3


@pytest.mark.parametrize("kwargs, match", [
    (dict(sex="female", height=1.68, bust=1.9, waist=0.7, hips=0.9), "bust"),
    (dict(sex="female", height=2.6, bust=0.9, waist=0.7, hips=0.9), "height"),
    (dict(sex="other", height=1.7), "sex"),
    (dict(sex="male", height=1.8, bust=0.9, waist=1.2, hips=0.95), "waist"),
])
def test_out_of_range_requests_are_refused(kwargs, match):
    with pytest.raises(InputError, match=match):
        make_body(**kwargs)


def test_cli_refuses_with_exit_2(tmp_path):
    out = tmp_path / "b.glb"
    res = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "body", "make",
                          "--sex", "female",
                          "--height", "168", "--bust", "0.9", "-o", str(out)],
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert "height" in res.stderr and "metres" in res.stderr
    assert "Traceback" not in res.stderr
    assert not out.exists()


def test_cli_makes_a_body(tmp_path):
    out = tmp_path / "b.glb"
    res = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "body", "make",
                          "--sex", "male",
                          "--height", "1.75", "--bust", "1.0", "--waist", "0.88",
                          "--hips", "1.0", "-o", str(out)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    summary = json.loads(res.stdout)
    for k in ("bust", "waist", "hips"):
        assert abs(summary["measured"][k] - summary["requested"][k]) <= 0.01
    assert out.stat().st_size > 500_000
