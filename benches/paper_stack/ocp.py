"""The trajectory problem of the belt-driven arm, built the way the paper's authors would have
built it: CasADi symbolic dynamics (SX) and IPOPT through `casadi.nlpsol`.

This is an independent implementation of docs/model.md sections 1-7, written without any code
of the Rust crate; it reads only the two input files:

- the robot, robots/belt_arm.urdf, parsed with xml.etree into a serial chain (fixed joints are
  merged into their parent, i.e. folded into the next movable joint's constant placement);
- the task, robots/tasks/pick_place.json (motion, weights, Cartesian box, motor limits,
  transmission matrix with symbolic entries "r1" .. "-r4", limit modes, IPOPT settings).

Dynamics: a recursive Newton-Euler algorithm (RNEA) written with CasADi SX, in link-local frames
(Craig / Luh-Walker-Paul form). The payload is a point mass at the task's point of its link.

Transcription (semi-implicit Euler, accelerations kept as variables, inverse dynamics as
equality rows), variables grouped by node, [q_k, v_k, a_k, u_k] for k < N and [q_N, v_N]:

    RNEA(q_k, v_k, a_k) - tau_k = 0          tau_k = G(r)^T u_k (actuation) or u_k (joint)
    v_(k+1) - v_k - h a_k = 0
    q_(k+1) - q_k - h v_(k+1) = 0
    (speed mode exact)   -w <= G v_k <= w     at the inner nodes k = 1 .. N-1
    (torque mode exact)  -t <= G^-T u_k <= t  at every k < N (joint space only)

Boundary conditions and boxes are variable bounds (IPOPT removes the fixed variables q_0, v_0,
q_N, v_N itself, `fixed_variable_treatment` make_parameter).

Cost: sum_(k<N) wq|q_k|^2 + wv|v_k|^2 + wu|u_k|^2 + rho_y c_y(q_k)^2 + rho_z c_z(q_k)^2 with
c = max(0, lo - p) + max(0, p - hi) for the TCP's world y and z.
"""

import json
import math
import os
import xml.etree.ElementTree as ET

import casadi as ca
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
DEFAULT_TASK = os.path.join(ROOT, "robots", "tasks", "pick_place.json")
# A static hold margin down to minus this counts as held, N m (the crate's HOLD_TOLERANCE_NM:
# rounding of g(q), never a real shortfall).
HOLD_TOLERANCE_NM = 1e-9


# ----------------------------------------------------------------------------------------------
# Rotations (numeric, numpy) and the URDF
# ----------------------------------------------------------------------------------------------

def rpy_matrix(rpy):
    """URDF roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll) (fixed axes x, y, z)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _floats(text, default):
    return [float(t) for t in text.split()] if text is not None else list(default)


class Body:
    """A rigid body of one link, in that link's frame: mass m, centre of mass c, inertia I_c
    about the centre of mass (3x3, link axes)."""

    def __init__(self, m, c, inertia):
        self.m = float(m)
        self.c = np.asarray(c, dtype=float)
        self.I = np.asarray(inertia, dtype=float)


class Joint:
    """A movable (revolute) joint of the chain and the link it carries.

    R0, p0: constant placement of the joint frame in the previous movable link's frame (or in
    the world for the first joint), fixed joints in between already folded in;
    axis: unit rotation axis in the joint (= child link) frame; bodies: the link's mass."""

    def __init__(self, name, link, R0, p0, axis, lower, upper, bodies):
        self.name, self.link = name, link
        self.R0, self.p0 = R0, p0
        self.axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
        self.lower, self.upper = lower, upper
        self.bodies = bodies


def read_chain(urdf_path):
    """Parses a serial-chain URDF into a list of movable joints, root to tip.

    Fixed joints are merged: a fixed joint's transform is composed into the placement of the
    next movable joint, and the masses of links hanging on fixed joints below a movable link
    are added to that link's bodies. Masses of links rigidly attached to the root do not move
    and are dropped (they exert no joint torque)."""
    root = ET.parse(urdf_path).getroot()
    links = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            links[link.get("name")] = None
            continue
        origin = inertial.find("origin")
        xyz = _floats(origin.get("xyz") if origin is not None else None, (0, 0, 0))
        rpy = _floats(origin.get("rpy") if origin is not None else None, (0, 0, 0))
        mass = float(inertial.find("mass").get("value"))
        i = inertial.find("inertia")
        g = lambda k: float(i.get(k, 0.0))
        inertia = np.array([[g("ixx"), g("ixy"), g("ixz")],
                            [g("ixy"), g("iyy"), g("iyz")],
                            [g("ixz"), g("iyz"), g("izz")]])
        R = rpy_matrix(rpy)
        links[link.get("name")] = (mass, np.array(xyz), R @ inertia @ R.T)

    children = {}
    child_links = set()
    for joint in root.findall("joint"):
        parent = joint.find("parent").get("link")
        child = joint.find("child").get("link")
        children.setdefault(parent, []).append(joint)
        child_links.add(child)
    (root_link,) = [name for name in links if name not in child_links]

    chain = []
    # Walk down: (link, transform of link frame in the frame of the last movable link)
    link, R_acc, p_acc = root_link, np.eye(3), np.zeros(3)
    while link in children:
        if len(children[link]) != 1:
            raise ValueError(f"link {link} has {len(children[link])} children: not a serial chain")
        joint = children[link][0]
        origin = joint.find("origin")
        xyz = np.array(_floats(origin.get("xyz") if origin is not None else None, (0, 0, 0)))
        rpy = _floats(origin.get("rpy") if origin is not None else None, (0, 0, 0))
        R_j, p_j = R_acc @ rpy_matrix(rpy), p_acc + R_acc @ xyz
        child = joint.find("child").get("link")
        kind = joint.get("type")
        if kind == "fixed":
            # merge: the child's mass belongs to the last movable link, in its frame
            if chain and links.get(child) is not None:
                m, c, inertia = links[child]
                chain[-1].bodies.append(Body(m, p_j + R_j @ c, R_j @ inertia @ R_j.T))
            R_acc, p_acc = R_j, p_j
        elif kind in ("revolute", "continuous"):
            axis_el = joint.find("axis")
            axis = _floats(axis_el.get("xyz") if axis_el is not None else None, (1, 0, 0))
            limit = joint.find("limit")
            lower = float(limit.get("lower")) if limit is not None and kind == "revolute" else -np.inf
            upper = float(limit.get("upper")) if limit is not None and kind == "revolute" else np.inf
            bodies = []
            if links.get(child) is not None:
                bodies.append(Body(*links[child]))
            chain.append(Joint(joint.get("name"), child, R_j, p_j, axis, lower, upper, bodies))
            R_acc, p_acc = np.eye(3), np.zeros(3)
        else:
            raise ValueError(f"joint type {kind} not supported")
        link = child
    return chain


# ----------------------------------------------------------------------------------------------
# Symbolic kinematics and dynamics (CasADi)
# ----------------------------------------------------------------------------------------------

def axis_rotation(axis, angle):
    """Rodrigues: rotation by `angle` (symbolic) about the constant unit vector `axis`."""
    k = ca.DM(axis)
    K = ca.skew(k)
    return ca.DM.eye(3) + ca.sin(angle) * K + (1 - ca.cos(angle)) * ca.mtimes(K, K)


class ArmModel:
    """The arm of one task and payload: symbolic RNEA and TCP position."""

    def __init__(self, chain, gravity, tcp_link, tcp_point, payload_kg=0.0, payload_link=None,
                 payload_point=None):
        self.chain = chain
        self.n = len(chain)
        self.gravity = np.asarray(gravity, dtype=float)
        self.tcp_index = [j.link for j in chain].index(tcp_link)
        self.tcp_point = np.asarray(tcp_point, dtype=float)
        # Per-link bodies, with the payload as a point mass (no rotational inertia).
        self.bodies = [list(j.bodies) for j in chain]
        if payload_kg != 0.0:
            index = [j.link for j in chain].index(payload_link)
            self.bodies[index].append(Body(payload_kg, payload_point, np.zeros((3, 3))))

    def rotations(self, q):
        """Parent-to-child rotations R_i(q_i) = R0_i Rot(axis_i, q_i) (x_parent = R x_child + p)."""
        return [ca.mtimes(ca.DM(j.R0), axis_rotation(j.axis, q[i])) for i, j in enumerate(self.chain)]

    def rnea(self, q, v, a):
        """Joint torques tau = M(q) a + C(q, v) v + g(q), recursive Newton-Euler in link frames.

        Forward pass (link i, frame i): angular velocity w, angular acceleration dw, linear
        acceleration of the frame origin ao (gravity enters as a base acceleration -g).
        Backward pass: force f and moment nm about the origin that link i-1 exerts on link i."""
        n = self.n
        R = self.rotations(q)
        w_p = ca.SX.zeros(3)
        dw_p = ca.SX.zeros(3)
        ao_p = ca.SX(ca.DM(-self.gravity))
        p_prev = None
        W, DW, AO = [], [], []
        for i, j in enumerate(self.chain):
            s = ca.DM(j.axis)
            Rt = R[i].T
            p = ca.DM(j.p0)
            # origin of frame i seen from frame i-1: p (constant; the rotation is about the axis
            # through the joint origin)
            ao = ca.mtimes(Rt, ao_p + ca.cross(dw_p, p) + ca.cross(w_p, ca.cross(w_p, p)))
            w_in = ca.mtimes(Rt, w_p)
            w = w_in + s * v[i]
            dw = ca.mtimes(Rt, dw_p) + s * a[i] + ca.cross(w_in, s * v[i])
            W.append(w), DW.append(dw), AO.append(ao)
            w_p, dw_p, ao_p = w, dw, ao
        tau = [None] * n
        f_next = ca.SX.zeros(3)
        n_next = ca.SX.zeros(3)
        for i in reversed(range(n)):
            w, dw, ao = W[i], DW[i], AO[i]
            f = ca.SX.zeros(3)
            nm = ca.SX.zeros(3)
            for b in self.bodies[i]:
                c = ca.DM(b.c)
                ac = ao + ca.cross(dw, c) + ca.cross(w, ca.cross(w, c))
                F = b.m * ac
                Ic = ca.DM(b.I)
                N = ca.mtimes(Ic, dw) + ca.cross(w, ca.mtimes(Ic, w))
                f = f + F
                nm = nm + N + ca.cross(c, F)
            if i + 1 < n:
                Rc = R[i + 1]
                pc = ca.DM(self.chain[i + 1].p0)
                fc = ca.mtimes(Rc, f_next)
                f = f + fc
                nm = nm + ca.mtimes(Rc, n_next) + ca.cross(pc, fc)
            tau[i] = ca.dot(ca.DM(self.chain[i].axis), nm)
            f_next, n_next = f, nm
        return ca.vertcat(*tau)

    def tcp_position(self, q):
        """World position of the TCP."""
        R = self.rotations(q)
        Rw = ca.DM.eye(3)
        pw = ca.DM.zeros(3)
        for i in range(self.tcp_index + 1):
            pw = pw + ca.mtimes(Rw, ca.DM(self.chain[i].p0))
            Rw = ca.mtimes(Rw, R[i])
        return pw + ca.mtimes(Rw, ca.DM(self.tcp_point))


# ----------------------------------------------------------------------------------------------
# Task, transmission, limit modes
# ----------------------------------------------------------------------------------------------

def load_task(path=DEFAULT_TASK):
    with open(path) as fh:
        task = json.load(fh)
    task["_dir"] = os.path.dirname(os.path.abspath(path))
    return task


def transmission_matrix(task, r):
    """G(r) from the task's matrix of numbers and names such as "r2" or "-r4"."""
    rows = []
    for row in task["transmission"]["matrix"]:
        out = []
        for e in row:
            if isinstance(e, str):
                sign = -1.0 if e.startswith("-") else 1.0
                name = e.lstrip("+-")
                out.append(sign * float(r[int(name[1:]) - 1]))
            else:
                out.append(float(e))
        rows.append(out)
    return np.array(rows)


def transmission_matrix_sx(task, r):
    """G(r) as a CasADi SX matrix of the symbols r (the ratios as NLP parameters), with the
    task's zeros structural, entry for entry the numbers of `transmission_matrix`."""
    rows = task["transmission"]["matrix"]
    G = ca.SX(len(rows), len(rows[0]))
    for i, row in enumerate(rows):
        for j, e in enumerate(row):
            if isinstance(e, str):
                name = e.lstrip("+-")
                ratio = r[int(name[1:]) - 1]
                G[i, j] = -ratio if e.startswith("-") else ratio
            elif float(e) != 0.0:
                G[i, j] = float(e)
    return G


def _box(lo, hi):
    """Elementwise box; where the two values come out reversed, from the smaller to the larger."""
    return np.minimum(lo, hi), np.maximum(lo, hi)


def torque_limits(G, mode, tau_max):
    """Joint torque limits of the joint-space problem: ('box', lo, hi) or ('rows', M, lo, hi)."""
    n = G.shape[0]
    ones = np.ones(n)
    if mode == "paper":
        return ("box",) + _box(-G.T @ ones * tau_max, G.T @ ones * tau_max)
    if mode == "interval":
        t = tau_max * np.abs(G).sum(axis=0)
        return ("box", -t, t)
    if mode == "exact":
        return ("rows", np.linalg.inv(G).T, -tau_max * ones, tau_max * ones)
    raise ValueError(mode)


def speed_limits(G, mode, w_max):
    """Joint speed limits (both spaces): ('box', lo, hi) or ('rows', G, lo, hi)."""
    n = G.shape[0]
    ones = np.ones(n)
    Gi = np.linalg.inv(G)
    if mode == "paper":
        return ("box",) + _box(-Gi @ ones * w_max, Gi @ ones * w_max)
    if mode == "interval":
        w = w_max * np.abs(Gi).sum(axis=1)
        return ("box", -w, w)
    if mode == "exact":
        return ("rows", G, -w_max * ones, w_max * ones)
    raise ValueError(mode)


# ----------------------------------------------------------------------------------------------
# The NLP
# ----------------------------------------------------------------------------------------------

class TrajectoryOCP:
    """One trajectory problem (space, payload, ratios, modes), built once; `solve()` runs IPOPT.

    Attributes after construction: `solver` (the casadi nlpsol Function) and `args` (x0, lbx,
    ubx, lbg, ubg, and p when parametric), so that `solver(**args)` is exactly one solve from
    the standard guess.

    `parametric=True` makes the ratios a parameter p of the NLP instead of numbers: the problem
    is built once and `solve_design(r)` solves any design with it (as a co-design loop would).
    Only where no variable bound depends on r: the actuation space with speed mode `exact` (the
    task's defaults), whose r enters only the dynamics rows (G^T u) and the speed rows (G v)."""

    def __init__(self, task=None, space="actuation", payload_kg=None, ratios=None,
                 torque_mode=None, speed_mode=None, linear_solver="mumps", print_level=0,
                 extra_options=None, jit=False, parametric=False):
        task = task if task is not None else load_task()
        self.task = task
        self.space = space
        chain = read_chain(os.path.join(task["_dir"], task["robot"]))
        pay = task["payload"]
        self.payload_kg = pay["mass_kg"] if payload_kg is None else float(payload_kg)
        self.model = ArmModel(chain, task["gravity"], task["tcp"]["link"], task["tcp"]["point"],
                              self.payload_kg, pay["at"]["link"], pay["at"]["point"])
        self.ratios = list(task["transmission"]["original"] if ratios is None else ratios)
        modes = task["limit_modes"]
        self.torque_mode = torque_mode or modes["torque"]
        self.speed_mode = speed_mode or modes["speed"]

        n = self.n = self.model.n
        motion = task["motion"]
        N = self.N = int(motion["steps"])
        T = float(motion["horizon_s"])
        h = T / N
        if not isinstance(motion["goal"], list):
            raise ValueError("motion.goal: this reference stack takes the goal as joint angles, "
                             "not a TCP position")
        q_start, q_goal = np.array(motion["start"]), np.array(motion["goal"])
        wts = task["weights"]
        box = task["cartesian_box"]
        tau_max = float(task["motors"]["torque_limit_nm"])
        w_max = float(task["motors"]["speed_limit_rad_s"])
        G = transmission_matrix(task, self.ratios)
        self.G = G
        self.parametric = bool(parametric)
        if self.parametric and (space != "actuation" or self.speed_mode != "exact"):
            raise ValueError(f"parametric ratios need the actuation space and speed mode exact "
                             f"(no bound depends on r); got {space} space, speed mode "
                             f"{self.speed_mode}")
        # r as the NLP's parameter, or G's numbers
        self.r = ca.SX.sym("r", len(self.ratios)) if self.parametric else None
        G_nlp = transmission_matrix_sx(task, self.r) if self.parametric else ca.DM(G)
        self._q_ends = (q_start, q_goal)
        self._tau_max = tau_max
        qlo = np.array([j.lower for j in chain])
        qhi = np.array([j.upper for j in chain])

        # One node's dynamics residual as a CasADi Function, called N times (inlined into SX).
        qs, vs, as_, us = (ca.SX.sym(s, n) for s in ("q", "v", "a", "u"))
        tau = ca.mtimes(G_nlp.T, us) if space == "actuation" else us
        if self.parametric:
            dyn = ca.Function("dyn", [qs, vs, as_, us, self.r],
                              [self.model.rnea(qs, vs, as_) - tau])
        else:
            dyn = ca.Function("dyn", [qs, vs, as_, us], [self.model.rnea(qs, vs, as_) - tau])
        # The static torques g(q) (gravity with the payload, v = a = 0) of the hold check.
        zero = ca.SX.zeros(n)
        self.gravity = ca.Function("gravity", [qs], [self.model.rnea(qs, zero, zero)])
        # Cost of one node's position: the soft Cartesian box on the TCP's world y and z.
        p = self.model.tcp_position(qs)
        box_cost = 0
        for axis, idx in (("y", 1), ("z", 2)):
            if axis in box:
                lo, hi = box[axis]["range"]
                c = ca.fmax(0, lo - p[idx]) + ca.fmax(0, p[idx] - hi)
                box_cost = box_cost + box[axis]["weight"] * c ** 2
        stage = ca.Function("stage", [qs, vs, us],
                            [wts["position"] * ca.sumsqr(qs) + wts["velocity"] * ca.sumsqr(vs)
                             + wts["control"] * ca.sumsqr(us) + box_cost])

        # Limits of the chosen modes.
        speed = speed_limits(G, self.speed_mode, w_max)
        if self.parametric:
            speed = ("rows", G_nlp) + speed[2:]
        if space == "actuation":
            control = ("box", -tau_max * np.ones(n), tau_max * np.ones(n))
        else:
            control = torque_limits(G, self.torque_mode, tau_max)

        # Variables, grouped by node; bounds and initial guess alongside.
        x, lbx, ubx, x0 = [], [], [], []
        g, lbg, ubg = [], [], []
        Q, V, A, U = [], [], [], []
        for k in range(N + 1):
            qk, vk = ca.SX.sym(f"q{k}", n), ca.SX.sym(f"v{k}", n)
            Q.append(qk), V.append(vk)
            x += [qk, vk]
            # positions: fixed at the ends, joint limits in between
            if k == 0:
                lbx += list(q_start); ubx += list(q_start)
            elif k == N:
                lbx += list(q_goal); ubx += list(q_goal)
            else:
                lbx += list(qlo); ubx += list(qhi)
            x0 += list(q_start + (k / N) * (q_goal - q_start))
            # speeds: at rest at the ends; the speed mode's box (if any) in between
            if k in (0, N):
                lbx += [0.0] * n; ubx += [0.0] * n
                x0 += [0.0] * n
            else:
                if speed[0] == "box":
                    lbx += list(speed[1]); ubx += list(speed[2])
                else:
                    lbx += [-np.inf] * n; ubx += [np.inf] * n
                x0 += list((q_goal - q_start) / T)
            if k < N:
                ak, uk = ca.SX.sym(f"a{k}", n), ca.SX.sym(f"u{k}", n)
                A.append(ak), U.append(uk)
                x += [ak, uk]
                lbx += [-np.inf] * n; ubx += [np.inf] * n
                x0 += [0.0] * n
                if control[0] == "box":
                    lbx += list(control[1]); ubx += list(control[2])
                else:
                    lbx += [-np.inf] * n; ubx += [np.inf] * n
                x0 += [0.0] * n

        J = 0
        for k in range(N):
            # node k's rows: dynamics, velocity, position, then the linear limit rows
            params = [self.r] if self.parametric else []
            g += [dyn(Q[k], V[k], A[k], U[k], *params),
                  V[k + 1] - V[k] - h * A[k],
                  Q[k + 1] - Q[k] - h * V[k + 1]]
            lbg += [0.0] * (3 * n); ubg += [0.0] * (3 * n)
            if speed[0] == "rows" and k > 0:
                rows = speed[1] if self.parametric else ca.DM(speed[1])
                g.append(ca.mtimes(rows, V[k]))
                lbg += list(speed[2]); ubg += list(speed[3])
            if control[0] == "rows":
                g.append(ca.mtimes(ca.DM(control[1]), U[k]))
                lbg += list(control[2]); ubg += list(control[3])
            J = J + stage(Q[k], V[k], U[k])

        self.x = ca.vertcat(*x)
        self.g = ca.vertcat(*g)
        self.J = J
        self.nlp = {"x": self.x, "f": J, "g": self.g}
        if self.parametric:
            self.nlp["p"] = self.r
        solver_cfg = task.get("solver", {})
        ipopt = {
            "tol": float(solver_cfg.get("tol", 1e-8)),
            "max_iter": int(solver_cfg.get("max_iter", 3000)),
            "hessian_approximation": "exact",
            "linear_solver": linear_solver,
            "print_level": int(print_level),
        }
        if print_level == 0:
            ipopt["sb"] = "yes"  # no banner
        ipopt.update(solver_cfg.get("options", {}))
        if extra_options:
            ipopt.update(extra_options)
        opts = {"ipopt": ipopt, "print_time": False}
        if jit:
            opts.update({"jit": True, "compiler": "shell",
                         "jit_options": {"flags": ["-O2"], "verbose": False}})
        self.solver = ca.nlpsol("trajectory", "ipopt", self.nlp, opts)
        self.args = {"x0": np.array(x0), "lbx": np.array(lbx), "ubx": np.array(ubx),
                     "lbg": np.array(lbg), "ubg": np.array(ubg)}
        if self.parametric:
            self.args["p"] = np.array(self.ratios, dtype=float)
        self._layout = (n, N)

    def solve(self):
        """One solve from the standard initial guess: returns a dict (status, cost, iterations,
        success, the raw solution)."""
        sol = self.solver(**self.args)
        return self.result(sol)

    def solve_design(self, ratios):
        """One solve of design `ratios` from the standard initial guess, with the problem built
        once (`parametric=True`); returns what `solve()` does."""
        if not self.parametric:
            raise ValueError("solve_design needs a problem built with parametric=True")
        sol = self.solver(**dict(self.args, p=np.asarray(ratios, dtype=float)))
        return self.result(sol)

    def static_hold(self, ratios=None):
        """The load held at rest (docs/model.md, section 6) of design `ratios` (the problem's own
        by default), without IPOPT: at the start and the goal the static torques g(q), with the
        payload, mapped to the problem's control (G^-T g in actuation space, g in joint space),
        against its control limits. Returns (holds, margins): margins per end, N m, the limit
        minus |the row's static torque| per row; a row holds down to -HOLD_TOLERANCE_NM."""
        G = transmission_matrix(self.task, self.ratios if ratios is None else ratios)
        n, tau_max = self.n, self._tau_max
        if self.space == "actuation":
            rows, lo, hi = np.linalg.inv(G).T, -tau_max * np.ones(n), tau_max * np.ones(n)
        else:
            limits = torque_limits(G, self.torque_mode, tau_max)
            rows, lo, hi = (np.eye(n),) + limits[1:] if limits[0] == "box" else limits[1:]
        margins = {}
        for end, q in zip(("start", "goal"), self._q_ends):
            value = rows @ np.array(self.gravity(q)).ravel()
            margins[end] = np.minimum(hi - value, value - lo)
        holds = all(np.all(m >= -HOLD_TOLERANCE_NM) for m in margins.values())
        return holds, margins

    def result(self, sol):
        stats = self.solver.stats()
        return {
            "status": stats["return_status"],
            "success": stats["return_status"] in ("Solve_Succeeded", "Solved_To_Acceptable_Level"),
            "iterations": stats["iter_count"],
            "cost": float(sol["f"]),
            "x": np.array(sol["x"]).ravel(),
        }

    def split(self, x):
        """Trajectory arrays q (N+1, n), v (N+1, n), a (N, n), u (N, n) from a solution vector."""
        n, N = self._layout
        body = x[: 4 * n * N].reshape(N, 4 * n)
        last = x[4 * n * N:]
        q = np.vstack([body[:, :n], last[:n]])
        v = np.vstack([body[:, n:2 * n], last[n:]])
        return q, v, body[:, 2 * n:3 * n], body[:, 3 * n:]


def rnea_function(payload_kg=0.0, task=None):
    """Numeric-callable RNEA and TCP position (CasADi Functions) of the task's arm, for checks."""
    task = task if task is not None else load_task()
    chain = read_chain(os.path.join(task["_dir"], task["robot"]))
    pay = task["payload"]
    model = ArmModel(chain, task["gravity"], task["tcp"]["link"], task["tcp"]["point"],
                     payload_kg, pay["at"]["link"], pay["at"]["point"])
    q, v, a = (ca.SX.sym(s, model.n) for s in "qva")
    return (ca.Function("rnea", [q, v, a], [model.rnea(q, v, a)]),
            ca.Function("tcp", [q], [model.tcp_position(q)]))


if __name__ == "__main__":
    # Quick run: the default problem with IPOPT's iteration log.
    import sys
    payload = float(sys.argv[1]) if len(sys.argv) > 1 else 0.0
    space = sys.argv[2] if len(sys.argv) > 2 else "actuation"
    ratios = [float(t) for t in sys.argv[3].split(",")] if len(sys.argv) > 3 else None
    ocp = TrajectoryOCP(space=space, payload_kg=payload, ratios=ratios, print_level=5)
    res = ocp.solve()
    print(f"{space} space, payload {payload} kg, r = {ocp.ratios}: {res['status']} in "
          f"{res['iterations']} iterations, J = {res['cost']:.9f}")
