"""Formulations: mechanics -> problem.

One module per formulation (drum, penalty mechanisms, friction frames, ...),
each with a docstring that derives its LCP or QP from the mechanics, with units.
Formulations register with the engine through the ``qpcontact.formulations``
entry-point group; ``qpcontact`` itself never imports this package.
"""
