"""``qpcontact stress``: the hard-case suite, run as a product.

Families x sizes x seeds x methods x accuracy levels.  Every instance carries
its answer or its status, built in (qpcontact.cases.planted, planted
solutions, exact integer constructions, an exact-penalty theorem, the
Siconos files' documented solutions), and every returned answer is judged
against it by code in this module — never by :func:`qpcontact.certify`:

``certified``  ok, and the independent check agrees
``proved``     no solution exists, and the method proved it (a checked Farkas
               vector or ray) — the right answer for infeasible/unbounded cases
``inaccurate`` a point came back and was not certified (said so)
``failed``     nothing usable (said so), a documented exception, or a crash
``silent_wrong`` reported ok (or a proof) and the check disagrees: must be 0
``hung``       stopped at the time limit (the backend's own, or killed)

"auto" runs beside every installed method; each row keeps the whole solve's
wall time and flags it when it passes its time share (run.time_share).

Each solve runs in one of ``workers`` long-lived child processes, so a
backend that crashes or hangs costs one row, and the run goes on (the child
is replaced).  Outputs: ``stress.csv`` (one row per solve, written
atomically), ``stress.md`` (per method and family), ``stress.png`` (heat map).

An ok answer counts as agreeing when it is within ``min(max(100 tol, 10 κ
tol), 0.1)`` of the reference, component by component on its own scale (the
planted value, its natural size where the data were scaled, and the scale
qpcontact promises it on — docs/certificates.md — recomputed here by
definition), where ``tol`` is the requested accuracy and κ the judge's own
condition number of the reference, from the case data (never the answer's
own forward-error estimate, which is huge exactly where the answer has no
digit).  The cap says that ok means at least one correct digit.
QPs are judged on the optimal value and on feasibility, each row on its own
scale, at ``1000 tol``.  The rounded families (qpcontact.cases.rounded) have
references decided in rational arithmetic; docs/testing.md has the details.
"""

from .cases import FAMILIES, FULL, QUICK, StressConfig, build_case
from .judge import judge
from .report import plot_heatmap, summarize, write_markdown
from .run import run_stress, tasks

__all__ = ["FAMILIES", "StressConfig", "QUICK", "FULL", "build_case", "judge", "run_stress",
           "tasks", "summarize", "write_markdown", "plot_heatmap"]
