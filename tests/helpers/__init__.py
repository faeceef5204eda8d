"""What the tests share, in one place: the checkout's paths and the peers'
data (``paths``), seeded SPD problems with a planted solution (``problems``),
exact references written independently of the package (``references``),
figure and CSV checks (``figures``) and the README's blocks (``readme``).
The package's own generators (qpcontact.cases) are imported from the package,
never shadowed here."""
