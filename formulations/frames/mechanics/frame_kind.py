"""What the shared analysis needs to know of a kind of frame.

The plane and the space frame are each one model (the data: nodes, members,
supports, contacts, loads) whose analysis is functions taking the model —
:mod:`.solving`, :mod:`.tracing`, :mod:`.tresca`, :mod:`.no_equilibrium`,
:mod:`.friction_export`.  Where the two kinds differ (how a contact problem's
answer becomes a result, which way a contact slides, what "auto" tries
first), those functions ask the model's ``kind``, a :class:`FrameKind` that
names the kind's own functions: ``frame.kind.result_from_z(frame, z, ...)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class FrameKind:
    """The functions and facts of one kind of frame the shared analysis
    calls (each takes the frame first):

    - ``routes``: the frame's own method names besides the registry's;
    - ``result_type``: its result class (a combination that cannot be
      carried gets an empty one, ``ok`` False);
    - ``solve_one(frame, p, method, accuracy, raise_on_failure, combination,
      built, options)``: one combination, without the large-displacement
      warning (the space frame's chooses the cone first);
    - ``active_set(frame, b, combo)``: "auto"'s first route, (z, state sets)
      or None; None where the kind has none;
    - ``result_from_z(frame, z, combo, route, b=None, lcp=None, tol=1e-9)``:
      the checked result for the contact LCP's answer z;
    - ``release_directions(frame, b)``: each contact's normal and tangents
      as columns over the dofs, and the friction coefficients;
    - ``support_keys(frame)``: each contact's key in ``result.supports``;
    - ``collapse_words(frame, proof, fric, carrying)``: how the frame fails,
      read off a Farkas vector;
    - ``slide_words(frame, ci, t)``: which way contact ci slides;
    - ``member_under(frame, name, N̄, along)``: the member's chain(s)
      under N(x) where its loads in the combination ``along`` make N vary
      along it (:mod:`.varying_axial`; a space member's two bending
      planes), else None.
    """

    name: str
    routes: tuple
    result_type: type
    solve_one: Callable
    result_from_z: Callable
    release_directions: Callable
    support_keys: Callable
    collapse_words: Callable
    slide_words: Callable
    active_set: Callable | None = None
    member_under: Callable | None = None
