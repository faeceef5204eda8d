"""Frictional contact (Coulomb), local and global, 2-D and 3-D."""

from .problem import *  # noqa: F401,F403  (temporary during the move)
