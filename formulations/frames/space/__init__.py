"""The SpaceFrame: its model, assembly, results, circular cone, tower and
worked examples."""
