"""Rafts in two independent FE codes, for the peer tests and
benchmarks/scale.py's raft rows: each takes a :class:`formulations.plates.Raft`
(its mesh, nodal soil springs k·A_i and nodal loads — the same lumping on
both sides) and returns (w, soil force per node, converged, iterations).
Their iterations are the engineers' route: compression-only springs
re-stiffened until the contact set repeats, with no certificate.

* PyNite (test extra PyNiteFEA): Quad3D (DKMQ) on ``def_support_spring(...,
  "-")`` springs.
* OpenSees (openseespy): ShellMITC4 with an ElasticMembranePlateSection on
  zeroLength springs of an ENT (elastic no-tension) material, Newton
  iterations on the unbalanced force (each a re-stiffening of the springs
  by their current state); converged when the displacement increment's norm
  drops below ``tol``."""

from __future__ import annotations

import numpy as np


def pynite_raft(raft, k, combination=None, max_iter=30):
    from Pynite import FEModel3D

    combination = combination or {"D": 1.0}
    mesh = raft.mesh
    E, nu, t = raft.E, raft.nu, raft.thickness
    m = FEModel3D()
    m.add_material("c", E, E / (2 * (1 + nu)), nu, 0.0)
    area = mesh.tributary_areas()
    for i, (x, y) in enumerate(mesh.nodes):       # z up in PyNite: our w is −DZ
        m.add_node(f"N{i}", x, y, 0.0)
        m.def_support(f"N{i}", support_DX=True, support_DY=True, support_RZ=True)
        m.def_support_spring(f"N{i}", "DZ", k * area[i], "-")   # resists moving down only
    for e, (a, b, c, d) in enumerate(mesh.elements):
        m.add_quad(f"Q{e}", f"N{a}", f"N{b}", f"N{c}", f"N{d}", t, "c")
    f = raft.load_vector(combination)
    for i in np.flatnonzero(f[0::3]):
        m.add_node_load(f"N{i}", "FZ", -f[3 * i], case="D")
    m.add_load_combo("C", {"D": 1.0})
    try:
        m.analyze(check_statics=False, max_iter=max_iter)
        converged = True
    except Exception:   # PyNite raises when its spring iteration does not settle
        return None, None, False, max_iter
    n = mesh.nodes.shape[0]
    return (np.array([-m.nodes[f"N{i}"].DZ["C"] for i in range(n)]),
            np.array([m.nodes[f"N{i}"].RxnFZ["C"] for i in range(n)]), converged, None)


def opensees_raft(raft, k, combination=None, max_iter=100, tol=1e-10):
    import openseespy.opensees as ops

    combination = combination or {"D": 1.0}
    mesh = raft.mesh
    nodes = mesh.nodes
    n = nodes.shape[0]
    area = mesh.tributary_areas()
    f = raft.load_vector(combination)
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for i, (x, y) in enumerate(nodes):
        ops.node(i + 1, float(x), float(y), 0.0)          # the raft
        ops.node(n + i + 1, float(x), float(y), 0.0)      # the ground under it
        ops.fix(i + 1, 1, 1, 0, 0, 0, 1)                  # bending only: no membrane, no drill
        ops.fix(n + i + 1, 1, 1, 1, 1, 1, 1)
    ops.section("ElasticMembranePlateSection", 1, raft.E, raft.nu, raft.thickness, 0.0)
    for e, (a, b, c, d) in enumerate(mesh.elements):
        ops.element("ShellMITC4", e + 1, int(a) + 1, int(b) + 1, int(c) + 1, int(d) + 1, 1)
    for i in range(n):
        # ENT: stiff in compression (ground-to-raft deformation < 0: the raft
        # moves down), nothing in tension
        ops.uniaxialMaterial("ENT", i + 1, float(k * area[i]))
        ops.element("zeroLength", len(mesh.elements) + i + 1, n + i + 1, i + 1,
                    "-mat", i + 1, "-dir", 3)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for i in np.flatnonzero(f[0::3]):
        ops.load(int(i) + 1, 0.0, 0.0, -float(f[3 * i]), 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", tol, max_iter, 0)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    converged = ops.analyze(1) == 0
    iterations = ops.testIter()
    w = np.array([-ops.nodeDisp(i + 1, 3) for i in range(n)])
    force = np.array([float(k * area[i]) * max(w[i], 0.0) for i in range(n)])
    ops.wipe()
    return w, force, converged, iterations
