"""The in-house pivoting methods: energy (Kolesnikov's energy criterion),
block principal pivoting, the interior-point-warm-started bpp, Lemke (dense and sparse forms), enumeration."""
