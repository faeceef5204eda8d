"""The QP backends: every solver qpsolvers finds, cvxpy's solvers, what their
wrappers share, and the accuracy ladder in each backend's own settings."""
