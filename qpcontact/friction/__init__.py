"""Frictional contact (Coulomb), local and global, 2-D and 3-D: the problem, its error measures, its methods."""
