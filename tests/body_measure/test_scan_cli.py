"""``catwalk body info`` / ``catwalk body measure``: JSON output, and every bad file exits 2
with a message naming the file and the problem, never a traceback."""

import json
import struct
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from catwalk.cli.main import main


@pytest.fixture(scope="module")
def female_stl(tmp_path_factory, bodies, body_faces):
    p = tmp_path_factory.mktemp("scan") / "female_mm_zup.stl"
    v = bodies["female"]
    zup = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1) * 1000.0
    trimesh.Trimesh(zup, body_faces, process=False).export(p)
    return p


def test_info_prints_readable_json(female_stl, capsys):
    assert main(["body", "info", str(female_stl)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("{\n  ")  # indented
    info = json.loads(out)
    assert info["units"] == "mm" and info["up_axis"] == "+Z" and info["forward_axis"] == "-Y"
    assert info["vertices"] == 13380 and info["faces"] == 26756
    assert info["watertight"] is True and info["holes"] == 0 and info["components"] == 1
    assert info["height_m"] == pytest.approx(1.590, abs=0.002)


def test_measure_prints_measurements_and_landmarks(female_stl, capsys, measured):
    assert main(["body", "measure", str(female_stl), "--sex", "female"]) == 0
    m = json.loads(capsys.readouterr().out)
    for k in ("height", "bust", "chest", "underbust", "waist", "hips", "inseam",
              "shoulder_width", "arm_length", "neck_girth", "upper_arm_girth", "bust_span"):
        assert m[k] == pytest.approx(measured["female"][k], abs=0.002), k
    assert set(measured["female"]["landmarks"]) == set(m["landmarks"])
    # the same landmarks in the file's own coordinates (millimetres, Z up)
    assert m["landmarks_file"]["crotch"][2] == pytest.approx(
        1000 * m["landmarks"]["crotch"][1] + 1000 * (-measured["female"]["landmarks"]["crotch"][1]
                                                     + measured["female"]["inseam"]), abs=1.0)


def _body_file(tmp_path, bodies, body_faces, name, vertices=None, faces=None):
    p = tmp_path / name
    v = bodies["female"] if vertices is None else vertices
    f = body_faces if faces is None else faces
    trimesh.Trimesh(v, f, process=False).export(p)
    return p


def _write(p, data: bytes):
    p.write_bytes(data)
    return p


def _bad_files(tmp_path, bodies, body_faces):
    v = bodies["female"]
    good_obj = _body_file(tmp_path, bodies, body_faces, "good.obj").read_bytes()
    good_glb = _body_file(tmp_path, bodies, body_faces, "good.glb").read_bytes()
    good_stl = _body_file(tmp_path, bodies, body_faces, "good.stl").read_bytes()
    nan = v.copy()
    nan[10] = np.nan
    inf = v.copy()
    inf[20, 2] = np.inf
    flat = v.copy()
    flat[:, 2] = 0.0
    zero_area = np.concatenate([body_faces[:100],
                                np.repeat(body_faces[100:, :1], 3, axis=1)[:, [0, 0, 0]]])
    zero_area[100:, 1] = zero_area[100:, 0]
    huge = tmp_path / "huge.stl"  # a binary STL declaring 2,000,001 triangles (sparse file)
    n = 2_000_001
    with open(huge, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", n))
        f.seek(84 + 50 * n - 1)
        f.write(b"\0")
    return {
        "empty": (_write(tmp_path / "empty.obj", b""), "empty"),
        "truncated_stl": (_write(tmp_path / "cut.stl", good_stl[: len(good_stl) // 2]),
                          "truncated"),
        "truncated_glb": (_write(tmp_path / "cut.glb", good_glb[: len(good_glb) // 2]),
                          "truncated"),
        "truncated_obj": (_write(tmp_path / "cut.obj", good_obj[: len(good_obj) // 3]),
                          "truncated"),
        "garbage_ply": (_write(tmp_path / "garbage.ply", b"ply\n" + bytes(range(256)) * 20),
                        "not a readable"),
        "not_a_mesh": (_write(tmp_path / "words.obj", b"hello world\n"), "no triangles"),
        "nan": (_body_file(tmp_path, bodies, body_faces, "nan.ply", vertices=nan), "NaN"),
        "inf": (_body_file(tmp_path, bodies, body_faces, "inf.obj", vertices=inf), "infinite"),
        "flat": (_body_file(tmp_path, bodies, body_faces, "flat.stl", vertices=flat),
                 "zero extent"),
        "zero_area": (_body_file(tmp_path, bodies, body_faces, "zero.ply", faces=zero_area),
                      "zero area"),
        "giant": (_body_file(tmp_path, bodies, body_faces, "giant.obj", vertices=v * 3.0),
                  "not a human size"),
        "too_many_faces": (huge, "2,000,001 faces"),
        "unsupported": (_write(tmp_path / "body.fbx", b"Kaydara FBX Binary"), "unsupported"),
        "missing": (tmp_path / "nowhere.obj", "no such file"),
    }


CASES = ["empty", "truncated_stl", "truncated_glb", "truncated_obj", "garbage_ply",
         "not_a_mesh", "nan", "inf", "flat", "zero_area", "giant", "too_many_faces",
         "unsupported", "missing"]


@pytest.fixture(scope="module")
def bad_files(tmp_path_factory, bodies, body_faces):
    return _bad_files(tmp_path_factory.mktemp("bad"), bodies, body_faces)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("command", ["info", "measure"])
def test_bad_file_exits_2_with_a_clear_message(case, command, bad_files, capsys):
    path, words = bad_files[case]
    assert main(["body", command, str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("catwalk: error: ")
    assert path.name in err, err
    assert words.lower() in err.lower(), err
    assert "Traceback" not in err


def test_bad_file_through_the_real_command(bad_files):
    path, _ = bad_files["nan"]
    res = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "body", "info", str(path)],
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert "NaN" in res.stderr and path.name in res.stderr
    assert "Traceback" not in res.stderr
    assert res.stdout == ""
