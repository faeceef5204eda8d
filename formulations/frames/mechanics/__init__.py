"""What the plane and the space frame share: the elements, loads, contact
springs, the contact LCP, the checks, and the analysis as functions taking a
frame (solving, tracing, the Tresca fixed point, the proofs of no
equilibrium, the export as a friction problem) with the result containers."""
