"""What a trace gives to read: its plot over the traced range, never past
a proved limit, and a frame without contacts too; a second-order trace's
pieces and states up to its stability limit, each state the frame's own
answer at its load (review 5a)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame

E, A, I = 2.1e8, 5e-3, 2e-5


def column_on_three_pads(W, a=1.0, h=6.0) -> Frame:
    """A column of height h on a base beam (100 times stiffer) resting on
    three pads (μ = 1), W on its top, the case "variable" a unit push."""
    fr = Frame(units=("kN", "m"))
    for n, x in (("L", -a), ("M", -0.3 * a), ("O", 0.0), ("R", a)):
        fr.add_node(n, x, 0.0)
    fr.add_node("T", 0.0, h)
    for i, j in (("L", "M"), ("M", "O"), ("O", "R")):
        fr.add_member(i, j, E * 1e2, A * 10, I * 1e2)
    fr.add_member("O", "T", E, A, I, name="column")
    for n in ("L", "M", "R"):
        fr.add_contact(n, normal=(0.0, 1.0), friction=1.0)
    fr.add_load("T", fy=-W)
    fr.add_load("T", fx=1.0, case="variable")
    return fr


def test_a_second_order_trace_plots_up_to_its_stability_limit_only(tmp_path):
    """Its path went on through unstable pieces past the limit (p_end 82
    against a limit of 10.1); the plot sampled up to p_end, where
    result_at(p) is a solve at a load the frame does not carry: it raised
    NoSolutionError ("it tips over about R") instead of drawing."""
    fr = column_on_three_pads(0.3 * np.pi ** 2 * E * I / (4 * 6.0 ** 2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")           # the column sways 0.26 m
        ft = fr.trace(second_order=True)
        assert ft.ended == "stability" and ft.ok, ft.message
        asked = []
        read = ft.result_at

        def result_at(p):
            asked.append(p)
            return read(p)

        ft.result_at = result_at
        ft.plot(tmp_path / "stability.png", "T")
        ft.plot(tmp_path / "asked_past.png", "T", p_max=ft.p_end)
    assert (tmp_path / "stability.png").stat().st_size > 1000
    assert max(asked) == ft.limit[1]


def test_the_trace_of_a_frame_without_contacts_plots(tmp_path):
    """A linear frame's trace (one interval, first or second order) had
    no plot range: AttributeError on 'NoContactPath'."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, 4.0)
    fr.add_member("A", "B", E, A, I)
    fr.add_support("A")
    fr.add_load("B", fy=-100.0, case="D")
    fr.add_load("B", fx=1.0, case="W")
    for name, ft in (("unbounded", fr.trace(constant={"D": 1.0}, variable="W")),
                     ("p_max", fr.trace(50.0, constant={"D": 1.0}, variable="W")),
                     ("second", fr.trace(50.0, constant={"D": 1.0}, variable="W",
                                         second_order=True))):
        ft.plot(tmp_path / f"{name}.png", "B")
        assert (tmp_path / f"{name}.png").stat().st_size > 1000, name


def test_a_second_order_traces_states_are_its_answers_up_to_its_limit():
    """Each state was the path's point on the end's stiffness, ok: past
    the limit too (a state at p = 46.2, ok, where no equilibrium exists
    from p = 13.7 on, proved), and below it off the answer at its load (a
    portal's joint rotation 5 % off).  The pieces stop at the limit; each
    state is the solve at its piece's middle."""
    fr = column_on_three_pads(0.3 * np.pi ** 2 * E * I / (4 * 6.0 ** 2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(second_order=True)
        assert ft.ended == "stability" and ft.ok, ft.message
        assert ft.p_end == ft.limit[0] and all(p < ft.limit[0] for p in ft.breakpoints)
        assert len(ft.states) == len(ft.intervals) == len(ft.events) + 1
        for (lo, hi), state in zip(ft.intervals, ft.states):
            alone = fr.solve(p=0.5 * (lo + hi), second_order=True)
            assert state.ok and state.second_order is not None, state.message
            np.testing.assert_allclose(state.displacements["T"], alone.displacements["T"],
                                       rtol=1e-12)
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 4.0, 0), ("C", 0, 6.0), ("D", 4.0, 6.0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "C", E, A, I)
    fr.add_member("B", "D", E, A, I)
    fr.add_member("C", "D", E, A, 10 * I)
    fr.add_support("A")
    fr.add_support("B")
    P = 0.3 * np.pi ** 2 * E * I / (4 * 36.0)
    fr.add_load("C", fy=-P, case="D")
    fr.add_load("D", fy=-P, case="D")
    fr.add_load("C", fx=1.0, case="W")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(400.0, constant={"D": 1.0}, variable="W", second_order=True)
        alone = fr.solve(combination={"D": 1.0, "W": 200.0}, second_order=True)
    assert ft.ok and ft.states[0].second_order is not None
    np.testing.assert_allclose(ft.states[0].displacements["C"], alone.displacements["C"],
                               rtol=1e-10)


def test_a_second_order_traces_answer_at_its_limit_is_its_last_equilibrium():
    """At the stability limit the solve sits on the limit: for the column
    on two pads it answered "failed", for the 20-storey tower NOT
    CONVERGED with its top 35 m the wrong way, which the plot drew as the
    curve's end.  There the answer is the path's last stable equilibrium,
    whose axial forces built the trace's stiffness: the sway by hand,
    H (tan kh − kh)/(W k) at H = W a / (h + (tan kh − kh)/k)."""
    from .test_second_order import E as E_, I as I_, column_on_pads

    h, a = 6.0, 1.0
    W = 0.3 * np.pi ** 2 * E_ * I_ / (4 * h ** 2)
    k = np.sqrt(W / (E_ * I_))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = column_on_pads(W, a, h).trace(second_order=True)
        assert ft.ended == "stability" and ft.ok, ft.message
        res = ft.result_at(ft.limit[0])
    H = ft.limit[0]
    assert H == pytest.approx(W * a / (h + (np.tan(k * h) - k * h) / k), rel=1e-9)
    assert res.ok and res.second_order["axial_error"] <= 1e-9, res.message
    assert res.displacements["T"][0] == pytest.approx(
        H * (np.tan(k * h) - k * h) / (W * k), rel=1e-6)
