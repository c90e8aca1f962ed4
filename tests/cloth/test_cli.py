import json
import subprocess
import sys

import numpy as np
import pytest

from catwalk.cli.main import main


def test_bench_cloth_json(capsys):
    assert main(["bench", "cloth", "--json", "--steps", "20", "--settle", "0.02"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert set(res) == {"points", "springs", "methods", "shear_energy_ratio"}
    # the grid's shear stiffness against the fabric's: whole below the compression's soft
    # band, falling towards (1 + 0.05)/2 beyond it (docs/cloth.md)
    sr = res["shear_energy_ratio"]
    assert list(sr) == ["0.5", "1.0", "2.0", "5.0", "10.0"]
    assert sr["0.5"] > 0.9 and sr["10.0"] < 0.65 and sr["5.0"] < sr["2.0"] < sr["0.5"]
    assert abs(res["points"] - 3372) < 100 and abs(res["springs"] - 18623) < 1500
    assert set(res["methods"]) == {"none", "ordered", "vassilev", "provot"}
    for r in res["methods"].values():
        assert set(r) == {"us_per_step", "max_strain"} and r["us_per_step"] > 0


def test_bench_drape_json(capsys):
    assert main(["bench", "drape", "--json", "--fabrics", "denim", "--h", "0.03",
                 "--max-seconds", "0.3"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert list(res) == ["fabrics", "against_measured", "probes"]
    assert set(res["fabrics"]["denim"]) == {"dc", "h", "nodes"}
    assert res["fabrics"]["denim"]["h"] == 0.03
    assert isinstance(res["fabrics"]["denim"]["nodes"], int)
    assert res["against_measured"] == {}   # denim's DC was not measured


def test_bench_drape_says_the_error_against_the_measured_fabrics_and_probes_a_property(
        capsys, tmp_path):
    args = ["bench", "drape", "--json", "--fabrics", "m2,m6", "--h", "0.03",
            "--max-seconds", "0.3"]
    assert main([*args, "--plot", str(tmp_path / "dc.png")]) == 0
    res = json.loads(capsys.readouterr().out)
    # the plot: a dot per measured fabric, ours blue and CLO3D's grey
    from PIL import Image

    img = np.asarray(Image.open(tmp_path / "dc.png").convert("RGB"))
    assert img.shape == (600, 900, 3)
    assert (img == (60, 90, 200)).all(axis=2).sum() > 2 * 30
    assert (img == (150, 150, 150)).all(axis=2).sum() > 2 * 30
    m = res["against_measured"]
    assert set(m["fabrics"]) == {"m2", "m6"}
    assert m["fabrics"]["m6"]["measured"] == 0.549
    assert m["fabrics"]["m6"]["error"] == round(res["fabrics"]["m6"]["dc"] - 0.549, 4)
    assert m["clo3d_mean_abs_error"] == round((abs(0.313 - 0.228) + abs(0.613 - 0.549)) / 2, 4)
    assert m["mean_abs_error"] == round(sum(abs(r["error"]) for r in m["fabrics"].values()) / 2,
                                        4)
    # a stiffer bend holds the specimen out further
    assert main([*args, "--bend-scale", "30"]) == 0
    stiff = json.loads(capsys.readouterr().out)
    assert stiff["probes"]["bend_scale"] == 30
    assert stiff["fabrics"]["m6"]["dc"] > res["fabrics"]["m6"]["dc"] + 0.05


def test_bench_cantilever_json(capsys):
    assert main(["bench", "cantilever", "--json", "--fabrics", "denim", "--h", "0.01"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["h"] == [0.01] and list(res["fabrics"]) == ["denim"]
    r = res["fabrics"]["denim"]
    assert set(r) == {"bending_length_m", "expected_m", "error", "settles", "worst_error"}
    for d in ("warp", "weft"):
        c = r["bending_length_m"][d]["0.01"]
        assert r["error"][d]["0.01"] == pytest.approx(c / r["expected_m"][d] - 1, abs=1e-3)
        assert abs(r["error"][d]["0.01"]) < 0.1          # denim bends over 1.7–2 cm
    assert r["expected_m"]["warp"] > r["expected_m"]["weft"]
    assert res["worst_error"] == r["worst_error"]


def test_bench_bad_input_exits_2():
    for args in (["bench", "drape", "--fabrics", "tweed"], ["bench", "cloth", "--h", "-1"],
                 ["bench", "drape", "--shear-scale", "0"],
                 ["bench", "drape", "--compression", "1.5"],
                 ["bench", "drape", "--fabrics", "denim", "--plot", "dc.png"],
                 ["bench", "cloth", "--methods", "magic"],
                 ["bench", "cantilever", "--h", "-1"], ["bench", "cantilever", "--h", "0.2"],
                 ["bench", "cantilever", "--fabrics", "tweed"]):
        res = subprocess.run([sys.executable, "-m", "catwalk.cli.main", *args], capture_output=True,
                             text=True)
        assert res.returncode == 2, args
        assert "catwalk: error:" in res.stderr and "Traceback" not in res.stderr
