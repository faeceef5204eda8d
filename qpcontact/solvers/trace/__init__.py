"""``"trace"``: the solution path of a parametric LCP as the load grows
(the load-trace paper of Osipova, Popov & Lovtsov).

:mod:`.driver` (the method, its endings and what proves them), :mod:`.path`
(working schemes, directions, pieces), :mod:`.result` (what comes back); the
collapse proof is in :mod:`qpcontact.proofs.parametric`, the plot in
:mod:`qpcontact.plots.trace`.
"""
