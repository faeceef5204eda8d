"""Result files written so that an interrupted run never leaves a broken one."""

from __future__ import annotations

import csv
import os
from pathlib import Path


def write_csv_atomic(path: Path, rows: list[dict], fields) -> None:
    """A temporary file, flushed to disk, then renamed over ``path``."""
    path = Path(path)
    tmp = path.with_suffix(path.suffix + ".tmp")
    with open(tmp, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(fields))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: row.get(k, "") for k in fields})
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def open_hdf5(path, error, what: str):
    """``h5py.File(path, "r")``, or ``error`` naming the path and saying
    whether the file is missing or not HDF5 (``what``: "an FCLIB file")."""
    import h5py

    path = Path(path)
    if not path.is_file():
        raise error(f"{path}: no such file (expected {what})")
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise error(f"{path}: not {what} ({exc})") from None
