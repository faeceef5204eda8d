"""FCLIB's HDF5 files of frictional contact problems (local and global), read
and written (atomically)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidProblemError
from ..core.friction_problem import FrictionProblem

__all__ = ["read_fclib", "write_fclib"]


def _cs_from_fclib(g, name: str):
    """A CSparse matrix as FCLIB stores it (nz = -1 columns, -2 rows, >= 0 triplets)."""
    m, n, nz = int(g["m"][0]), int(g["n"][0]), int(g["nz"][0])
    p, i, x = np.asarray(g["p"]), np.asarray(g["i"]), np.asarray(g["x"], float)
    if nz == -1:
        return sp.csc_matrix((x[:p[-1]], i[:p[-1]], p), shape=(m, n))
    if nz == -2:
        return sp.csr_matrix((x[:p[-1]], i[:p[-1]], p), shape=(m, n)).tocsc()
    if nz >= 0:
        return sp.csc_matrix((x[:nz], (i[:nz], p[:nz])), shape=(m, n))
    raise InvalidProblemError(f"FCLIB matrix {name}: unknown storage nz = {nz}")


def read_fclib(path: str | os.PathLike):
    """Read an FCLIB HDF5 file (local or global problem; the stored
    ``solution`` and ``guesses`` when present).  Returns a
    :class:`~qpcontact.core.friction_problem.FrictionProblem`."""
    from ..core.files import open_hdf5

    path = Path(path)
    with open_hdf5(path, InvalidProblemError, "an FCLIB HDF5 file") as h:
        sol = {k: np.asarray(v) for k, v in h["solution"].items()} if "solution" in h else None
        guesses = []
        if "guesses" in h:
            for key in sorted(k for k in h["guesses"] if k != "number_of_guesses"):
                guesses.append({k: np.asarray(v) for k, v in h["guesses"][key].items()})
        if "fclib_local" in h:
            g = h["fclib_local"]
            prob = FrictionProblem(_cs_from_fclib(g["W"], "W"), np.asarray(g["vectors/q"]),
                                   np.asarray(g["vectors/mu"]), int(g["spacedim"][0]),
                                   name=path.stem)
        elif "fclib_global" in h:
            g = h["fclib_global"]
            prob = FrictionProblem.global_problem(
                _cs_from_fclib(g["M"], "M"), _cs_from_fclib(g["H"], "H"),
                np.asarray(g["vectors/f"]), np.asarray(g["vectors/w"]),
                np.asarray(g["vectors/mu"]), int(g["spacedim"][0]), name=path.stem)
        else:
            raise InvalidProblemError(f"{path.name}: neither fclib_local nor fclib_global inside")
    prob.solution, prob.guesses = sol, guesses
    return prob


def _cs_to_fclib(group, A) -> None:
    """Store A in compressed columns (nz = -1), as FCLIB's writer does."""
    A = sp.csc_matrix(A)
    A.sort_indices()
    for key, value in (("m", A.shape[0]), ("n", A.shape[1]), ("nz", -1), ("nzmax", A.nnz)):
        group.create_dataset(key, data=np.array([value], dtype=np.int32))
    group.create_dataset("p", data=A.indptr.astype(np.int32))
    group.create_dataset("i", data=A.indices.astype(np.int32))
    group.create_dataset("x", data=A.data.astype(float))


def write_fclib(problem, path: str | os.PathLike, *, title: str = "", description: str = "",
                solution: dict | None = None, guesses: list | None = None) -> Path:
    """Write a :class:`~qpcontact.core.friction_problem.FrictionProblem` as an FCLIB HDF5
    file that FCLIB's reader (and :func:`read_fclib`) takes: ``fclib_global``
    (M, H, f, w, mu) when the problem came from a global one, else
    ``fclib_local`` (W, q, mu); ``solution`` and ``guesses`` as dicts of
    ``r``, ``u`` (and ``v``), defaulting to the problem's own.  Written to a
    temporary file and renamed, so an interrupted write never leaves a broken
    file.  Returns the path."""
    import h5py

    path = Path(path)
    solution = problem.solution if solution is None else solution
    guesses = problem.guesses if guesses is None else guesses
    tmp = path.with_name(path.name + ".tmp")
    try:
        with h5py.File(tmp, "w") as h:
            g = problem.global_data
            top = h.create_group("fclib_global" if g is not None else "fclib_local")
            if g is not None:
                _cs_to_fclib(top.create_group("M"), g["M"])
                _cs_to_fclib(top.create_group("H"), g["H"])
                vectors = {"f": g["f"], "w": g["w"], "mu": problem.mu}
            else:
                _cs_to_fclib(top.create_group("W"), problem.W)
                vectors = {"q": problem.q, "mu": problem.mu}
            vg = top.create_group("vectors")
            for key, value in vectors.items():
                vg.create_dataset(key, data=np.asarray(value, dtype=float))
            top.create_dataset("spacedim", data=np.array([problem.dim], dtype=np.int32))
            info = top.create_group("info")
            for key, value in (("title", title or problem.name), ("description", description),
                               ("math_info", "")):
                info.create_dataset(key, data=np.bytes_(value.encode()))
            if solution is not None:
                sg = h.create_group("solution")
                for key, value in solution.items():
                    sg.create_dataset(key, data=np.asarray(value, dtype=float))
            if guesses:
                gg = h.create_group("guesses")
                gg.create_dataset("number_of_guesses", data=np.array([len(guesses)], np.int32))
                for k, guess in enumerate(guesses, 1):
                    sub = gg.create_group(str(k))
                    for key, value in guess.items():
                        sub.create_dataset(key, data=np.asarray(value, dtype=float))
            h.flush()
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path
