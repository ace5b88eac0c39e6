"""FEM tests keep their mesh cache in a temporary folder shared by the session."""

import pytest


@pytest.fixture(scope="session", autouse=True)
def _fem_cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SOFTCATH_CACHE", str(tmp_path_factory.mktemp("softcath-cache")))
        yield
