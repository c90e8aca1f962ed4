import json
import subprocess
import sys

from catwalk.cli import main


def test_bench_cloth_json(capsys):
    assert main(["bench", "cloth", "--json", "--steps", "20", "--settle", "0.02"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert set(res) == {"points", "springs", "methods"}
    assert abs(res["points"] - 3372) < 100 and abs(res["springs"] - 18623) < 1500
    assert set(res["methods"]) == {"none", "ordered", "vassilev", "provot"}
    for r in res["methods"].values():
        assert set(r) == {"us_per_step", "max_strain"} and r["us_per_step"] > 0


def test_bench_drape_json(capsys):
    assert main(["bench", "drape", "--json", "--fabrics", "denim", "--h", "0.03",
                 "--max-seconds", "0.3"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert list(res) == ["fabrics"]
    assert set(res["fabrics"]["denim"]) == {"dc", "h", "nodes"}
    assert res["fabrics"]["denim"]["h"] == 0.03
    assert isinstance(res["fabrics"]["denim"]["nodes"], int)


def test_bench_bad_input_exits_2():
    for args in (["bench", "drape", "--fabrics", "tweed"], ["bench", "cloth", "--h", "-1"],
                 ["bench", "cloth", "--methods", "magic"]):
        res = subprocess.run([sys.executable, "-m", "catwalk.cli", *args], capture_output=True,
                             text=True)
        assert res.returncode == 2, args
        assert "catwalk: error:" in res.stderr and "Traceback" not in res.stderr
