r"""Plane frames on unilateral supports with Coulomb friction (P3, Osipova,
Popov & Lovtsov): the displacement-method LCP, solved by Lemke, by the exact SPD
methods when there is no friction, or by a Tresca fixed point on QP backends;
and the increasing-load algorithm (``"trace"``).

Units: the user's, consistent (e.g. kN, m, kN·m, kN/m²).  Nothing is converted.

Sign conventions
----------------
Global axes x (right), y (up), rotations counterclockwise.  Nodal loads
(fx, fy, mz) and distributed loads wx, wy (global, per unit length) are
positive along the axes.  A contact at a node has a unit normal n pointing from
the support into the structure (the direction the support pushes) and the
tangent t = (n_y, -n_x).  X_n >= 0 is the normal force the support exerts on
the node (compression), X_t the tangential (friction) force on the node along
t (n turned clockwise: under a beam, n = (0, 1) and t = (1, 0)).  The gap
opening is Z_n = g + n·(u_node - u_other) (+ X_n/k for an elastic contact), >= 0; the slip is Δ_t = t·(u_node - u_other) (+ X_t/k).  For a pair
(``other=``) the forces act on ``other`` with the opposite sign.  Member end
forces are in member axes (x from node i to j); diagrams: axial N tension
positive, bending moment M positive when it compresses the member's +y fibre
(sagging for a beam drawn left to right), shear V = dM/dx.

The LCP (unit dislocations)
---------------------------
K u = F + H X: the frame's stiffness on its free degrees of freedom, the loads,
and the contact links' forces X mapped by H (columns n and t at the contact's
node, minus at ``other``).  The links' relative displacements are Δ = H'u.
The contact stiffness matrix R and load vector R_F of P3's *basic system*
(every link fixed) are read from the saddle-point system

    [K  H] [u]   [F]
    [H' 0] [y] = [Δ],     X = -y = R Δ + R_F,

for unit dislocations Δ = e_j (columns of R) and for the loads with Δ = 0
(R_F).  We use unit dislocations through this system rather than condensing
K onto the links because K alone is singular whenever the frame relies on its
contacts for stability (a beam resting on unilateral supports only), while the
basic system is not.  R is symmetric positive definite.  Elastic contacts add
their flexibility: R ← (I + R D)⁻¹ R, R_F ← (I + R D)⁻¹ R_F, D = diag(1/k).

Unknowns per contact: z = (Z_n, Z⁺, Z⁻) with Δ_n = Z_n - g, Δ_t = Z⁺ - Z⁻, and
w = (X_n, f X_n + X_t, f X_n - X_t): the normal pair (force / opening) and the
two tangential reserves against the two slip parts — the holonomic
(path-independent) Coulomb law of P3: total slip against total force, with
no history.  States: separated (X_n = 0), closed (a frictionless contact
carrying load: it slides freely), stick (Z± = 0, |X_t| <= f X_n), slip+
(Z⁺ > 0, X_t = -f X_n), slip- (Z⁻ > 0, X_t = f X_n); each decided on the
component's own scale (STATE_RTOL).  w = M z + q with M
nonsymmetric: Lemke.  Loads are F = F_c + p F_v (constant and variable), so
q = q_c + p q_v: a ParametricLCP for P3's increasing-load algorithm.

Only the effects the model calls for: contacts with f = 0 build no tangential
link at all, and a frame without friction builds the normal-only LCP
(M = R_nn, symmetric positive definite), solved by the exact SPD methods.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from qpcontact.certify import ComponentScales, certify_lcp
from qpcontact.errors import InvalidOptionError, InvalidProblemError, SolverFailedError
from qpcontact.methods.active_set import check_options
from qpcontact.problems import ParametricLCP
from qpcontact.solve import solve

__all__ = ["Frame", "FrameResult", "FrameTrace", "FrameEvent", "SupportResult", "STATES",
           "EQUILIBRIUM_RTOL"]

STATES = ("separated", "closed", "stick", "slip+", "slip-")
#: A normal force or slip below STATE_RTOL of its own componentwise scale is zero
#: when the support's state is named.
STATE_RTOL = 1e-9
DOFS = ("ux", "uy", "rz")
#: Global equilibrium residual (relative to the loads) above which a result is flagged.
EQUILIBRIUM_RTOL = 1e-8
#: Entries of the contact stiffness R below R_ROUNDING x (largest stiffness
#: term) are rounding noise of the basic-system solve and are set to zero.
R_ROUNDING = 256 * np.finfo(float).eps


@dataclass
class _Member:
    name: str
    i: str
    j: str
    E: float
    A: float
    I: float
    hinge_i: bool
    hinge_j: bool
    loads: list = field(default_factory=list)   # (wx, wy, kind) global per length


@dataclass
class _Contact:
    node: str
    normal: np.ndarray
    friction: float
    gap: float
    stiffness: float | None
    other: str | None


@dataclass
class SupportResult:
    """A contact's outcome: ``state`` in STATES, normal force X_n (>= 0,
    compression), tangential force X_t (along t = (n_y, -n_x)), gap opening
    Z_n and slip Δ_t (user's units)."""

    state: str
    normal: float
    tangential: float
    opening: float
    slip: float


@dataclass
class FrameResult:
    """One analysed load combination: support states and forces, nodal
    displacements (ux, uy, rz), member end forces (member axes: N, V, M at i,
    then at j), bilateral reactions, and the checks.

    ``ok`` is True only when the LCP certificate meets the tolerance and the
    global equilibrium residual is below EQUILIBRIUM_RTOL; ``route`` says
    which method produced the contact forces.
    """

    p: float
    supports: dict
    displacements: dict
    member_forces: dict
    reactions: dict
    equilibrium_residual: float
    lcp_error: float
    route: str
    ok: bool
    message: str
    frame: "Frame" = field(repr=False, default=None)
    _u: np.ndarray = field(repr=False, default=None)

    def diagram(self, member: str, points: int = 21):
        """(x, N, V, M) along a member, x from node i (member axes)."""
        return self.frame._diagram(self, member, points)

    def plot(self, path, scale: float | None = None, title: str = "") -> str:
        """Deformed shape with support states, and the bending-moment diagram (PNG)."""
        return self.frame._plot_result(self, path, scale, title)


@dataclass
class FrameEvent:
    """A breakpoint of the trace: at load parameter ``p`` the supports in
    ``changes`` go from one state to another ({support: (before, after)})."""

    p: float
    changes: dict

    def __str__(self) -> str:
        return "; ".join(f"{k}: {a} \u2192 {b}" for k, (a, b) in self.changes.items())


@dataclass
class FrameTrace:
    """The increasing-load analysis (P3).

    ``breakpoints``: the values of p where some support changes state, with
    ``events`` saying which and how ("S3: stick → slip-"); ``intervals``
    [(p_start, p_end)] between them and ``states`` (a FrameResult at the
    middle of each); ``ended``: why the trace stopped — "p_max" (reached),
    "unbounded" (no support changes state again, p_max = inf), "collapse"
    (no equilibrium exists beyond the end: proved, and ``message`` says how
    the frame fails), "fold" (equilibria may exist beyond but none continues
    this path), "breakdown", "max_pieces" (see docs/frames.md); ``ok`` is True
    when every traced piece passed the LCP certificate and the equilibrium
    check at its start, middle and end, and the ending is proved.
    ``result_at(p)`` analyses any p inside the traced range.
    """

    breakpoints: np.ndarray
    states: list
    intervals: list
    events: list
    ended: str
    message: str
    ok: bool
    trace: object = field(repr=False, default=None)
    frame: "Frame" = field(repr=False, default=None)
    _built: dict = field(repr=False, default=None)   # the frame's assembly, reused by result_at

    @property
    def p_end(self) -> float:
        """Where the traced range ends (inf on an unbounded last interval)."""
        return self.intervals[-1][1] if self.intervals else 0.0

    def result_at(self, p: float) -> FrameResult:
        return self.frame._result_from_z(self.trace.z_at(p), p, "trace", b=self._built)

    def plot(self, path, node: str, dof: str = "ux", p_max: float | None = None) -> str:
        """Load parameter against a displacement of ``node``, breakpoints
        labelled with their events (PNG).  Default range: the traced one (an
        unbounded last interval: 1.5 x the last breakpoint)."""
        return self.frame._plot_trace(self, path, node, dof, p_max)


def _beam_k(E, A, I, L):
    """Local 6x6 stiffness of a 2-D Euler-Bernoulli frame element."""
    a, b, c, d = E * A / L, 12 * E * I / L ** 3, 6 * E * I / L ** 2, 4 * E * I / L
    return np.array([[a, 0, 0, -a, 0, 0],
                     [0, b, c, 0, -b, c],
                     [0, c, d, 0, -c, d / 2],
                     [-a, 0, 0, a, 0, 0],
                     [0, -b, -c, 0, b, -c],
                     [0, c, d / 2, 0, -c, d]])


class Frame:
    """A plane frame with bilateral supports and unilateral, possibly
    frictional, contacts (module docstring: units and sign conventions)."""

    def __init__(self):
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, _Member] = {}
        self.fixed: dict[str, set] = {}
        self.contacts: list[_Contact] = []
        self.nodal_loads: list = []   # (node, fx, fy, mz, kind)

    # -- model ------------------------------------------------------------
    def add_node(self, name: str, x: float, y: float) -> str:
        if name in self.nodes:
            raise InvalidProblemError(f"node {name!r} exists already")
        self.nodes[name] = np.array([float(x), float(y)])
        return name

    def _node(self, name):
        if name not in self.nodes:
            raise InvalidProblemError(f"no node named {name!r}; nodes: {list(self.nodes)}")
        return name

    def add_beam(self, i: str, j: str, E: float, A: float, I: float, *, name: str | None = None,
                 hinge_i: bool = False, hinge_j: bool = False) -> str:
        """A frame member from node i to node j (E, A, I in consistent units);
        ``hinge_i``/``hinge_j`` release the end moment.  Returns its name."""
        self._node(i), self._node(j)
        if i == j:
            raise InvalidProblemError("a member needs two different nodes")
        for v, nm in ((E, "E"), (A, "A"), (I, "I")):
            if not (np.isfinite(v) and v > 0):
                raise InvalidProblemError(f"member {i}-{j}: {nm} must be positive; got {v}")
        name = name or f"M{len(self.members) + 1}"
        if name in self.members:
            raise InvalidProblemError(f"member {name!r} exists already")
        self.members[name] = _Member(name, i, j, float(E), float(A), float(I), hinge_i, hinge_j)
        return name

    def add_support(self, node: str, fix=("ux", "uy", "rz")) -> None:
        """Bilateral support: the listed degrees of freedom are fixed."""
        self._node(node)
        fix = (fix,) if isinstance(fix, str) else tuple(fix)
        bad = [d for d in fix if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {bad}")
        self.fixed.setdefault(node, set()).update(fix)

    def add_contact(self, node: str, normal=(0.0, 1.0), friction: float = 0.0, gap: float = 0.0,
                    stiffness: float | None = None, other: str | None = None) -> int:
        """A unilateral support (or node-to-node contact pair with ``other``):
        normal from the support into the structure, Coulomb coefficient
        ``friction`` (0: no tangential link), initial ``gap`` >= 0, rigid unless
        ``stiffness`` is given.  Returns the contact's index."""
        self._node(node)
        if other is not None:
            self._node(other)
        n = np.array(normal, float)
        if n.shape != (2,) or not np.isfinite(n).all() or np.linalg.norm(n) == 0:
            raise InvalidProblemError(f"contact at {node!r}: normal must be a nonzero 2-vector")
        if not (friction >= 0 and np.isfinite(friction)):
            raise InvalidProblemError(f"contact at {node!r}: friction must be >= 0")
        if not (gap >= 0 and np.isfinite(gap)):
            raise InvalidProblemError(f"contact at {node!r}: gap must be >= 0 (no initial overlap)")
        if stiffness is not None and not stiffness > 0:
            raise InvalidProblemError(f"contact at {node!r}: stiffness must be > 0 or None (rigid)")
        self.contacts.append(_Contact(node, n / np.linalg.norm(n), float(friction), float(gap),
                                      stiffness, other))
        return len(self.contacts) - 1

    def add_load(self, node: str, fx: float = 0.0, fy: float = 0.0, mz: float = 0.0,
                 kind: str = "constant") -> None:
        """Nodal force and moment, ``kind`` "constant" or "variable" (scaled by p)."""
        self._node(node)
        self._kind(kind)
        self.nodal_loads.append((node, float(fx), float(fy), float(mz), kind))

    def add_distributed_load(self, member: str, wx: float = 0.0, wy: float = 0.0,
                             kind: str = "constant") -> None:
        """Uniform load on a member, global components per unit length."""
        if member not in self.members:
            raise InvalidProblemError(f"no member named {member!r}; members: {list(self.members)}")
        self._kind(kind)
        self.members[member].loads.append((float(wx), float(wy), kind))

    @staticmethod
    def _kind(kind):
        if kind not in ("constant", "variable"):
            raise InvalidProblemError(f"load kind must be 'constant' or 'variable', not {kind!r}")

    @property
    def has_friction(self) -> bool:
        return any(c.friction > 0 for c in self.contacts)

    # -- assembly -----------------------------------------------------------
    def _geometry(self, m: _Member):
        d = self.nodes[m.j] - self.nodes[m.i]
        L = float(np.hypot(*d))
        if L == 0:
            raise InvalidProblemError(f"member {m.name}: nodes {m.i} and {m.j} coincide")
        c, s = d / L
        T3 = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1.0]])
        T = scipy.linalg.block_diag(T3, T3)
        return L, c, s, T

    def _member_local(self, m: _Member, kind: str | None):
        """Local stiffness and fixed-end forces (loads of ``kind``, or all) with hinges condensed."""
        L, c, s, T = self._geometry(m)
        k = _beam_k(m.E, m.A, m.I, L)
        fe = np.zeros(6)
        for wx, wy, knd in m.loads:
            if kind is not None and knd != kind:
                continue
            wxl, wyl = c * wx + s * wy, -s * wx + c * wy
            fe += np.array([wxl * L / 2, wyl * L / 2, wyl * L ** 2 / 12,
                            wxl * L / 2, wyl * L / 2, -wyl * L ** 2 / 12])
        for r, hinged in ((2, m.hinge_i), (5, m.hinge_j)):
            if hinged:
                kr = k[:, r].copy()
                fe = fe - kr * fe[r] / k[r, r]
                k = k - np.outer(kr, kr) / k[r, r]
                k[r, :] = 0.0
                k[:, r] = 0.0
        return k, fe, T, L

    def _assemble(self):
        names = list(self.nodes)
        idx = {nm: 3 * i for i, nm in enumerate(names)}
        N = 3 * len(names)
        K = np.zeros((N, N))
        Fc, Fv = np.zeros(N), np.zeros(N)
        for m in self.members.values():
            k, _, T, _ = self._member_local(m, None)
            dofs = np.r_[idx[m.i]:idx[m.i] + 3, idx[m.j]:idx[m.j] + 3]
            K[np.ix_(dofs, dofs)] += T.T @ k @ T
            for kind, F in (("constant", Fc), ("variable", Fv)):
                _, fe, _, _ = self._member_local(m, kind)
                F[dofs] += T.T @ fe
        for node, fx, fy, mz, kind in self.nodal_loads:
            (Fc if kind == "constant" else Fv)[idx[node]:idx[node] + 3] += (fx, fy, mz)
        fixed = np.zeros(N, bool)
        for node, dofs in self.fixed.items():
            for d in dofs:
                fixed[idx[node] + DOFS.index(d)] = True
        # a rotation no member resists (only hinged ends, or no member) is not a dof
        fixed |= np.isclose(np.diag(K), 0.0) & (np.arange(N) % 3 == 2)
        return names, idx, K, Fc, Fv, fixed

    def _links(self, idx, N):
        """H (N x links) and, per link: contact index, kind 'n'/'t'."""
        cols, info = [], []
        for ci, c in enumerate(self.contacts):
            t = np.array([c.normal[1], -c.normal[0]])
            for kind, vec in (("n", c.normal), ("t", t)):
                if kind == "t" and c.friction == 0:
                    continue  # no tangential link without friction
                h = np.zeros(N)
                h[idx[c.node]:idx[c.node] + 2] += vec
                if c.other is not None:
                    h[idx[c.other]:idx[c.other] + 2] -= vec
                cols.append(h)
                info.append((ci, kind))
        return (np.array(cols).T if cols else np.zeros((N, 0))), info

    def build(self):
        """Assemble K, the links, and R, R_F for constant and variable loads.

        Returns a dict with everything the LCP and the results need.
        """
        if not self.contacts:
            raise InvalidProblemError("the frame has no contacts: it is a linear problem; "
                                      "add_contact() defines the unilateral supports")
        names, idx, K, Fc, Fv, fixed = self._assemble()
        N = K.shape[0]
        H, info = self._links(idx, N)
        free = np.flatnonzero(~fixed)
        Kf = K[np.ix_(free, free)]
        # The links enter scaled by a typical stiffness kappa, so that the saddle
        # matrix is balanced (steel in N and m has K ~ 1e8 against H ~ 1) and
        # the singularity test below is meaningful: X = -kappa y.
        kappa = float(np.max(np.abs(np.diag(Kf)))) if free.size else 1.0
        Hf = kappa * H[free]
        nl = Hf.shape[1]
        S = np.block([[Kf, Hf], [Hf.T, np.zeros((nl, nl))]])
        try:
            with warnings.catch_warnings():  # singularity is diagnosed below, with advice
                warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                lu = scipy.linalg.lu_factor(S, check_finite=False)
        except (np.linalg.LinAlgError, ValueError):
            lu = None
        piv = np.abs(np.diag(lu[0])) if lu is not None else np.zeros(1)
        if lu is None or piv.min() <= 1e-13 * piv.max():
            raise InvalidProblemError(self._mechanism_message(S, free, names, Kf.shape[0]))
        nf = free.size
        rhs = np.zeros((nf + nl, nl + 2))
        rhs[nf:, :nl] = kappa * np.eye(nl)
        rhs[:nf, nl] = Fc[free]
        rhs[:nf, nl + 1] = Fv[free]
        sol = scipy.linalg.lu_solve(lu, rhs, check_finite=False)
        R = -kappa * sol[nf:, :nl]
        R = 0.5 * (R + R.T)
        # R's entries are sums of terms of size kappa (the stiffness), so each
        # carries a rounding error of a few eps * kappa.  An entry that small is
        # zero: a dislocation that a rigid motion of the frame absorbs (a portal
        # on two pins lifted at one base) costs no force, and noise in its place
        # would turn "this link has no effect" into a random sign — which the
        # trace's collapse proof (a Farkas vector, M'y <= 0 column by column)
        # and the support states would read as data.
        R[np.abs(R) <= R_ROUNDING * kappa] = 0.0
        RFc, RFv = -kappa * sol[nf:, nl], -kappa * sol[nf:, nl + 1]
        flex = np.array([0.0 if self.contacts[ci].stiffness is None else 1.0 / self.contacts[ci].stiffness
                         for ci, _ in info])
        if np.any(flex > 0):
            E = np.eye(nl) + R * flex[None, :]
            R = np.linalg.solve(E, R)
            R = 0.5 * (R + R.T)
            RFc, RFv = np.linalg.solve(E, RFc), np.linalg.solve(E, RFv)
        return dict(names=names, idx=idx, K=K, Fc=Fc, Fv=Fv, fixed=fixed, free=free, H=H,
                    info=info, lu=lu, R=R, RFc=RFc, RFv=RFv, flex=flex, nf=nf, kappa=kappa)

    @staticmethod
    def _mechanism_message(S, free, names, nf) -> str:
        """Name the free motion of a singular basic system (its null vector)."""
        try:
            null = scipy.linalg.null_space(S, rcond=1e-12)
        except (ValueError, np.linalg.LinAlgError):
            null = np.zeros((S.shape[0], 0))
        if null.shape[1] == 0:
            return ("the basic system (every contact link fixed) is singular: check supports, "
                    "hinges and that no two contacts constrain the same displacement")
        v = null[:nf, 0]
        if np.max(np.abs(v)) <= 1e-9 * np.max(np.abs(null[:, 0])):
            return ("two or more contact links constrain the same displacement (redundant links): "
                    "remove one of them")
        order = np.argsort(-np.abs(v))[:3]
        moves = ", ".join(f"{names[free[i] // 3]} {DOFS[free[i] % 3]}" for i in order
                          if abs(v[i]) > 0.1 * abs(v[order[0]]))
        return (f"the frame is a mechanism even with every contact closed: it can move freely "
                f"({moves} move together); add supports, contacts or friction that prevent it")

    # -- the LCP --------------------------------------------------------------
    def _layout(self, b):
        """Per contact: the link positions of n and t, and z positions."""
        pos = {}
        for li, (ci, kind) in enumerate(b["info"]):
            pos.setdefault(ci, {})[kind] = li
        return pos

    def lcp(self, b=None):
        """The contact LCP as (M, q_constant, q_variable, P, g) with z -> link
        displacement Δ = P z - g: z = (Z_n per contact, then Z⁺, Z⁻ per
        frictional contact)."""
        b = b or self.build()
        pos = self._layout(b)
        nc = len(self.contacts)
        fric = [ci for ci in range(nc) if "t" in pos[ci]]
        nl = len(b["info"])
        nz = nc + 2 * len(fric)
        P = np.zeros((nl, nz))
        g = np.zeros(nl)
        for ci in range(nc):
            P[pos[ci]["n"], ci] = 1.0
            g[pos[ci]["n"]] = self.contacts[ci].gap
        for k, ci in enumerate(fric):
            P[pos[ci]["t"], nc + 2 * k] = 1.0
            P[pos[ci]["t"], nc + 2 * k + 1] = -1.0
        # rows of w as combinations of the link forces X: X_n; f X_n + X_t; f X_n - X_t
        W = np.zeros((nz, nl))
        for ci in range(nc):
            W[ci, pos[ci]["n"]] = 1.0
        for k, ci in enumerate(fric):
            f = self.contacts[ci].friction
            W[nc + 2 * k, pos[ci]["n"]] = f
            W[nc + 2 * k, pos[ci]["t"]] = 1.0
            W[nc + 2 * k + 1, pos[ci]["n"]] = f
            W[nc + 2 * k + 1, pos[ci]["t"]] = -1.0
        R = b["R"]
        M = W @ R @ P
        qc = W @ (b["RFc"] - R @ g)
        qv = W @ b["RFv"]
        if not fric:
            M = 0.5 * (M + M.T)  # = R_nn exactly; remove rounding asymmetry
        return M, qc, qv, P, g, fric

    # -- solving ------------------------------------------------------------------
    def solve(self, p: float = 1.0, method: str = "auto", accuracy="high",
              raise_on_failure: bool = False, **options) -> FrameResult:
        """Analyse the combination constant + p·variable loads.

        ``method``: "auto" (frictionless: the exact SPD methods; with friction:
        "lemke"), any registered LCP method or QP backend name (frictionless),
        "lemke", or "tresca" (with friction: a fixed point of convex QPs with
        Tresca bounds f·X_n from the previous iterate, on QP backend
        ``options.get('qp_method', 'auto')``, stopped on the full LCP
        certificate; falls back to Lemke when it does not converge).
        """
        b = self.build()
        M, qc, qv, P, g, fric = self.lcp(b)
        # q's terms are the constant and the variable load's sizes: a force that is
        # their difference is judged against them, not against its own rounding
        lcp = ParametricLCP(M, qc, qv).at(p)
        from qpcontact.accuracy import resolve_accuracy

        _, tol = resolve_accuracy(accuracy)
        if method == "tresca":
            if not fric:
                raise InvalidOptionError("'tresca' is for frictional frames; this one has no friction")
            z, route = self._tresca(b, lcp, P, g, fric, p, tol, accuracy, options)
        else:
            if fric and method not in ("auto", "lemke"):
                raise InvalidOptionError(
                    f"with friction the LCP is not symmetric; use method='lemke' or 'tresca', "
                    f"not {method!r}")
            if method == "auto":
                sol = (solve(lcp, method="lemke", accuracy=accuracy) if fric
                       else self._frictionless_auto(lcp, accuracy))
            else:
                sol = solve(lcp, method=method, accuracy=accuracy, **options)
            z, route = sol.z, sol.method
            if z is None:
                raise SolverFailedError(
                    f"frame: {sol.method} found no contact state ({sol.message}); a frame whose "
                    "load cannot be carried by its supports (it would lift off or slide away) "
                    "has none")
        res = self._result_from_z(z, p, route, b=b, lcp=lcp, tol=tol)
        if raise_on_failure and not res.ok:
            raise SolverFailedError(f"frame: {res.message}")
        return res

    @staticmethod
    def _frictionless_auto(lcp, accuracy):
        """No friction: M = R_nn is symmetric.  Positive definite (the frame is
        stable without its contacts): the exact SPD method "bpp"; only
        semidefinite (it rests on them): the QP backends in solve.AUTO_ORDER."""
        from qpcontact.methods import methods
        from qpcontact.solve import AUTO_ORDER

        if lcp.is_positive_definite:
            return solve(lcp, method="bpp", accuracy=accuracy)
        available = methods()
        best = None
        for name in AUTO_ORDER:
            m = available.get(name)
            if m is None or m.family == "pivoting":
                continue
            sol = solve(lcp, method=name, accuracy=accuracy)
            if sol.ok:
                return sol
            if best is None or sol.error < best.error:
                best = sol
        return best

    def solve_combinations(self, combinations: dict, **kw) -> dict:
        """Each named combination {name: p} solved on its own — its own contact
        states, reactions and checks (no state carried over from another)."""
        return {name: self.solve(p=p, **kw) for name, p in combinations.items()}

    def _tresca(self, b, lcp, P, g, fric, p, tol, accuracy, options):
        """Fixed point on Tresca bounds s = f X_n: each iteration the convex QP
        min ½(Pz-g)'R(Pz-g) + R_F'(Pz-g) + s'(Z⁺ + Z⁻), z >= 0 (its KKT system is
        the LCP with the bounds frozen); stopped when z solves the full LCP."""
        from qpsolvers import Problem

        check_options("tresca", options, ("qp_method", "max_iter"))
        qp_method = options.get("qp_method", "auto")
        max_iter = int(options.get("max_iter", 50))
        R = b["R"]
        RF = b["RFc"] + p * b["RFv"]
        nc = len(self.contacts)
        pos = self._layout(b)
        H = P.T @ R @ P
        H = 0.5 * (H + H.T)
        base = P.T @ (RF - R @ g)
        xn = np.zeros(nc)
        for it in range(max_iter):
            s = np.zeros(P.shape[1])
            for k, ci in enumerate(fric):
                s[nc + 2 * k] = s[nc + 2 * k + 1] = self.contacts[ci].friction * max(xn[ci], 0.0)
            sol = solve(Problem(H, base + s, lb=np.zeros(H.shape[0])), method=qp_method,
                        accuracy=accuracy)
            if sol.x is None:
                break
            z = np.maximum(sol.x, 0.0)
            if certify_lcp(lcp, z).ok(tol):
                return z, f"tresca fixed point ({sol.method}, {it + 1} iterations)"
            X = R @ (P @ z - g) + RF
            xn = np.array([X[pos[ci]["n"]] for ci in range(nc)])
        sol = solve(lcp, method="lemke", accuracy=accuracy)
        if sol.z is None:
            raise SolverFailedError(f"frame: Tresca did not converge and Lemke failed ({sol.message})")
        return sol.z, f"lemke (Tresca fixed point did not converge in {max_iter} iterations)"

    # -- results --------------------------------------------------------------------
    def _result_from_z(self, z, p, route, b=None, lcp=None, tol=1e-9) -> FrameResult:
        b = b or self.build()
        M, qc, qv, P, g, fric = self.lcp(b)
        lcp = lcp or ParametricLCP(M, qc, qv).at(p)
        z = np.maximum(np.asarray(z, float), 0.0)
        R = b["R"]
        RF = b["RFc"] + p * b["RFv"]
        delta = P @ z - g                      # link displacements incl. contact flexibility
        X = R @ delta + RF
        delta_struct = delta - b["flex"] * X   # what the structure itself displaces
        nf, free = b["nf"], b["free"]
        F = b["Fc"] + p * b["Fv"]
        rhs = np.r_[F[free], b["kappa"] * delta_struct]
        sol = scipy.linalg.lu_solve(b["lu"], rhs, check_finite=False)
        u = np.zeros(b["K"].shape[0])
        u[free] = sol[:nf]
        # reactions at the fixed dofs: K u - F - H X on them (member loads included)
        r_all = b["K"] @ u - F - b["H"] @ X
        reactions = {}
        for node in b["names"]:
            i0 = b["idx"][node]
            if node in self.fixed:
                reactions[node] = tuple(float(r_all[i0 + k]) if b["fixed"][i0 + k] else 0.0
                                        for k in range(3))
        # global equilibrium: applied loads + contact forces + reactions (forces and moment)
        eq = self._equilibrium(b, F, X, r_all)
        cert = certify_lcp(lcp, z)
        pos = self._layout(b)
        # each state decided on the component's own scale (the certificate's):
        # X_n against the terms it is made of, a slip part against its own size
        zeta, sigma = ComponentScales(M, lcp.q_terms).at(z)
        nc = len(self.contacts)
        slot = {ci: nc + 2 * k for k, ci in enumerate(fric)}
        keys = self._support_keys()
        supports = {}
        for ci, c in enumerate(self.contacts):
            xn = float(X[pos[ci]["n"]])
            zn = float(z[ci])
            t = np.array([c.normal[1], -c.normal[0]])
            rel = np.array(u[b["idx"][c.node]:b["idx"][c.node] + 2])
            if c.other is not None:
                rel = rel - u[b["idx"][c.other]:b["idx"][c.other] + 2]
            if "t" in pos[ci]:
                xt = float(X[pos[ci]["t"]])
                slip = float(delta[pos[ci]["t"]])
            else:  # frictionless: no tangential link, the node slides freely
                xt, slip = 0.0, float(t @ rel)
            if xn <= STATE_RTOL * sigma[ci]:
                state = "separated"
            elif ci not in slot:
                state = "closed"
            elif max(z[slot[ci]], z[slot[ci] + 1]) <= STATE_RTOL * max(zeta[slot[ci]], zeta[slot[ci] + 1]):
                state = "stick"
            else:
                state = "slip+" if slip > 0 else "slip-"
            supports[keys[ci]] = SupportResult(state, xn, xt, zn, slip)
        displacements = {nd: tuple(float(u[b["idx"][nd] + k]) for k in range(3)) for nd in b["names"]}
        member_forces = {}
        for m in self.members.values():
            k, fe, T, _ = self._member_local(m, None)
            fe_p = self._member_fe(m, p)
            dofs = np.r_[b["idx"][m.i]:b["idx"][m.i] + 3, b["idx"][m.j]:b["idx"][m.j] + 3]
            member_forces[m.name] = k @ (T @ u[dofs]) - fe_p
        ok = cert.ok(tol) and eq <= EQUILIBRIUM_RTOL
        msg = (f"{route}: LCP certificate {cert.error:.1e}, equilibrium residual {eq:.1e}"
               + ("" if ok else " — CHECK FAILED"))
        return FrameResult(p=p, supports=supports, displacements=displacements,
                           member_forces=member_forces, reactions=reactions,
                           equilibrium_residual=eq, lcp_error=cert.error, route=route, ok=ok,
                           message=msg, frame=self, _u=u)

    def _member_fe(self, m, p):
        _, fc, _, _ = self._member_local(m, "constant")
        _, fv, _, _ = self._member_local(m, "variable")
        return fc + p * fv

    def _equilibrium(self, b, F, X, r_all):
        """|Σ forces| and |Σ moments about the origin| of loads, contact forces and
        reactions, relative to the largest load term (PyNite-style statics check)."""
        xy = np.array([self.nodes[nd] for nd in b["names"]])
        f_tot = F + b["H"] @ X + np.where(b["fixed"], r_all, 0.0)
        fx, fy, mz = f_tot[0::3], f_tot[1::3], f_tot[2::3]
        res_f = np.array([fx.sum(), fy.sum(), mz.sum() + (xy[:, 0] * fy - xy[:, 1] * fx).sum()])
        Fx, Fy, Mz = F[0::3], F[1::3], F[2::3]
        ref = max(np.abs(F).max(initial=0.0), np.abs(b["H"] @ X).max(initial=0.0),
                  np.abs(Mz + xy[:, 0] * Fy - xy[:, 1] * Fx).max(initial=0.0), 1e-300)
        return float(np.abs(res_f).max() / ref)

    def _diagram(self, res: FrameResult, member: str, points: int):
        m = self.members[member]
        L, c, s, _ = self._geometry(m)
        f = res.member_forces[member]
        wxl = wyl = 0.0
        for wx, wy, kind in m.loads:
            fac = 1.0 if kind == "constant" else res.p
            wxl += fac * (c * wx + s * wy)
            wyl += fac * (-s * wx + c * wy)
        x = np.linspace(0.0, L, points)
        N = -f[0] - wxl * x
        M = -f[2] + f[1] * x + wyl * x ** 2 / 2
        V = f[1] + wyl * x
        return x, N, V, M

    # -- trace -----------------------------------------------------------------------
    def _support_keys(self) -> list:
        """The key of each contact in FrameResult.supports, in contact order."""
        keys = []
        for c in self.contacts:
            key = c.node if c.other is None else f"{c.node}-{c.other}"
            keys.append(f"{key}#{len(keys)}" if key in keys else key)
        return keys

    def trace(self, p_max: float | None = None, accuracy="high") -> FrameTrace:
        """P3's increasing-load analysis: the constant loads, then the variable
        loads scaled by p from 0 to ``p_max`` (None: until no support changes
        state again, or no equilibrium continues the path).

        Every piece of the path is checked like a single solve (LCP certificate
        and global equilibrium, at its start, middle and end); a piece that
        fails is not returned and the trace ends "breakdown".  Breakpoints where
        only the LCP's bookkeeping changes (a separated contact's slip changing
        sign) are merged: ``breakpoints`` are where a support changes state.
        """
        from qpcontact.accuracy import resolve_accuracy

        _, tol = resolve_accuracy(accuracy)
        b = self.build()
        M, qc, qv, P, g, fric = self.lcp(b)
        tr = solve(ParametricLCP(M, qc, qv), method="trace", accuracy=accuracy,
                   p_max=np.inf if p_max is None else p_max)
        runs = []        # [p_start, p_end, states]
        ended, failed = tr.end, None
        for piece in tr.pieces:
            hi = piece.p_end if np.isfinite(piece.p_end) else piece.p_start + max(1.0, piece.p_start)
            checks = [self._result_from_z(piece.z(pp), pp, "trace", b=b, tol=tol)
                      for pp in (piece.p_start, 0.5 * (piece.p_start + hi), hi)]
            bad = [r for r in checks if not r.ok]
            if bad:
                ended, failed = "breakdown", bad[0]
                break
            key = {k: v.state for k, v in checks[1].supports.items()}
            if runs and runs[-1][2] == key:
                runs[-1][1] = piece.p_end
            else:
                runs.append([piece.p_start, piece.p_end, key])
        intervals = [(r[0], r[1]) for r in runs]
        events = [FrameEvent(r1[0], {k: (r0[2][k], r1[2][k]) for k in r1[2] if r0[2][k] != r1[2][k]})
                  for r0, r1 in zip(runs[:-1], runs[1:])]
        ft = FrameTrace(breakpoints=np.array([ev.p for ev in events]), states=[], intervals=intervals,
                        events=events, ended=ended, message="", ok=False, trace=tr, frame=self,
                        _built=b)
        for lo, hi in intervals:
            top = hi if np.isfinite(hi) else lo + max(1.0, lo)
            ft.states.append(ft.result_at(0.5 * (lo + top)))
        if failed is not None:
            ft.message = (f"the piece from p = {failed.p:g} failed the frame's checks "
                          f"({failed.message}); the trace stops there")
        elif ended == "collapse":
            words = (self._collapse_words(tr.proof, fric, ft) if tr.proof["farkas"] is not None
                     else "no combination of support states carries the load")
            how = ("a Farkas certificate" if tr.proof["patterns"] == 1 else
                   f"Farkas certificates for all {tr.proof['patterns']} combinations of support "
                   "states left after branching")
            bound = ("" if not np.isfinite(tr.proof["z_bound"]) else
                     f" for openings and slips summing below {tr.proof['z_bound']:.1e}")
            ft.message = (f"no equilibrium exists for p >= {tr.proof['p_limit']:.10g} (the last one "
                          f"is at p = {tr.p_end:.10g}): {words} (proved by {how}, checked from "
                          f"the data{bound})")
        elif ended == "unbounded":
            ft.message = (f"no support changes state for p >= {tr.proof['from']:g}: the frame "
                          "carries any larger load in its last working scheme")
        else:
            ft.message = tr.message
        ft.ok = bool(tr.ok and failed is None)
        ft.message += f"; {len(events)} change(s) of the working scheme"
        return ft

    def _collapse_words(self, proof, fric, ft) -> str:
        """How the frame fails, read off the Farkas vector y.

        y'w = Σ_c (A_c X_n + T_c X_t) with A_c = y_n + f (y+ + y-) and T_c =
        y+ - y-, and y'M = 0 makes this combination independent of the
        displacements: it is the virtual work of the contact forces in a rigid
        motion of the frame with normal motion A_c >= f |T_c| and tangential
        motion T_c at each contact.  A contact lifts off in it when A_c >
        f |T_c|, slides (along ±t) when T_c != 0 and A_c = f |T_c| (Coulomb's
        cone), and stays (a pivot) when both are zero.
        """
        y = proof["farkas"]
        keys = self._support_keys()
        nc = len(self.contacts)
        A = y[:nc].copy()
        T = np.zeros(nc)
        for k, ci in enumerate(fric):
            yp, ym = y[nc + 2 * k], y[nc + 2 * k + 1]
            A[ci] += self.contacts[ci].friction * (yp + ym)
            T[ci] = yp - ym
        big = max(A.max(initial=0.0), np.abs(T).max(initial=0.0))
        lift, slide, stay = [], [], []
        for ci in range(nc):
            f = self.contacts[ci].friction
            if A[ci] <= 1e-9 * big and abs(T[ci]) <= 1e-9 * big:
                stay.append(keys[ci])
            elif A[ci] > f * abs(T[ci]) * (1 + 1e-6) + 1e-9 * big:
                lift.append(keys[ci])
            else:
                slide.append(f"{keys[ci]} ({'+t' if T[ci] > 0 else '-t'})")
        carrying = [k for k, v in ft.states[-1].supports.items()
                    if v.state != "separated"] if ft.states else []
        if slide and not lift:
            whole = all(any(s.startswith(k + " ") for s in slide) for k in carrying)
            return (("the frame slides away as a rigid body: " if whole else "it slides: ")
                    + "friction exhausted at " + ", ".join(slide))
        if lift and not slide:
            if stay:
                return f"it tips over about {', '.join(stay)}: {', '.join(lift)} lift off"
            return "it lifts off: " + ", ".join(lift) + " would have to pull"
        return ("it lifts off at " + ", ".join(lift) + " and slides at " + ", ".join(slide))

    # -- plots ---------------------------------------------------------------------------
    def _plot_result(self, res: FrameResult, path, scale, title):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from qpcontact.plotting import save_figure

        xy = np.array(list(self.nodes.values()))
        span = max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-12)
        umax = max(max(abs(d[0]), abs(d[1])) for d in res.displacements.values())
        scale = scale or (0.1 * span / umax if umax > 0 else 1.0)
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5))
        colors = {"separated": "tab:red", "closed": "tab:blue", "stick": "tab:green", "slip+": "tab:orange",
                  "slip-": "tab:purple"}
        diagrams = {m.name: res.diagram(m.name) for m in self.members.values()}
        m_max = max(max(np.abs(d[3]).max() for d in diagrams.values()), 1e-300)
        mscale = 0.15 * span / m_max
        for m in self.members.values():
            a, bnode = self.nodes[m.i], self.nodes[m.j]
            ax1.plot([a[0], bnode[0]], [a[1], bnode[1]], color="0.75", lw=1)
            du = np.array(res.displacements[m.i][:2]), np.array(res.displacements[m.j][:2])
            ax1.plot([a[0] + scale * du[0][0], bnode[0] + scale * du[1][0]],
                     [a[1] + scale * du[0][1], bnode[1] + scale * du[1][1]], color="k", lw=1.8)
            x, N, V, Mo = diagrams[m.name]
            L, c, sn, _ = self._geometry(m)
            px, py = a[0] + c * x, a[1] + sn * x
            # sagging moment compresses the +y fibre: the tension side is -y (member axes)
            ox, oy = -sn * Mo * mscale, c * Mo * mscale
            ax2.plot([a[0], bnode[0]], [a[1], bnode[1]], color="k", lw=1.5)
            ax2.fill(np.r_[px, (px - ox)[::-1]], np.r_[py, (py - oy)[::-1]], alpha=0.3,
                     color="tab:blue")
            ax2.plot(px - ox, py - oy, color="tab:blue", lw=1)
            k_max = int(np.argmax(np.abs(Mo)))
            ax2.annotate(f"{Mo[k_max]:.3g}", (px[k_max] - ox[k_max], py[k_max] - oy[k_max]),
                         fontsize=7)
        for key, sres in res.supports.items():
            node = key.split("-")[0].split("#")[0]
            p0 = self.nodes[node] + scale * np.array(res.displacements[node][:2])
            ax1.plot(*p0, "^", ms=11, color=colors[sres.state])
            ax1.annotate(f"{key}: {sres.state}\nN={sres.normal:.3g} T={sres.tangential:.3g}",
                         p0, textcoords="offset points", xytext=(5, -22), fontsize=7)
        for node in self.fixed:
            ax1.plot(*self.nodes[node], "s", ms=9, color="tab:blue")
        ax1.set_title(f"deformed shape (x{scale:.3g}); supports: red separated, green stick, "
                      "blue closed (frictionless), orange/purple slip", fontsize=9)
        ax2.set_title("bending moment diagram (drawn on the tension side)", fontsize=9)
        for ax in (ax1, ax2):
            ax.set_aspect("equal", adjustable="datalim")
            ax.grid(True, alpha=0.3)
        fig.suptitle(title or f"p = {res.p:g}; {res.message}", fontsize=9)
        fig.tight_layout()
        return save_figure(fig, path)

    def _plot_trace(self, ft: FrameTrace, path, node, dof, p_max):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from qpcontact.plotting import save_figure

        k = DOFS.index(dof)
        top = ft.trace.plot_range()
        if p_max is not None:
            top = min(float(p_max), ft.p_end)
        ps = np.unique(np.r_[0.0, ft.breakpoints[ft.breakpoints <= top], np.linspace(0, top, 60)])
        disp = [ft.result_at(p).displacements[node][k] for p in ps]
        fig, ax = plt.subplots(figsize=(7, 4.5))
        ax.plot(disp, ps, "k-")
        lo, hi = min(disp), max(disp)
        for ev in ft.events:
            if ev.p <= top:
                d = ft.result_at(ev.p).displacements[node][k]
                ax.plot(d, ev.p, "o", color="tab:red")
                right = d > lo + 0.5 * (hi - lo)   # label on the side with room
                ax.annotate(f"p = {ev.p:.4g}: {ev}", (d, ev.p), textcoords="offset points",
                            xytext=(-6 if right else 6, 5), ha="right" if right else "left",
                            fontsize=7)
        if ft.ended in ("collapse", "fold", "breakdown") and ft.p_end <= top:
            ax.axhline(ft.p_end, color="tab:red", ls="--", lw=0.8)
            ax.annotate(ft.ended, (ax.get_xlim()[0], ft.p_end), textcoords="offset points",
                        xytext=(4, 4), fontsize=8, color="tab:red")
        ax.set_xlabel(f"{dof} at {node}")
        ax.set_ylabel("load parameter p")
        ax.set_title(f"increasing load: {len(ft.breakpoints)} change(s) of the working scheme; "
                     f"ended: {ft.ended}", fontsize=9)
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        return save_figure(fig, path)


def demo(console) -> int:
    """The frame part of ``qpcontact demo``: a beam pinned at one end on a
    frictional support (limit f P/2 by hand) solved below and above the limit
    by Lemke and by the Tresca fixed point; then the portal of
    :func:`portal_example` traced to its collapse, against the hand values.
    Returns the number of failed checks."""
    from rich.markup import escape
    from rich.table import Table

    def beam(H):
        fr = Frame()
        for nm, x in (("A", 0.0), ("C", 2.0), ("B", 4.0)):
            fr.add_node(nm, x, 0.0)
        fr.add_beam("A", "C", E=2e8, A=0.01, I=1e-4)
        fr.add_beam("C", "B", E=2e8, A=0.01, I=1e-4)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_contact("B", normal=(0.0, 1.0), friction=0.3)
        fr.add_load("C", fy=-100.0)
        fr.add_load("B", fx=H)
        return fr

    table = Table(title="Frame (P3): beam pinned at A, resting on a support at B with f = 0.3, "
                        "100 kN at midspan, H at B; by hand: stick iff H <= f*50 = 15 kN")
    for col in ("H [kN]", "route", "state at B", "X_n [kN]", "X_t [kN]", "LCP error", "equilibrium"):
        table.add_column(escape(col), justify="left" if col in ("route", "state at B") else "right")
    failed = 0
    for H in (10.0, 20.0):
        for method in ("lemke", "tresca"):
            r = beam(H).solve(method=method)
            s = r.supports["B"]
            expect = "stick" if H <= 15 else "slip+"
            failed += int(not r.ok or s.state != expect)
            table.add_row(f"{H:g}", r.route, s.state, f"{s.normal:.3f}", f"{s.tangential:.3f}",
                          f"{r.lcp_error:.0e}", f"{r.equilibrium_residual:.0e}")
    console.print(table)
    tr = portal_example().trace(p_max=40.0)
    table = Table(title="Increasing load (P3's trace): pinned-base portal 6 m x 4 m on two frictional "
                        "bases (f = 0.3), 20 kN/m on the beam, P = p kN lateral at B")
    for col in ("p", "by hand", "event"):
        table.add_column(col, justify="left" if col == "event" else "right")
    hand = (25.4363, 0.3 * 20.0 * 6.0)   # force method; f w L
    rows = [(ev.p, str(ev)) for ev in tr.events] + [(tr.p_end, f"{tr.ended}: {tr.message}")]
    for (p, what), ref in zip(rows, hand):
        table.add_row(f"{p:.6g}", f"{ref:.6g}", escape(what))
    console.print(table)
    got = [p for p, _ in rows]
    failed += int(not (tr.ok and tr.ended == "collapse" and len(got) == 2
                       and abs(got[0] - hand[0]) < 5e-5 and abs(got[1] - hand[1]) < 1e-8 * hand[1]))
    return failed


def portal_example() -> Frame:
    """The portal of issue 15: columns A(0,0)-B(0,4) and D(6,0)-C(6,4), beam B-C,
    IPE 300 (E = 210e6 kN/m², A = 5.381e-3 m², I = 8.356e-5 m⁴), both bases rigid
    frictional contacts (normal (0, 1), f = 0.3, free rotation), 20 kN/m down on
    the beam (constant), P = p kN at B along +x (variable).  By hand: base D
    starts slipping at P = 25.4363 kN (force method) and the frame slides away
    at P = f w L = 36 kN."""
    fr = Frame()
    for name, x, y in (("A", 0.0, 0.0), ("B", 0.0, 4.0), ("C", 6.0, 4.0), ("D", 6.0, 0.0)):
        fr.add_node(name, x, y)
    E, A, I = 210e6, 5.381e-3, 8.356e-5
    fr.add_beam("A", "B", E, A, I)
    beam = fr.add_beam("B", "C", E, A, I)
    fr.add_beam("D", "C", E, A, I)
    fr.add_contact("A", normal=(0.0, 1.0), friction=0.3)
    fr.add_contact("D", normal=(0.0, 1.0), friction=0.3)
    fr.add_distributed_load(beam, wy=-20.0)
    fr.add_load("B", fx=1.0, kind="variable")
    return fr


def instances(size: str = "small", hardness: str = "easy", seed: int = 0):
    """Frame LCPs for ``qpcontact compare``: a continuous beam on 3, 10 or 30
    unilateral supports (size small/medium/large) under gravity and uplifting
    point loads; "easy" without friction (symmetric), "hard" with friction
    f = 0.3 and a lateral load (nonsymmetric: QP backends are not applicable).
    Named ``frames/10-supports-friction``; the contact forces are w's first
    entries (X_n)."""
    from qpcontact.compare import Instance

    spans = {"small": 3, "medium": 10, "large": 30}[size]
    rng = np.random.default_rng(seed + spans)
    fr = Frame()
    xs = np.cumsum(np.r_[0.0, rng.uniform(2.0, 4.0, spans)])
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", float(x), 0.0)
    for k in range(spans):
        m = fr.add_beam(f"N{k}", f"N{k + 1}", E=2.1e8, A=5.4e-3, I=5.7e-5)
        fr.add_distributed_load(m, wy=-20.0)
    friction = 0.3 if hardness == "hard" else 0.0
    fr.add_support("N0", fix=("ux", "uy", "rz"))
    for k in range(1, spans + 1):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), friction=friction, gap=float(rng.uniform(0, 2e-3)))
    for k in rng.choice(np.arange(1, spans + 1), size=max(1, spans // 3), replace=False):
        fr.add_load(f"N{k}", fy=float(rng.uniform(20, 60)), fx=40.0 if friction else 0.0)
    M, qc, qv, P, g, fric = fr.lcp()
    name = f"frames/{spans}-supports" + ("-friction" if friction else "")
    return [Instance(name, "frames", f"{spans}-supports", ParametricLCP(M, qc, qv).at(1.0),
                     forces=("w", spans))]
