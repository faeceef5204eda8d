"""Shared fixtures: the peers' data in ../shared/data (helpers in tests/helpers)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.helpers.paths import SICONOS_DIR


@pytest.fixture
def siconos_dir() -> Path:
    if not SICONOS_DIR.is_dir():
        pytest.skip(f"Siconos LCP test data not found at {SICONOS_DIR} (the repo's ../shared/data); "
                    "these tests need the shared data set beside the checkout, or QPCONTACT_DATA")
    return SICONOS_DIR
