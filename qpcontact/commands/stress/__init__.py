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

Each solve runs in one of ``workers`` long-lived child processes, so a
backend that crashes or hangs costs one row, and the run goes on (the child
is replaced).  Outputs: ``stress.csv`` (one row per solve, written
atomically), ``stress.md`` (per method and family), ``stress.png`` (heat map).

An answer counts as agreeing when it is within ``max(100 tol, 10 f)`` of the
planted one, component by component on its own scale (the planted value, its
natural size where the data were scaled, and the scale qpcontact promises it
on — docs/certificates.md — recomputed here by definition), where ``tol`` is the
requested accuracy and ``f`` the forward error the solution itself reports
(an ill-conditioned problem may move a certified answer that far, and the
solution says so; being farther than that is being wrong without saying so).
QPs are judged on the optimal value and on feasibility, each row on its own
scale, at ``1000 tol``.
"""

from .cases import FAMILIES, FULL, QUICK, StressConfig, build_case
from .judge import judge
from .report import plot_heatmap, summarize, write_markdown
from .run import run_stress, tasks

__all__ = ["FAMILIES", "StressConfig", "QUICK", "FULL", "build_case", "judge", "run_stress",
           "tasks", "summarize", "write_markdown", "plot_heatmap"]
