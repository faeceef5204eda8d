"""Figures, outside the engine: atomic saving (``figures``) and the load trace's
plot (``trace``)."""
