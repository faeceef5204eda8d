"""The frictional-contact methods (Coulomb, local and global, 2-D and 3-D):
NSGS, NSGS then Newton, the fixed points of SOCPs, semismooth Newton and the
LCP route.  The problem type is :mod:`qpcontact.core.friction_problem`, its
certificate :mod:`qpcontact.judge.friction_certificate`; docs/architecture.md
has the friction subject's table, one module in each layer."""
