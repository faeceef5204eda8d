"""The in-house pivoting methods: energy (P0), block principal pivoting, the
interior-point-warm-started bpp, Lemke (dense and sparse forms), enumeration."""
