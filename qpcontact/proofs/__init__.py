"""Proofs that no solution exists, checked from the data: Farkas vectors and rays
(exact rational checks), the load trace's collapse by branch and bound, a
frictional problem's no-equilibrium motion."""
