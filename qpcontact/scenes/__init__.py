"""Scene files (TOML), their results files (HDF5) and figures."""

from .schema import *  # noqa: F401,F403  (temporary during the move)
