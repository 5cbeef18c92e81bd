"""Fixtures of the fault suite: a private cache, and processes without in-memory caches."""

import pytest

from memory_caches import forget_in_memory_caches


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A private, empty ``$RECIPROCITY_CACHE``."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("RECIPROCITY_CACHE", str(folder))
    forget_in_memory_caches()
    yield folder
    forget_in_memory_caches()
