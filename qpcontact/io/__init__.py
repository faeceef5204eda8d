"""Problem files: Siconos's .dat (LCP, frictional contact: :mod:`.siconos`) and
FCLIB's HDF5 (:mod:`.fclib`); :func:`read_problem` reads any of them."""

from __future__ import annotations

import os
from pathlib import Path

from .fclib import read_fclib, write_fclib
from .siconos import read_siconos, read_siconos_fc, read_siconos_lcp, write_siconos_fc

__all__ = ["read_problem", "read_siconos", "read_siconos_lcp", "read_siconos_fc", "read_fclib",
           "write_fclib", "write_siconos_fc"]


def read_problem(path: str | os.PathLike):
    """Read any problem file qpcontact knows: FCLIB HDF5 (``.hdf5``/``.h5``:
    a FrictionProblem) or a Siconos ``.dat`` file, LCP or frictional contact.
    The two layouts are told apart by which one reads the file; after the data
    only a comment (and frictional contact's isComplete flag) is allowed, and
    anything else raises InvalidProblemError naming the file and the line
    (:mod:`qpcontact.io.siconos`)."""
    path = Path(path)
    if path.suffix in (".hdf5", ".h5"):
        return read_fclib(path)
    return read_siconos(path)
