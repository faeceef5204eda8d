"""Problems with their answer built in: seeded families, planted LCPs, QPs and
frictional problems, the decomposition paper's examples, and named instances
for the comparison sweep."""
