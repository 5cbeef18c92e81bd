"""Fixtures shared by the arenas tests."""

import pytest

import arenas


@pytest.fixture(scope="module")
def paper():
    return arenas.load("paper")
