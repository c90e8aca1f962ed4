import pytest


@pytest.fixture(scope="session")
def dressable_body():
    """The female MakeHuman base body, rigged, with landmarks and girths (≈ 1 s to make)."""
    from catwalk.body.measure import measure_body
    from catwalk.body.rig import rigged_base_body

    body = rigged_base_body(0.0)
    m = measure_body(body.vertices, body.faces, sex="female")
    body.landmarks = {k: [float(x) for x in v] for k, v in m["landmarks"].items()}
    body.meta["measured"] = {k: float(v) for k, v in m.items()
                             if isinstance(v, (int, float))}
    body.meta["sex"] = "female"
    return body


@pytest.fixture(scope="session")
def body_glb(dressable_body, tmp_path_factory):
    from catwalk.export.gltf import write_glb

    path = tmp_path_factory.mktemp("tryon") / "body.glb"
    write_glb(path, dressable_body)
    return path


@pytest.fixture(scope="session")
def repo_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]
