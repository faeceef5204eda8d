""""auto" on frictional problems records where its time budget went: each
link's seconds beside what it tried (``stats["auto_link_times"]``, read by
benchmarks/friction.py --dense for each route's share)."""

from __future__ import annotations

import qpcontact
from qpcontact.cases.piles import disc_pile, sphere_pile


def _links_agree(sol):
    tried = [name for name, _, _ in sol.stats["auto_tried"]]
    links = sol.stats["auto_link_times"]
    assert [name for name, _ in links] == tried, (links, tried)
    assert all(seconds > 0 for _, seconds in links), links
    # the links ran one after the other inside the one budget
    assert sum(seconds for _, seconds in links) <= sol.stats["total_time"] + 1e-9
    return tried


def test_auto_records_each_links_time_in_3d():
    """A small 3-D sphere pile: De Saxcé's fixed point first (below 500
    contacts), then whatever it takes; every link that ran has its time."""
    p = sphere_pile(40, seed=1).problem
    sol = qpcontact.solve(p, "auto", accuracy=1e-8)
    assert sol.ok, sol.message
    tried = _links_agree(sol)
    assert tried[0] == "desaxce-fp" and tried[-1] == sol.method


def test_auto_records_each_links_time_when_a_link_runs_out_of_its_share():
    """A 2-D compact pile above 200 contacts with a budget too short for its
    first link: the links' times still add up to no more than the run's."""
    p = disc_pile(300, seed=0, agitation=0.1, polydispersity=0.005).problem
    sol = qpcontact.solve(p, "auto", accuracy=1e-14, time_limit=0.5)
    tried = _links_agree(sol)
    assert tried[0] == "nsgs-newton"
