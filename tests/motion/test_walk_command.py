import json
from pathlib import Path

import numpy as np
import pytest

from catwalk.body.types import Body
from catwalk.cli.main import main
from catwalk.exchange import gltf


@pytest.fixture(scope="module")
def body_glb(tmp_path_factory, neutral_body):
    path = tmp_path_factory.mktemp("walk") / "body.glb"
    gltf.write_glb(path, neutral_body)
    return path


def test_walk_command_writes_an_animated_glb(body_glb, tmp_path, capsys):
    out = tmp_path / "walk.glb"
    rc = main(["walk", "--body", str(body_glb), "--seconds", "2", "--speed", "1.3",
               "--style", "normal", "-o", str(out)])
    assert rc == 0
    info = json.loads(capsys.readouterr().out)
    assert info["style"] == "normal"
    assert abs(info["seconds"] - 2.0) < 0.7      # whole gait cycles
    motion = gltf.read_motion(out)
    body = gltf.read_body(out)
    assert motion is not None and motion.frames == info["frames"]
    assert motion.rotations.shape == (info["frames"], len(body.skeleton.names), 4)
    assert np.isclose(motion.meta["speed_m_s"], 1.3)
    dots = np.sum(motion.rotations[1:] * motion.rotations[:-1], axis=-1)
    assert dots.min() > 0.9


@pytest.mark.parametrize("args, message", [
    (["--seconds", "2"], "no such file"),
    (["--seconds", "0"], "--seconds"),
    (["--seconds", "-1"], "--seconds"),
    (["--seconds", "2", "--speed", "3.5"], "--speed"),
    (["--seconds", "2", "--speed", "0.2"], "--speed"),
])
def test_walk_command_bad_arguments(args, message, body_glb, tmp_path, capsys):
    body = "missing.glb" if message == "no such file" else str(body_glb)
    rc = main(["walk", "--body", str(tmp_path / body) if body == "missing.glb" else body,
               *args, "-o", str(tmp_path / "w.glb")])
    assert rc == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "w.glb").exists()


def test_walk_command_body_without_rig(neutral_body, tmp_path, capsys):
    plain = tmp_path / "plain.glb"
    gltf.write_glb(plain, Body(vertices=neutral_body.vertices, faces=neutral_body.faces))
    rc = main(["walk", "--body", str(plain), "--seconds", "1", "-o", str(tmp_path / "w.glb")])
    assert rc == 2
    assert "no rig" in capsys.readouterr().err
    assert not Path(tmp_path / "w.glb").exists()


def test_walk_of_a_body_read_back_matches(neutral_body, body_glb):
    from catwalk.motion.gait import walk_motion

    back = gltf.read_body(body_glb)
    a = walk_motion(neutral_body, 1.0, style="catwalk")
    b = walk_motion(back, 1.0, style="catwalk")
    assert a.frames == b.frames
    dots = np.abs(np.sum(a.rotations * b.rotations, axis=-1))
    assert dots.min() > 0.9999
    assert np.abs(a.translations - b.translations).max() < 1e-3
