"""The lattice engine: a struct-of-arrays system (:class:`LatticeState`) and the time loop
around the generated kernel (:class:`Engine`: chunks of steps, contact-list rebuilds and
re-freezing of bonds between them, the NaN/runaway guard). Stable step (spec section 5): the
quick estimate omega_est^2 = max_i max(2 sum_j k_ij/m_i, 2 sum_j k_theta,ij/J_i), k = max(k_n, k_s).
"""

import math
import time
from dataclasses import dataclass, field

import numba
import numpy as np

from craquelure.codegen import effect_flags, specialise
from craquelure.lattice.geometry import INTACT, find_bonds, search_box
from craquelure.lattice.kernel_template import PARAMS
from craquelure.periodic import minimum_image
from craquelure.registry import kernel_parameters, parameter_vector
from craquelure.runner import Divergence, diverged, heartbeat, non_finite
from craquelure.sph.neighbours import neighbour_list

# below this many bonds a serial kernel is faster (thread start-up per parallel region;
# benchmarks/lattice_engine.py)
PARALLEL_MIN_BONDS = 20000
# per-step displacements within this many rounding units of the positions: the energy budget
# is lost to round-off (the guard then says to raise the step, not to lower it)
ROUND_OFF_STEPS = 1000


KERNEL_TEMPLATE = "craquelure.lattice.kernel_template"


def kernel_flags(effects, periodic_x: bool, node_averaged: bool, bending: bool,
                 parallel: bool) -> dict[str, bool]:
    """Flags of the kernel template: the effects' (from the registry) and the engine options."""
    flags = effect_flags("lattice", effects)
    flags["PERIODIC_X"] = bool(periodic_x)
    flags["NODE_AVERAGED"] = bool(node_averaged) and flags["FRACTURE"]
    flags["BENDING"] = bool(bending) and flags["FRACTURE"]
    flags["PARALLEL"] = bool(parallel)
    return flags


@dataclass
class LatticeState:
    x: np.ndarray
    y: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    diameter: np.ndarray
    bi: np.ndarray
    bj: np.ndarray
    kn: np.ndarray
    ka: np.ndarray
    kb: np.ndarray
    theta: np.ndarray | None = None
    fix: np.ndarray | None = None      # (3, n) uint8: x, y, theta clamped
    drive: np.ndarray | None = None    # (2, n) uint8: x, y prescribed by the drive
    load: np.ndarray | None = None     # (2, n) external load
    unbreakable: np.ndarray | None = None
    state: np.ndarray | None = None
    period_x: float = 0.0
    L: float = 1.0

    def __post_init__(self):
        n, nb = self.x.size, self.bi.size
        self.x = np.ascontiguousarray(self.x, np.float64)
        self.y = np.ascontiguousarray(self.y, np.float64)
        for name, default in (("theta", np.zeros(n)), ("fix", np.zeros((3, n), np.uint8)),
                              ("drive", np.zeros((2, n), np.uint8)), ("load", np.zeros((2, n))),
                              ("unbreakable", np.zeros(nb, np.uint8)),
                              ("state", np.full(nb, INTACT, np.int8))):
            if getattr(self, name) is None:
                setattr(self, name, default)

    @property
    def n(self) -> int:
        return self.x.size


def rest_state(x, y, theta, bi, bj, period_x: float = 0.0) -> np.ndarray:
    """(5, nb): L0, cos alpha0, sin alpha0 (rest chord direction), theta_i ref, theta_j ref
    of bonds made stress-free in this configuration."""
    dx = x[bj] - x[bi]
    if period_x > 0:
        dx = minimum_image(dx, period_x)
    dy = y[bj] - y[bi]
    ell = np.hypot(dx, dy)
    return np.vstack([ell, dx / ell, dy / ell, theta[bi], theta[bj]])


def csr_bonds(n: int, bi: np.ndarray, bj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Particle -> bond CSR (bond ids of each particle, in bond order)."""
    ends = np.concatenate([bi, bj])
    ids = np.concatenate([np.arange(bi.size), np.arange(bj.size)])
    order = np.lexsort((ids, ends))
    counts = np.bincount(ends, minlength=n)
    off = np.zeros(n + 1, np.int64)
    np.cumsum(counts, out=off[1:])
    return off, ids[order].astype(np.int64)


def chunks(n: int, bi: np.ndarray, bj: np.ndarray, nchunk: int
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Work split of the kernel: bond chunk bounds (nchunk + 1), the node range [lo, hi) of
    the ends of each bond chunk (2, nchunk) and particle chunk bounds (nchunk + 1)."""
    cb = np.linspace(0, bi.size, nchunk + 1).round().astype(np.int64)
    crange = np.zeros((2, nchunk), np.int64)
    for c in range(nchunk):
        lo, hi = cb[c], cb[c + 1]
        if hi > lo:
            crange[0, c] = min(bi[lo:hi].min(), bj[lo:hi].min())
            crange[1, c] = max(bi[lo:hi].max(), bj[lo:hi].max()) + 1
    cn = np.linspace(0, n, nchunk + 1).round().astype(np.int64)
    return cb, crange, cn


def pair_keys(i: np.ndarray, j: np.ndarray, n: int) -> np.ndarray:
    """One integer per ordered pair (i, j) of n particles: i n + j (re-freezing tests its
    candidate pairs against the bond list with np.isin on these, not with Python sets of
    tuples)."""
    return np.asarray(i, np.int64) * n + np.asarray(j, np.int64)


@numba.njit(cache=True)
def unbonded_pairs(off, idx, poff, pidx, bi, bj, state):
    """Pairs i < j of the neighbour list (CSR off, idx) not an intact bond (bi, bj), in list
    order (i ascending, then as listed). Compiled, because a fracture run rebuilds its contact
    list after every step that breaks a beam: marking each particle's bonded partners (bond
    CSR poff, pidx) costs O(bonds)."""
    n = off.size - 1
    mark = np.full(n, -1, np.int64)
    ci = np.empty(idx.size, np.int64)
    cj = np.empty(idx.size, np.int64)
    m = 0
    for i in range(n):
        for kk in range(poff[i], poff[i + 1]):
            b = pidx[kk]
            if state[b] == INTACT and bi[b] == i:  # bonds are stored i < j
                mark[bj[b]] = i
        for kk in range(off[i], off[i + 1]):
            j = idx[kk]
            if i < j and mark[j] != i:
                ci[m] = i
                cj[m] = j
                m += 1
    return ci[:m].copy(), cj[:m].copy()


def stable_step_estimate(system: LatticeState) -> float:
    """2/omega_est with the spec's quick estimate (safe by 1.16-1.37 for the triangular
    lattice)."""
    ks = 2.0 * (system.ka + system.kb) / system.L**2
    k = np.maximum(system.kn, ks)
    kt = system.ka
    live = system.state == INTACT
    sk = np.bincount(system.bi[live], k[live], system.n) + np.bincount(system.bj[live], k[live],
                                                                        system.n)
    st = np.bincount(system.bi[live], kt[live], system.n) + np.bincount(system.bj[live],
                                                                         kt[live], system.n)
    w2 = max(float(np.max(2 * sk / system.mass)), float(np.max(2 * st / system.inertia)))
    return 2.0 / math.sqrt(w2) if w2 > 0 else math.inf


def schema_owned() -> dict[str, str]:
    """``{parameter: scene path}`` of the kernel parameters whose default the schema holds
    (declared with a NaN neutral value)."""
    return {name: p.path for name, (p, _) in kernel_parameters("lattice").items()
            if math.isnan(p.neutral)}


def require_schema_owned(p: np.ndarray, effects) -> None:
    """The schema-owned parameters the effect set reads (contact's skin and friction
    regularisation with contact, the energy check's tolerance always) must come from the scene
    (or the schema for a probe): their neutral value is NaN, so a caller that forgets one stops
    here instead of running on a second copy of the default."""
    missing = [name for name, (prm, owners) in kernel_parameters("lattice").items()
               if math.isnan(prm.neutral) and math.isnan(p[PARAMS.index(name)])
               and (not owners or owners & set(effects))]
    if missing:
        raise ValueError(f"lattice engine: parameter(s) {', '.join(missing)} not given; they "
                         "come from the resolved scene (engine_params) or, for a system that "
                         "is not a scene's, from probe_engine (the schema's defaults)")


@dataclass
class Engine:
    """Time integration of a :class:`LatticeState` with a given effect set (kernel flags) and
    the resolved scene's options (:func:`.initial_state.engine_options`)."""

    system: LatticeState
    effects: tuple[str, ...]
    params: dict
    series_every: int
    node_averaged: bool
    bending: bool
    freeze_every: int  # 0: no re-freezing (melting off)
    refreeze_radius: float
    seed: int = 0
    step: int = 0
    series: list = field(default_factory=list)
    parallel: bool | None = None  # None: parallel kernel for large systems on > 1 thread

    def __post_init__(self):
        s = self.system
        parallel = self.parallel
        if parallel is None:
            parallel = s.bi.size >= PARALLEL_MIN_BONDS and numba.get_num_threads() > 1
        self.flags = kernel_flags(self.effects, s.period_x > 0, self.node_averaged,
                                  self.bending, parallel)
        self.kernel = specialise(KERNEL_TEMPLATE, self.flags, "lattice")
        self.p = parameter_vector("lattice", values={**self.params, "period_x": s.period_x})
        require_schema_owned(self.p, self.effects)
        self.dt = float(self.p[PARAMS.index("dt")])
        self.q = np.ascontiguousarray(np.vstack([s.x, s.y, s.theta]))
        self.qm = self.q.copy()
        self.qref = self.q[:2].copy()
        self.qbuild = self.q[:2].copy()
        self.bref = rest_state(s.x, s.y, s.theta, s.bi, s.bj, s.period_x)
        self.bk = np.ascontiguousarray(np.vstack([s.kn, s.ka, s.kb]))
        self._alloc_bond_arrays()
        self.acc = np.zeros(self.kernel.N_ACC)
        self.fc = np.zeros((2, s.n))
        self.cpi = np.zeros(0, np.int64)
        self.cpj = np.zeros(0, np.int64)
        if self.flags["CONTACT"]:
            self.rebuild_contacts()

    def _alloc_bond_arrays(self):
        s = self.system
        nb = s.bi.size
        self.bprev = np.zeros((6, nb))
        self.kernel.bond_deformations(self.qm, s.bi, s.bj, self.bref, s.state, s.period_x,
                                      self.bprev)
        self.bforce = np.zeros((4, nb))
        self.benergy = np.zeros(nb)
        self.bratio = np.zeros(nb)
        self.tbreak = np.full(nb, -1.0)
        self.poff, self.pidx = csr_bonds(s.n, s.bi, s.bj)
        self.cb, self.crange, self.cn = chunks(s.n, s.bi, s.bj, self.kernel.NCHUNK)
        self.fn = np.zeros((self.kernel.NCHUNK, 3, s.n))

    def set_velocity(self, vx, vy, omega=None):
        """Set x(t - dt) so that the backward velocity is (vx, vy, omega)."""
        self.qm[0] = self.q[0] - self.dt * np.asarray(vx)
        self.qm[1] = self.q[1] - self.dt * np.asarray(vy)
        if omega is not None:
            self.qm[2] = self.q[2] - self.dt * np.asarray(omega)
        s = self.system
        self.kernel.bond_deformations(self.qm, s.bi, s.bj, self.bref, s.state, s.period_x,
                                      self.bprev)

    @property
    def time(self) -> float:
        return self.step * self.dt

    def _neighbours(self, radius):
        """Neighbour list of the current positions (x wrapped into one period)."""
        x, y, period = self.q[0], self.q[1], self.system.period_x
        if period > 0:
            x = np.mod(x - x.min(), period) + x.min()
        return neighbour_list(x, y, radius, search_box(x, y, radius, period))

    def rebuild_contacts(self):
        """Verlet list of unbonded (or broken-bond) pairs within d_max + skin."""
        s = self.system
        off, idx = self._neighbours(float(s.diameter.max()) + float(self.p[PARAMS.index("skin")]))
        self.cpi, self.cpj = unbonded_pairs(off, idx, self.poff, self.pidx, s.bi, s.bj, s.state)
        self.qbuild = self.q[:2].copy()

    def refreeze(self):
        """New stress-free beams between unbonded pairs closer than r_f L (melting)."""
        s = self.system
        off, idx = self._neighbours(self.refreeze_radius * s.L)
        i = np.repeat(np.arange(s.n), np.diff(off))
        keep = i < idx
        i, j = i[keep], idx[keep]
        new = ~np.isin(pair_keys(i, j, s.n), pair_keys(s.bi, s.bj, s.n))
        if not new.any():
            return 0
        ni = np.ascontiguousarray(i[new], np.int64)
        nj = np.ascontiguousarray(j[new], np.int64)
        # stiffness of a new beam: that of the first beam (uniform lattices) [D]
        s.bi, s.bj = np.concatenate([s.bi, ni]), np.concatenate([s.bj, nj])
        for name in ("kn", "ka", "kb"):
            arr = getattr(s, name)
            setattr(s, name, np.concatenate([arr, np.full(ni.size, arr[0])]))
        s.state = np.concatenate([s.state, np.full(ni.size, INTACT, np.int8)])
        s.unbreakable = np.concatenate([s.unbreakable, np.zeros(ni.size, np.uint8)])
        self.bref = np.ascontiguousarray(np.hstack([
            self.bref, rest_state(self.q[0], self.q[1], self.q[2], ni, nj, s.period_x)]))
        self.bk = np.ascontiguousarray(np.vstack([s.kn, s.ka, s.kb]))
        tb = self.tbreak
        self._alloc_bond_arrays()
        self.tbreak[: tb.size] = tb
        return ni.size

    def run(self, n_steps: int) -> None:
        """Advance n_steps; appends energy-series rows to ``self.series``; raises
        :class:`SimulationDiverged` when the kernel's guard fails."""
        bad = self.advance(n_steps)
        if bad is not None:
            raise diverged("lattice", bad, self.step, self.time)

    # wall time of one kernel call (s): between calls the runner's heartbeat prints progress
    # and stops the run at a signal, so that a long frame is interrupted inside
    HEARTBEAT_S = 0.5

    def advance(self, n_steps: int) -> Divergence | None:
        """Advance n_steps (fewer when the kernel's NaN/runaway guard stops it: then the
        failed check is returned).

        The steps of a chunk run in kernel calls of about :attr:`HEARTBEAT_S` of wall time,
        with :func:`~craquelure.runner.heartbeat` before each (it raises
        :class:`~craquelure.runner.Interrupted` at a stop signal, the state then being that of
        the last call's end). Only the call that ends a chunk records the end-of-call series
        row, so where the calls end changes nothing in the trajectory or the series."""
        k = self.kernel
        remaining = int(n_steps)
        buf = np.zeros((remaining // self.series_every + 2, k.N_SERIES))
        per_call = 8
        while remaining > 0:
            heartbeat()
            chunk = remaining
            if self.freeze_every and self.flags["MELTING"]:
                chunk = min(chunk, self.freeze_every - self.step % self.freeze_every)
            call = min(chunk, per_call)
            began = time.perf_counter()
            try:
                status, done, rows = self._advance(call, buf, call == chunk)
            except ArithmeticError as exc:  # numba raises division by zero as Python does
                return Divergence("finite", f"the state can no longer be computed "
                                  f"({type(exc).__name__}: {exc}) at dt = {self.dt:.6g}; "
                                  f"check the loads and numerics.dt_factor")
            if done == call:  # aim the next call at HEARTBEAT_S (at most 4x longer)
                spent = max(time.perf_counter() - began, 1e-6)
                per_call = max(1, min(4 * call, int(call * self.HEARTBEAT_S / spent)))
            self.series.extend(buf[:rows].copy())
            self.step += done
            remaining -= done
            if status == k.NAN or status == k.RUNAWAY:
                return self._divergence(status)
            if status == k.REBUILD:
                self.rebuild_contacts()
            if (self.freeze_every and self.flags["MELTING"]
                    and self.step % self.freeze_every == 0):
                self.refreeze()
                if self.flags["CONTACT"]:
                    self.rebuild_contacts()
        return None

    def _divergence(self, status: int) -> Divergence:
        hint = f" at dt = {self.dt:.6g}; reduce numerics.dt_factor or check loads"
        if status == self.kernel.NAN:
            bad = non_finite({"position": self.q, "previous position": self.qm})
            return Divergence("finite", "NaN/inf in the energy" + hint,
                              bad.particle if bad is not None else None)
        last = self.series[-1]
        v = (self.q - self.qm) / self.dt
        ke = 0.5 * self.system.mass * (v[0] ** 2 + v[1] ** 2)
        step = float(np.abs(self.q[:2] - self.qm[:2]).max())
        size = float(np.abs(self.q[:2]).max())
        if step < ROUND_OFF_STEPS * np.finfo(float).eps * size:
            hint = (f" at dt = {self.dt:.6g}, but the step is too small for the positions to "
                    f"resolve the motion (largest displacement per step {step:.3g} against "
                    f"positions up to {size:.3g}, within {ROUND_OFF_STEPS} rounding units): "
                    f"increase numerics.dt_factor")
        return Divergence("runaway", f"energy ran away: E_tot = {last[10]:.6g} vs E_0 = "
                          f"{self.acc[6]:.6g}" + hint, int(np.argmax(ke)))

    def _advance(self, chunk: int, buf: np.ndarray, ends_chunk: bool = True):
        s, k = self.system, self.kernel
        return k.advance(
            self.qm, self.q, self.qref, self.qbuild, s.mass, s.inertia,
            s.diameter, s.fix, s.drive, s.load, s.bi, s.bj, self.bref, self.bk, s.state,
            s.unbreakable, self.bprev, self.bforce, self.benergy, self.bratio, self.tbreak,
            self.poff, self.pidx, self.cb, self.crange, self.cn, self.fn, self.cpi,
            self.cpj, self.fc, self.p, self.acc, self.seed, self.step, chunk,
            self.series_every, int(ends_chunk), buf)

    # bond-indexed arrays of the engine (rows, bond) and of the system (bond) in a checkpoint
    BOND_STATE = ("bref", "bk", "bprev", "bforce", "benergy", "bratio", "tbreak")
    SYSTEM_BONDS = ("bi", "bj", "kn", "ka", "kb", "state", "unbreakable")

    def state(self) -> dict[str, np.ndarray]:
        """Everything that evolves (configurations, bond rest states and history, bond list,
        contact list, accumulators, energy series, step); particle constants are rebuilt from
        the scene. Taking it changes nothing, so a checkpoint may be written at any chunk."""
        s = self.system
        out = {name: getattr(self, name).copy() for name in ("qm", "q", "qref", "qbuild", "acc",
                                                            "cpi", "cpj", *self.BOND_STATE)}
        out.update({name: getattr(s, name).copy() for name in self.SYSTEM_BONDS})
        out["series"] = self.series_array()
        out["step"] = np.array(self.step)
        return out

    def restore(self, ck: dict[str, np.ndarray]) -> None:
        """Continue from :meth:`state` (bit-identical to the uninterrupted run)."""
        s = self.system
        for name in self.SYSTEM_BONDS:
            setattr(s, name, np.ascontiguousarray(ck[name]).astype(getattr(s, name).dtype))
        self._alloc_bond_arrays()
        for name in ("qm", "q", "qref", "qbuild", "acc", *self.BOND_STATE):
            setattr(self, name, np.ascontiguousarray(ck[name], np.float64))
        self.cpi, self.cpj = (np.ascontiguousarray(ck[k], np.int64) for k in ("cpi", "cpj"))
        self.step = int(ck["step"])
        self.series = list(np.asarray(ck["series"]).reshape(-1, self.kernel.N_SERIES))

    def series_array(self) -> np.ndarray:
        return np.array(self.series).reshape(-1, self.kernel.N_SERIES)


def lattice_system(x, y, L=1.0, *, kn, ka, kb, rho=1.0, period_x=0.0,  # noqa: N803
                   body=None) -> LatticeState:
    """Discs of diameter L (mass rho pi L^2/4, J = m L^2/8) bonded to neighbours closer than
    1.1 L with uniform stiffnesses."""
    n = x.size
    body = np.zeros(n, np.int64) if body is None else body
    bi, bj = find_bonds(x, y, body, L, period_x)
    m = rho * math.pi * L * L / 4.0
    nb = bi.size
    return LatticeState(x=x, y=y, mass=np.full(n, m), inertia=np.full(n, m * L * L / 8.0),
                  diameter=np.full(n, L), bi=bi, bj=bj, kn=np.full(nb, kn),
                  ka=np.full(nb, ka), kb=np.full(nb, kb), period_x=period_x, L=L)
