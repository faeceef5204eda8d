"""Figures, outside the engine: atomic saving (``figures``), what makes a
figure read at a glance (``style``: colour-blind-safe colours and markers,
exact zeros, tick labels that do not overprint), the load trace's plot
(``trace``) and the comparison's work-precision plot (``work_precision``)."""
