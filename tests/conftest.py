"""Test-session settings: the condensed-interface cache lives in the session's
temporary directory, not in the user's home."""
import pytest

from brakewear.interfaces.condensation import CACHE_ENV


@pytest.fixture(autouse=True, scope="session")
def _condensation_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv(CACHE_ENV, str(tmp_path_factory.mktemp("condensed")))
    yield
    mp.undo()
