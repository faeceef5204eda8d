"""The saddle system of a frame on elastic contacts solved through its
condensed stiffness (a banded LU): the same solutions as the saddle matrix
itself solved by SuperLU, state set by state set (links holding, open and
slipping at random), the same states and forces as the active set on the
saddle matrix, no
factor where a state set leaves a mechanism, and the saddle matrix's own
LU kept where a contact is rigid or far stiffer than the frame."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

from formulations.frames import Frame
from formulations.frames.plane.frame import Contact
from formulations.frames.mechanics import banded_saddle, contact_lcp
from formulations.frames.plane import plane_assembly
from formulations.frames.plane import sparse_active_set as active_set

from .frame_cases import frictional_beam, stub_cantilever, three_bay_tower


def _state_set_matrix(b, kin, coef, partner):
    """The state set's saddle matrix as the sparse active set writes it:
    the basic system's rows where a link holds, static rows (κ, and κf on
    the normal link of a slipping tangent) where it does not."""
    S = b["S"].tolil()
    nf, kappa = b["nf"], b["kappa"]
    for l in np.flatnonzero(~kin):
        S[nf + l, :] = 0.0
        S[nf + l, nf + l] = kappa
        if coef[l]:
            S[nf + l, nf + partner[l]] = kappa * coef[l]
    return sp.csc_matrix(S)


@pytest.mark.parametrize("seed, inclined", [(0, False), (1, False), (2, True), (3, True)])
def test_condensed_solves_are_the_saddle_matrix_solves(seed, inclined):
    fr = frictional_beam(40, seed, inclined=inclined)
    b = fr.build()
    assert b["band"] is not None and b["band"]["bw"] <= banded_saddle.BAND_MAX
    ca = plane_assembly.contact_arrays(fr, b)
    nl = len(b["info"])
    has_t = ca["t_link"] >= 0
    partner = np.zeros(nl, int)
    partner[ca["t_link"][has_t]] = ca["n_link"][has_t]
    rng = np.random.default_rng(10 + seed)
    for _ in range(6):
        closed = rng.random(len(fr.contacts)) < 0.7
        closed[:3] = True                        # the beam stays supported
        slip = np.where(closed & has_t, rng.integers(-1, 2, len(fr.contacts)), 0)
        kin = np.zeros(nl, bool)
        kin[ca["n_link"][closed]] = True
        kin[ca["t_link"][closed & has_t & (slip == 0)]] = True
        coef = np.zeros(nl)
        sl = closed & has_t & (slip != 0)
        coef[ca["t_link"][sl]] = ca["mu"][sl] * slip[sl]
        S = _state_set_matrix(b, kin, coef, partner)
        ref = contact_lcp.regular_lu(S)
        lu = banded_saddle.factor(b["band"], kin, coef, partner)
        assert ref is not None and lu is not None
        rhs = rng.standard_normal((S.shape[0], 3))
        x, x_ref = lu.solve(rhs), ref.solve(rhs)
        assert np.abs(S @ x - rhs).max() <= 1e-12 * np.abs(rhs).max() * 1e3
        assert np.abs(x - x_ref).max() <= 1e-9 * np.abs(x_ref).max()
        one = lu.solve(rhs[:, 0])                # one right-hand side: refined once
        assert np.abs(one - x_ref[:, 0]).max() <= 1e-9 * np.abs(x_ref).max()
        assert np.abs(S @ one - rhs[:, 0]).max() <= 1e-12 * np.abs(rhs).max() * 1e3


@pytest.mark.parametrize("seed, friction", [(4, 0.1), (5, 0.3), (6, 0.5)])
def test_condensed_state_sets_agree_with_the_saddle_route(seed, friction, monkeypatch):
    """The whole active set, its state sets on the condensed banded LU
    against the same search on the saddle matrix's SuperLU: the same states
    and forces.  (Seed 4 slides 188 m on its few sticking contacts; Lemke's
    answer there is 7e-7 of the largest force off both, and seed 6 ends
    Lemke on a secondary ray: the LCP route is not the reference here.)"""
    monkeypatch.setattr(active_set, "LINK_SPACE_MAX", 0)
    calls = []
    real = banded_saddle.factor
    monkeypatch.setattr(banded_saddle, "factor",
                        lambda *a: calls.append(1) or real(*a))
    fr = frictional_beam(35, seed, friction=friction)
    band = fr.solve(method="active-set")
    assert band.ok and len(calls) > 1            # the basic system and state sets
    monkeypatch.setattr(banded_saddle, "CONDENSE_MAX", 0.0)
    saddle = fr.solve(method="active-set")
    assert saddle.ok
    assert {k: s.state for k, s in band.supports.items()} == \
        {k: s.state for k, s in saddle.supports.items()}
    big = max(abs(s.normal) for s in saddle.supports.values())
    for k, s in saddle.supports.items():
        assert abs(band.supports[k].normal - s.normal) <= 1e-10 * big, k
        assert abs(band.supports[k].tangential - s.tangential) <= 1e-10 * big, k


def test_a_state_set_that_leaves_a_mechanism_has_no_factor():
    fr = frictional_beam(10, 0)
    b = fr.build()
    nl = len(b["info"])
    ca = plane_assembly.contact_arrays(fr, b)
    kin = np.zeros(nl, bool)                 # every contact open: the beam floats
    assert banded_saddle.factor(b["band"], kin, np.zeros(nl), np.zeros(nl, int)) is None
    kin[ca["n_link"][:1]] = True             # one contact and the pin: it still turns
    assert banded_saddle.factor(b["band"], kin, np.zeros(nl), np.zeros(nl, int)) is None
    kin[ca["n_link"][-1:]] = True            # two: it stands
    assert banded_saddle.factor(b["band"], kin, np.zeros(nl), np.zeros(nl, int)) is not None


def test_rigid_or_very_stiff_contacts_keep_the_saddle_matrix():
    assert frictional_beam(10, 0).build()["band"] is not None
    b = frictional_beam(10, 0, stiffness=1e14).build()     # 1e7 times the beam's largest stiffness
    assert b["band"] is None and isinstance(b["lu"], contact_lcp.ScaledLU)
    fr = Frame()
    for k in range(5):
        fr.add_node(f"N{k}", 3.0 * k, 0.0)
    for k in range(4):
        fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.32, 0.017)
    fr.add_support("N0", fix=("ux",))
    for k in (0, 2, 4):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0))          # rigid
    assert fr.build()["band"] is None


@pytest.mark.parametrize("k", [1e2, 1e4, 1e7, 1e9, 1e11, 1e13])
def test_a_cantilever_on_a_spring_beside_a_stub_by_hand(k, monkeypatch):
    """The frame on which the saddle matrix's banded LU was dropped (a 1 cm
    stub at a cantilever's tip on a contact, the load straight into it),
    here on an elastic contact of stiffness k from soft to 100 times the
    stub's own EA/L: the contact force is the hand statics' of a spring in
    series with the cantilever, X = P kδ/(1 + kδ), δ = L³/(3EI), to 1e-11 — by the
    condensed banded LU where k <= CONDENSE_MAX κ, by SuperLU beyond."""
    fr = stub_cantilever(k)
    b = fr.build()
    assert (b["band"] is not None) == (k <= banded_saddle.CONDENSE_MAX * b["kappa"])
    delta = 10.01 ** 3 / (3 * 30e6 * 0.02)
    r = fr.solve()
    assert r.ok and r.supports["T"].state == "closed", r.message
    # (the saddle matrix's SuperLU is within 1.2e-13 at k = 1e9, the
    # condensed LU with its refinement step 1.3e-12)
    assert abs(r.supports["T"].normal - 10.0 * k * delta / (1 + k * delta)) <= 1e-11 * 10.0
    u = -10.0 * delta / (1 + k * delta)
    assert abs(r.displacements["T"][1] - u) <= 1e-10 * abs(u)


@pytest.mark.parametrize("storeys", [14, 20])
def test_a_wide_band_basic_system_by_cholesky_solves_the_saddle_matrix(storeys):
    """A tower (its own order 200+ dofs wide, reordered to a band wider than
    NARROW; 14 storeys or more: REORDER_MIN): its basic system by banded Cholesky solves the explicitly
    written saddle matrix as SuperLU does, one right-hand side and many;
    the link rows alone (R's route: forward solves through G) are those
    rows of the whole solve; R from them is SuperLU's R."""
    b = three_bay_tower(storeys)[0].build()
    lu, nf, nl = b["lu"], b["nf"], len(b["info"])
    assert b["band"]["bw"] > banded_saddle.NARROW and lu.piv is None   # Cholesky
    S = b["S"]                                   # the saddle matrix, made from the blocks
    ref = contact_lcp.regular_lu(S)
    rng = np.random.default_rng(storeys)
    rhs = rng.standard_normal((nf + nl, 5))
    rhs[:nf, :2] = 0.0                           # R's columns: no load on the dofs
    x, x_ref = lu.solve(rhs), ref.solve(rhs)
    assert np.abs(x - x_ref).max() <= 1e-9 * np.abs(x_ref).max()
    one = lu.solve(rhs[:, 3])
    assert np.abs(S @ one - rhs[:, 3]).max() <= 1e-12 * np.abs(rhs).max() * 1e3
    assert np.abs(lu.link_rows(rhs, nl) - x_ref[nf:]).max() <= 1e-9 * np.abs(x_ref[nf:]).max()
    unit = np.zeros((nf + nl, nl))
    unit[nf:] = b["kappa"] * np.eye(nl)
    R_ref = -b["kappa"] * ref.solve(unit)[nf:]
    R = b["R_solve"]
    assert np.abs(R - 0.5 * (R_ref + R_ref.T)).max() <= 1e-9 * np.abs(R_ref).max()


def test_a_wide_band_mechanism_has_no_cholesky_factor():
    """A tower with a node on two collinear pin-ended bars (free across
    them to first order) is a mechanism with every contact holding: its
    banded Cholesky has no factor (dpbtrf finds a pivot not positive), and the frame
    is refused with the saddle matrix's words; without the node it stands
    on a Cholesky factor."""
    fr = three_bay_tower(14)[0]                  # 219 free dofs: reordered (REORDER_MIN)
    b = fr.build()
    nl = len(b["info"])
    assert banded_saddle.factor(b["band"], np.ones(nl, bool), np.zeros(nl),
                                np.zeros(nl, int)).piv is None
    fr.add_node("P", 15.0, 12.25)                # midway between N4_3 and N3_2
    fr.add_member("N4_3", "P", 210e6, 1e-3, 1e-5, hinge_i=True, hinge_j=True)
    fr.add_member("P", "N3_2", 210e6, 1e-3, 1e-5, hinge_i=True, hinge_j=True)
    fr.add_spring("P", rz=1e3)
    with pytest.raises(InvalidProblemError, match="node P is free in ux, uy"):
        fr.build()
    calls = []
    real = banded_saddle.factor
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(banded_saddle, "factor", lambda *a: calls.append(real(*a)) or calls[-1])
        with pytest.raises(InvalidProblemError):
            fr.build()
    assert len(calls) == 1 and calls[0] is None


def test_a_contact_of_a_node_with_itself_carries_nothing_and_leaves_r_as_the_saddle_matrix():
    """A contact between a node and itself (add_contact refuses it; made
    here around it, as a degenerate pair the kernels must still handle)
    puts its two entries of H on one dof, which cancel: its links never
    move, and on an elastic contact with gap 0 its force is k·0 = 0 whatever
    the frame does (by hand).  R's forward solves (link_rows, through G)
    must sum the two entries as H's products do: R is the dense solve of
    the saddle matrix written from the blocks (numpy.linalg, not the banded
    route)."""
    fr = three_bay_tower(14)[0]
    with pytest.raises(InvalidProblemError, match="the contact's own node"):
        fr.add_contact("N7_1", normal=(0.3, 1.0), stiffness=1e5, other="N7_1", friction=0.5)
    n = np.array([0.3, 1.0]) / np.hypot(0.3, 1.0)
    fr.contacts.append(Contact("N7_1", n, 0.5, 0.0, 1e5, "N7_1"))
    b = fr.build()
    assert b["band"]["bw"] > banded_saddle.NARROW and b["lu"].piv is None   # Cholesky: G
    nf, nl, kappa = b["nf"], len(b["info"]), b["kappa"]
    unit = np.zeros((nf + nl, nl))
    unit[nf:] = kappa * np.eye(nl)
    R_ref = -kappa * np.linalg.solve(contact_lcp.saddle_matrix(b).toarray(), unit)[nf:]
    assert np.abs(b["R_solve"] - 0.5 * (R_ref + R_ref.T)).max() <= 1e-9 * np.abs(R_ref).max()
    r = fr.solve(combination={"constant": 1.0, "variable": 1.3})
    own = r.supports[list(r.supports)[-1]]
    assert r.ok and own.normal == 0.0 and own.tangential == 0.0, own
