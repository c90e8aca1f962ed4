import pytest


@pytest.fixture(scope="session")
def mpfb2():
    from catwalk.assets import ensure_assets

    return ensure_assets()
