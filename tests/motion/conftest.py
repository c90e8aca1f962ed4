import pytest


@pytest.fixture(scope="session")
def neutral_body():
    from catwalk.body.rig import rigged_base_body

    return rigged_base_body(0.5)


@pytest.fixture(scope="session")
def female_body():
    from catwalk.body.rig import rigged_base_body

    return rigged_base_body(0.0)


@pytest.fixture(scope="session")
def male_body():
    from catwalk.body.rig import rigged_base_body

    return rigged_base_body(1.0)
