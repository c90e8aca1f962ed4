import json

import numpy as np
from PIL import Image

from catwalk.cli.main import main


def test_bench_collide_json_keys(capsys, tmp_path):
    png = tmp_path / "maps.png"
    rc = main(["bench", "collide", "--body", "mannequin", "--frames", "1", "--substeps", "2",
               "--points", "300", "--repeat", "1", "--no-skips", "--map-size", "64",
               "--maps-png", str(png), "--json"])
    assert rc == 0
    r = json.loads(capsys.readouterr().out)
    assert set(r["modes"]) == {"hybrid", "image", "object"}
    for m in r["modes"].values():
        assert m["ms_per_frame"] > 0 and m["query_us_per_substep"] > 0
        assert m["contacts_per_substep"] > 0
    assert r["modes"]["image"]["refit_ms_per_frame"] == 0
    assert r["modes"]["object"]["maps_ms_per_frame"] == 0
    assert r["points"] == 300 and r["machine"]["nproc"] >= 1
    img = np.asarray(Image.open(png))
    assert img.ndim == 3 and (img < 128).any() and (img == 255).any()


def test_bench_collide_bad_arguments_exit_2(capsys):
    assert main(["bench", "collide", "--frames", "0"]) == 2
    assert "must be >= 1" in capsys.readouterr().err
