"""Problem files: Siconos .dat (LCP, frictional contact) and FCLIB HDF5."""

from .formats import read_fclib, read_problem, read_siconos_fc, read_siconos_lcp, write_fclib

__all__ = ["read_problem", "read_siconos_lcp", "read_siconos_fc", "read_fclib", "write_fclib"]
