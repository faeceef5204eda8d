"""The command line and the jobs it runs: ``qpcontact`` (cli), the demo, the
comparison sweep (compare) and the hard-case suite (stress)."""
