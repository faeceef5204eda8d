"""Result files written so that an interrupted run never leaves a broken one,
and the shared data sets (the Siconos collections), found from anywhere."""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path

from .errors import InvalidOptionError

#: The environment variable naming the folder that holds the data sets
#: (``siconos-lcp/``, ``siconos-fc/``).
DATA_ENV = "QPCONTACT_DATA"
#: The data sets by name: what each holds.
DATA_SETS = {"siconos-lcp": "Siconos's LCP files", "siconos-fc": "Siconos's friction files"}
# qpcontact/core/files.py -> the checkout; its data live beside it, in ../shared/data
_CHECKOUT = Path(__file__).resolve().parents[2]


def data_locations(name: str) -> list[Path]:
    """Where the data set ``name`` is looked for, in order: ``$QPCONTACT_DATA/name``,
    ``../shared/data/name`` beside the checkout, then beside the current folder."""
    places = []
    if os.environ.get(DATA_ENV):
        places.append(Path(os.environ[DATA_ENV]).expanduser() / name)
    places.append(_CHECKOUT.parent / "shared" / "data" / name)
    places.append(Path.cwd().parent / "shared" / "data" / name)
    return list(dict.fromkeys(Path(os.path.abspath(p)) for p in places))


def find_data(name: str) -> Path | None:
    """The first folder of :func:`data_locations` that exists, or None."""
    return next((p for p in data_locations(name) if p.is_dir()), None)


def missing_data(name: str, option: str, places=None) -> str:
    """Why the data set ``name`` was not found in ``places`` (default:
    :func:`data_locations`) and how to point at it."""
    looked = ", ".join(str(p) for p in (data_locations(name) if places is None else places))
    return (f"no {DATA_SETS.get(name, name)} ({name}/): looked in {looked}; set {DATA_ENV} to "
            f"the folder that holds {name}/, or pass {option}")


def make_folder(path, option: str = "--out") -> Path:
    """The folder ``path``, made with its parents when missing; InvalidOptionError
    naming ``option``, the path and why when it cannot be (a file stands there
    or on the way, no permission)."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InvalidOptionError(f"{option} {path}: is a file, not a folder; give a folder "
                                 "(it is made if missing)")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        on_way = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
        raise InvalidOptionError(
            f"{option} {path}: cannot make the folder: {on_way or 'a part of the path'} is a "
            "file; give a path under a folder") from None
    except OSError as exc:
        raise InvalidOptionError(f"{option} {path}: cannot make the folder "
                                 f"({exc.strerror or exc}); give a folder you can write to") from None
    return path


def file_target(path, option: str = "--out") -> Path:
    """``path`` for a file to be written, its folder made (:func:`make_folder`);
    InvalidOptionError when ``path`` is a folder."""
    path = Path(path)
    if path.is_dir():
        raise InvalidOptionError(f"{option} {path}: is a folder; give the file's name, e.g. "
                                 f"{path / 'results.h5'}")
    make_folder(path.parent, f"{option} {path}: its folder")
    return path


def write_csv_atomic(path: Path, rows: list[dict], fields) -> None:
    """The rows as CSV, written by :func:`write_text_atomic` (its folder
    made: :func:`file_target`)."""
    path = file_target(path, "the CSV file")
    text = io.StringIO(newline="")
    writer = csv.DictWriter(text, fieldnames=list(fields))
    writer.writeheader()
    for row in rows:
        writer.writerow({k: row.get(k, "") for k in fields})
    write_text_atomic(path, text.getvalue())


def write_text_atomic(path: Path, text: str) -> Path:
    """``text`` into a temporary file beside ``path``, flushed to disk, then
    renamed over it: an interrupted write leaves the old file, never half a
    new one."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        with open(tmp, "w", newline="") as fh:     # the text as given, line ends too
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


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
