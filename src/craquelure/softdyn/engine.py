"""A Soft Dynamics system: particles, a fixed pair list, loads, parameters and the specialised
right-hand side, with the diagnostics the runs and tests need.

Units are the scene's (radius R, viscosity eta, Young modulus E); the force unit F and the Stokes
time tau = eta R^2 / F are chosen by the scenario (:mod:`craquelure.softdyn.initial_state`).

Velocity solve: ``linear_solver: dense`` runs the whole right-hand side in one numba function
(N d <= 128 with ``auto``); ``sparse`` computes the per-pair blocks in numba and solves the
(N d)^2 system with SuperLU (``scipy.sparse.linalg.splu``, last particle pinned and the mean
velocity removed afterwards; LSQR with the sum rows when ``lubrication_tangential`` is absent and
the system may be singular). The sparsity pattern is fixed by the pair list and built once.
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from craquelure.codegen import effect_flags, specialise
from craquelure.errors import SceneError
from craquelure.registry import parameter_vector
from craquelure.softdyn import kernel_template as template
from craquelure.softdyn.integrate import Result, integrate

# the dense solve is the faster one up to this size (benchmarks/softdyn_cost.py)
DENSE_MAX_UNKNOWNS = 128


@dataclass(frozen=True)
class Flags:
    """What the right-hand side is compiled for: the scene's effects (their kernel flags from
    the registry) and the deflection rule (scene rules: :mod:`craquelure.softdyn.rules`)."""

    effects: tuple[str, ...]
    literal: bool = False

    @property
    def hertz(self) -> bool:
        return "hertz" in self.effects

    @property
    def tangential(self) -> bool:
        return "lubrication_tangential" in self.effects

    def template_flags(self) -> dict[str, bool]:
        return {**effect_flags("softdyn", self.effects), "LITERAL_DEFLECTION": self.literal}


def kernels(flags: Flags):
    """The right-hand side module compiled for ``flags`` (:func:`craquelure.codegen.specialise`)."""
    return specialise(template.__name__, flags.template_flags(), "softdyn")


def flags_for(scene) -> Flags:
    return Flags(scene.effects, scene.get("numerics.deflection_rule") == "literal")


def sample_times(scene) -> np.ndarray:
    """Log-spaced sample times (units of tau) from t_r/10 (or 1e-3) to t_end."""
    t_end = scene.get("outputs.t_end")
    t_r = scene.get("loads.ramp_time")
    first = min(t_r / 10.0 if t_r > 0 else 1e-3, t_end / 10.0)
    return np.geomspace(first, t_end, scene.get("outputs.n_samples") - 1)


def run(setup, sample_times_tau: np.ndarray | None = None, desc: str = "softdyn") -> Result:
    """The run of a scenario (:class:`craquelure.softdyn.initial_state.Setup`): its system
    integrated to ``outputs.t_end`` tau with the scene's integrator, stop rule and guards,
    sampled at ``sample_times_tau`` (default :func:`sample_times`)."""
    sc = setup.scene
    if sample_times_tau is None:
        sample_times_tau = sample_times(sc)
    dt = sc.optional("numerics.dt")  # heun's step; absent: adaptive steps (heun refuses)
    return integrate(
        setup.system, sc.get("outputs.t_end") * setup.tau, method=sc.get("numerics.integrator"),
        rtol=sc.get("numerics.rtol"), atol=sc.get("numerics.atol"),
        dt=None if dt is None else dt * setup.tau, stop=setup.stop_function(),
        sample_times=np.asarray(sample_times_tau) * setup.tau, force_scale=setup.f_v,
        drift_tolerance=sc.get("numerics.drift_tolerance"), time_unit=setup.tau,
        max_steps=sc.get("numerics.max_steps"), desc=desc,
        terminal=not sc.get("outputs.run_past_stop"))


@dataclass
class Engine:
    """The Soft Dynamics engine: particles (N, d), pairs (P), nominal loads F0 (N, d) and
    parameters; it solves the velocity system of the pair forces."""

    x0: np.ndarray
    pairs: np.ndarray
    F0: np.ndarray
    radius: float
    viscosity: float
    young: float
    k_n: float
    k_t: float
    c_n: float
    c_t: float
    tau_baumgarte: float
    ramp_time: float
    flags: Flags
    linear_solver: str
    pair_names: tuple[str, ...] = ()
    particle_names: tuple[str, ...] = ()
    symmetry: tuple[tuple[tuple[int, ...], tuple[float, ...]], ...] = ()
    n_rhs: int = field(default=0, init=False)

    def __post_init__(self) -> None:
        self.x0 = np.ascontiguousarray(self.x0, dtype=np.float64)
        self.F0 = np.ascontiguousarray(self.F0, dtype=np.float64)
        self.pairs = np.ascontiguousarray(self.pairs, dtype=np.int64)
        self.n, self.d = self.x0.shape  # particles, dimension
        self.n_pairs, self.n_unknowns = self.pairs.shape[0], self.n * self.d
        self.pi = np.ascontiguousarray(self.pairs[:, 0])
        self.pj = np.ascontiguousarray(self.pairs[:, 1])
        net = np.abs(self.F0.sum(axis=0)).max()
        if net > 1e-12 * max(np.abs(self.F0).max(), 1e-300):
            raise SceneError(f"loads: the external forces must sum to zero (overdamped, no drag "
                             f"on the particles), net force {self.F0.sum(axis=0)}")
        self.p = parameter_vector("softdyn", values={
            "R": self.radius, "eta": self.viscosity, "E": self.young, "k_n": self.k_n,
            "k_t": self.k_t, "c_n": self.c_n, "c_t": self.c_t,
            "inv_tau_B": 1.0 / self.tau_baumgarte, "t_r": self.ramp_time})
        self.k = kernels(self.flags)
        solver = self.linear_solver
        if solver == "auto":
            solver = "dense" if self.n_unknowns <= DENSE_MAX_UNKNOWNS else "sparse"
        self.solver = solver
        if solver == "sparse":
            self._build_pattern()
        self._projector = self._symmetry_projector() if self.symmetry else None

    # ---- sizes and state -------------------------------------------------------------
    @property
    def state_size(self) -> int:
        size = self.n * self.d
        if self.flags.hertz:
            size += self.n_pairs
            if self.flags.tangential:
                size += self.n_pairs * self.d
        return size

    def initial_state(self) -> np.ndarray:
        return np.zeros(self.state_size)  # displacements, deflections: all zero

    def unpack(self, y):
        return self.k.unpack(np.ascontiguousarray(y, dtype=np.float64), self.x0, self.n_pairs)

    # ---- right-hand side -------------------------------------------------------------
    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        self.n_rhs += 1
        y = np.ascontiguousarray(y, dtype=np.float64)
        if self.solver == "dense":
            out = self.k.rhs_dense(float(t), y, self.x0, self.pi, self.pj, self.F0, self.p)
        else:
            out = self._rhs_sparse(float(t), y)
        if self._projector is not None:
            out = self._projector @ out
        return out

    # ---- imposed symmetry ------------------------------------------------------------
    def _symmetry_projector(self) -> np.ndarray:
        """Average of the signed state permutations of a point group given as generators
        ``symmetry = ((particle permutation, axis signs), ...)``: the projector on the states
        the group leaves invariant. Positions map as u'_{pi(i)} = M u_i (M = diag(signs)),
        deflections as s' = s and q' = +-M q on the image pair (minus when the image pair is
        stored with the opposite orientation: q_ji = -q_ij since f_ji = -f_ij)."""
        gens = [self._state_map(np.asarray(perm), np.asarray(signs, dtype=float))
                for perm, signs in self.symmetry]
        size = self.state_size
        group = {np.eye(size).tobytes(): np.eye(size)}
        frontier = list(group.values())
        while frontier:
            new = []
            for g in frontier:
                for gen in gens:
                    h = gen @ g
                    if h.tobytes() not in group:
                        group[h.tobytes()] = h
                        new.append(h)
            frontier = new
            if len(group) > 64:
                raise SceneError("symmetry: the generators do not close to a small group")
        for perm, signs in self.symmetry:
            image = np.empty_like(self.x0)
            image[list(perm)] = self.x0 * np.asarray(signs, dtype=float)
            if not np.allclose(image, self.x0, rtol=0.0, atol=1e-12 * self.radius):
                raise SceneError("symmetry: the initial positions are not invariant")
        return sum(group.values()) / len(group)

    def _state_map(self, perm: np.ndarray, signs: np.ndarray) -> np.ndarray:
        n, d, npair = self.n, self.d, self.n_pairs
        G = np.zeros((self.state_size, self.state_size))
        for i in range(n):
            for e in range(d):
                G[perm[i] * d + e, i * d + e] = signs[e]
        if not self.flags.hertz:
            return G
        index = {(int(i), int(j)): k for k, (i, j) in enumerate(self.pairs)}
        off_s, off_q = n * d, n * d + npair
        for k, (i, j) in enumerate(self.pairs):
            pi_, pj_ = int(perm[i]), int(perm[j])
            if (pi_, pj_) in index:
                kk, orient = index[(pi_, pj_)], 1.0
            else:
                kk, orient = index[(pj_, pi_)], -1.0
            G[off_s + kk, off_s + k] = 1.0
            if self.flags.tangential:
                for e in range(d):
                    G[off_q + kk * d + e, off_q + k * d + e] = orient * signs[e]
        return G

    def evaluate(self, t: float, y: np.ndarray) -> dict[str, np.ndarray]:
        """Everything at one state: velocities, rates, pair quantities, blocks, residual."""
        y = np.ascontiguousarray(y, dtype=np.float64)
        x, s, q = self.unpack(y)
        nv, r, h, a, zn, zt, f, A, b = self.k.pair_terms(x, s, q, self.pi, self.pj, self.p)
        c, resid = self.k.particle_terms(float(t), self.pi, self.pj, self.F0, self.p, f, b)
        v = self._solve(A, c)
        ydot = self.k.rates(v, self.pi, self.pj, nv, r, a, zn, zt, s, q, self.p, self.n, self.d)
        if not self.flags.hertz:
            f = self.k.rigid_forces(v, self.pi, self.pj, A, self.d)
            resid = resid.copy()
            np.add.at(resid, self.pi, f)
            np.subtract.at(resid, self.pj, f)
        fn = np.einsum("kc,kc->k", f, nv)
        ft = f - fn[:, None] * nv
        return {"x": x, "s": s, "q": q, "n": nv, "r": r, "h": h, "a": a, "zeta_n": zn,
                "zeta_t": zt, "f": f, "f_n": fn, "f_t": ft, "A": A, "b": b, "c": c,
                "residual": resid, "v": v.reshape(self.n, self.d), "ydot": ydot,
                "load": self.load(t)}

    def load(self, t: float) -> np.ndarray:
        ramp, _ = self.k.load_factors(float(t), self.ramp_time)
        return ramp * self.F0

    def min_gap(self, y: np.ndarray) -> float:
        return float(self.k.min_gap(np.ascontiguousarray(y, dtype=np.float64), self.x0,
                                    self.pi, self.pj, self.radius))

    # ---- sparse path -----------------------------------------------------------------
    def _build_pattern(self) -> None:
        d, m = self.d, self.n_unknowns
        last = self.n - 1
        rows, cols, src, sgn = [], [], [], []
        for k, (i, j) in enumerate(self.pairs):
            for bi, bj, sign in ((i, i, 1.0), (i, j, -1.0), (j, j, 1.0), (j, i, -1.0)):
                if bi == last:
                    continue
                for e in range(d):
                    for g in range(d):
                        rows.append(bi * d + e)
                        cols.append(bj * d + g)
                        src.append(k * d * d + e * d + g)
                        sgn.append(sign)
        # Gauge: with lubrication_tangential the last particle is pinned (v_last = 0, one
        # diagonal entry per component) and the mean velocity is removed after the solve; a
        # dense row sum_i v_i = 0 would fill the LU factors. Without it (possible rotation
        # null modes, LSQR) the sum rows are kept.
        self._pinned = self.flags.tangential
        if self._pinned:
            extra_rows = extra_cols = [last * d + e for e in range(d)]
        else:
            extra_rows = [last * d + e for e in range(d) for _ in range(self.n)]
            extra_cols = [i * d + e for e in range(d) for i in range(self.n)]
        self._sp_rows = np.array(rows + extra_rows, dtype=np.int64)
        self._sp_cols = np.array(cols + extra_cols, dtype=np.int64)
        self._sp_src = np.array(src, dtype=np.int64)
        self._sp_sign = np.array(sgn)
        self._sp_shape = (m, m)

    def _solve(self, A: np.ndarray, c: np.ndarray) -> np.ndarray:
        if self.solver == "dense":
            M, rhs = self.k.assemble_dense(self.pi, self.pj, A, c)
            return self.k.solve_dense(M, rhs)
        return self._solve_sparse(A, c)

    def _solve_sparse(self, A: np.ndarray, c: np.ndarray) -> np.ndarray:
        d, m = self.d, self.n_unknowns
        data = A.reshape(-1)[self._sp_src] * self._sp_sign
        scale = float(np.abs(A).max()) or 1.0
        data = np.concatenate([data, np.full(self._sp_rows.size - data.size, scale)])
        M = sp.csc_matrix((data, (self._sp_rows, self._sp_cols)), shape=self._sp_shape)
        rhs = c.reshape(-1).copy()
        rhs[(self.n - 1) * d:] = 0.0
        if self._pinned:
            # rows sum to zero (translation null mode) and the last particle's equations
            # follow from the others, so the pinned solution plus a uniform shift solves all;
            # the pattern is structurally symmetric: minimum degree on A^T + A
            v = spla.splu(M, permc_spec="MMD_AT_PLUS_A").solve(rhs).reshape(self.n, d)
            return (v - v.mean(axis=0)).reshape(-1)
        return spla.lsqr(M, rhs, atol=1e-15, btol=1e-15, iter_lim=50 * m)[0]

    def _rhs_sparse(self, t: float, y: np.ndarray) -> np.ndarray:
        x, s, q = self.unpack(y)
        nv, r, h, a, zn, zt, f, A, b = self.k.pair_terms(x, s, q, self.pi, self.pj, self.p)
        c, _ = self.k.particle_terms(t, self.pi, self.pj, self.F0, self.p, f, b)
        v = self._solve_sparse(A, c)
        return self.k.rates(v, self.pi, self.pj, nv, r, a, zn, zt, s, q, self.p, self.n, self.d)
