"""``solve``: one entry point for every problem kind — routes, calls (time
limits, isolation, the engine handed to composite methods), one run per kind,
and "auto"."""
