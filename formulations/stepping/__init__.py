"""The contact time step shared by the planar mechanisms
(:mod:`formulations.mechanisms`) and the spatial trees
(:mod:`formulations.multibody`): the penalty QP of one integration step
(:mod:`.penalty_step`, after Nikolsky, Kopylov, Romanenko & Kudryashov 2012,
with its derivation and units) and the semi-implicit step around it
(:mod:`.contact_step`).  It imports neither of the formulations that use it,
so the folders import one way: mechanisms -> multibody -> stepping.  Import
from the two modules (the mechanisms re-export what their users need)."""

