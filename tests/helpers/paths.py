"""The checkout's folders and the peers' data beside it (../shared/data, or
$QPCONTACT_DATA through qpcontact.core.files.find_data)."""

from __future__ import annotations

from pathlib import Path

from qpcontact.core.files import find_data

#: the repository's root (the folder with pyproject.toml)
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
SCENES = EXAMPLES / "scenes"
DOCS = ROOT / "docs"
#: ../shared/data beside the checkout
SHARED_DATA = ROOT.parent / "shared" / "data"


def data_dir(name: str) -> Path:
    """A peer collection (``siconos-lcp``, ``siconos-fc``): $QPCONTACT_DATA/name,
    else the checkout's ../shared/data/name (it may not exist: callers skip)."""
    return find_data(name) or SHARED_DATA / name


SICONOS_DIR = data_dir("siconos-lcp")


def siconos_files() -> list[Path]:
    return sorted(SICONOS_DIR.glob("*.dat")) if SICONOS_DIR.is_dir() else []
