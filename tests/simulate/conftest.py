import pytest


@pytest.fixture(scope="session")
def dressable_body():
    """The female MakeHuman base body, rigged, with landmarks and girths (≈ 1 s to make)."""
    from catwalk.body.rig import measured_base_body

    return measured_base_body(0.0)


@pytest.fixture(scope="session")
def male_body():
    """The male MakeHuman base body, rigged, with landmarks and girths."""
    from catwalk.body.rig import measured_base_body

    return measured_base_body(1.0)


@pytest.fixture(scope="session")
def body_glb(dressable_body, tmp_path_factory):
    from catwalk.exchange.gltf import write_glb

    path = tmp_path_factory.mktemp("tryon") / "body.glb"
    write_glb(path, dressable_body)
    return path


@pytest.fixture(scope="session")
def repo_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]
