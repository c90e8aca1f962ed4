import os

import numpy as np
import pytest
from PIL import Image

from catwalk.collide.shapes import Mannequin, figure10_pose, sphere
from catwalk.errors import CatwalkError
from catwalk.render.preview import render_meshes, save_png


def test_sphere_renders_shaded_disc_on_grey(tmp_path):
    v, f = sphere((0.0, 1.0, 0.0), 0.3)
    img = render_meshes([(v, f, (1.0, 0.0, 0.0))], "front", (120, 160), floor=False,
                        margin=0.0)
    assert img.shape == (160, 120, 3) and img.dtype == np.uint8
    red = (img[..., 0] > img[..., 1] + 40)
    # the sphere fills the box's height (160 px for 0.6 m): a disc of radius 80 px > width
    # → only check the middle row is all red and the disc is lit from the upper left
    assert red[80, 5:115].all()
    assert img[40, 40, 0] > img[120, 80, 0]
    corners = img[[0, 0, -1, -1], [0, -1, 0, -1]]
    assert np.all(corners > 180) and np.all(np.ptp(corners, axis=1) < 10)  # light grey
    path = tmp_path / "s.png"
    save_png(img, path)
    back = np.asarray(Image.open(path))
    np.testing.assert_array_equal(back, img)
    assert not list(tmp_path.glob(".*"))  # no temporary left behind
    umask = os.umask(0)
    os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask  # not the temporary's 0600


def test_views_and_colours_of_a_mannequin():
    m = Mannequin(0.5)
    v = m.vertices(figure10_pose())
    cols = np.array([[200, 170, 150], [40, 40, 220], [220, 40, 40], [40, 200, 40],
                     [40, 200, 40]], np.uint8)[m.parts]
    front = render_meshes([(v, m.faces, cols)], "front", (128, 192))
    back = render_meshes([(v, m.faces, cols)], "back", (128, 192))

    front, back = front.astype(int), back.astype(int)

    def blue_x(img):
        b = (img[..., 2] > img[..., 0] + 60) & (img[..., 2] > img[..., 1] + 60)
        return np.nonzero(b)[1].mean()

    # the left arm (+X, blue) is on the right of a front view, on the left of a back view
    assert blue_x(front) > 64 > blue_x(back)
    # in front, the right forearm (red) crosses the torso; from the back it is hidden
    red = lambda im: ((im[..., 0] > im[..., 1] + 60) & (im[..., 0] > im[..., 2] + 60)).sum()  # noqa: E731
    assert red(front) > 1.4 * red(back)


def test_bench_render_reports_its_cost(capsys):
    # speed is a benchmark figure (docs/render.md), not a timed test: check the command works
    import json

    from catwalk.cli.main import main

    assert main(["bench", "render", "--size", "128x192", "--repeats", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["triangles"] == 26756 and out["size"] == [128, 192]
    assert 0 < out["ms_per_frame"] <= out["ms_median"]


def test_bad_meshes_are_catwalk_errors():
    with pytest.raises(CatwalkError):
        render_meshes([])
    with pytest.raises(CatwalkError):
        render_meshes([(np.zeros((3, 2)), [[0, 1, 2]], (1, 0, 0))])
    with pytest.raises(CatwalkError):
        render_meshes([(np.zeros((3, 3)), [[0, 1, 2]], (1, 0, 0))], view="sideways")
    with pytest.raises(CatwalkError):
        save_png(np.zeros((4, 4, 3)), "/tmp/never.png")
