"""How frame results are shown: tables, engineering notation, the plane
and space drawings with their labels and load arrows, the trace plot."""
