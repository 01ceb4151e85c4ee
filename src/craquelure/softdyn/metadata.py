"""CF metadata of Soft Dynamics (reduced units of R, E and eta): title, references and the long
name and units of each variable, read by :func:`craquelure.cf.apply`."""

from craquelure.cf import ModelMetadata

METADATA = ModelMetadata(
    title="Soft Dynamics: elastic spheres in a viscous fluid (normal approach, T1 "
          "rearrangement)",
    references="P. Rognon, C. Gay, Soft Dynamics simulation: 1. Normal approach of two "
               "deformable particles in a viscous fluid and optimal-approach strategy, Eur. "
               "Phys. J. E 27, 253 (2008), arXiv:0803.1573; 2. Elastic spheres undergoing a T1 "
               "process in a viscous fluid, arXiv:0901.0171 (2009); project spec "
               "../shared/spec/softdyn.md",
    reduced_unit_system="softdyn spec section 1: length R (sphere radius), force F_v (the "
                        "tension driving the T1), time tau = eta R^2/F_v (Stokes time); E R^2 "
                        "and eta R are the elastic and viscous scales",
    variables={
        "time": ("time", "tau"),
        "position": ("centre position", "R"),
        "velocity": ("centre velocity", "R/tau"),
        "load": ("applied force", "F_v"),
        "gap": ("surface-to-surface gap h", "R"),
        "interaction_radius": ("radius a of the interaction region", "R"),
        "force_tangential": ("tangential pair force |f_t|", "F_v"),
        "zeta_n": ("normal lubrication friction coefficient", "eta R"),
        "zeta_t": ("tangential lubrication friction coefficient", "eta R"),
        "particle": ("sphere label", None),
        "pair": ("pair label", None),
        # initial state: the two spheres of each pair, as indices along "particle"
        "pair_i": ("index (along particle) of the first sphere of the pair", "1"),
        "pair_j": ("index (along particle) of the second sphere of the pair", "1"),
        "dim": ("Cartesian component", None),
        "point": ("grid point of the sweep", "1"),
        "h0": ("initial gap h0", "R"),
        "force": ("reduced force F~", "1"),
        "h_star": ("Hertz gap h* = R (F~/k_n)^(2/3)", "R"),
        "duration": ("T1 duration (CD force reaches phi F_v)", "tau"),
        "finished": ("1 if the T1 ended before outputs.t_end", "1"),
        "computed": ("1 if the point is inside study.window and was run", "1"),
        "theta_end": ("angle AC-AB at the end", "degree"),
        "T_P": ("Poiseuille prediction c_n ln(R/h0) (Eq. 33)", "tau"),
        "T_H": ("Hertz prediction (c_n/2)(h*/h0)^2 (Eq. 34)", "tau"),
        "T_sep": ("quadrature of the AB opening time (section 7)", "tau"),
        "h0_over_h_star": ("h0/h*, h* = R (F~/k_n)^(2/3)", "1"),
        "regime": ("hertz (h0/h* <= 1/3), poiseuille (>= 3) or crossover", None),
        "n_rhs": ("right-hand-side evaluations", "1"),
        "n_steps": ("time steps", "1"),
        "run_wall_time_s": ("wall time of the run", "s"),
        "integrator": ("time integrator", None),
        "rtol": ("relative tolerance of the adaptive integrator", "1"),
        "dt": ("fixed time step", "tau"),
        "theta": ("angle between AC and AB", "degree"),
        # accuracy study: adaptive integrators (integrator, rtol) and fixed-step Heun (dt)
        "adaptive_duration": ("T1 duration, adaptive integrator", "tau"),
        "adaptive_n_rhs": ("right-hand-side evaluations, adaptive integrator", "1"),
        "adaptive_wall_time_s": ("wall time, adaptive integrator", "s"),
        "heun_duration": ("T1 duration, fixed-step Heun", "tau"),
        "heun_n_rhs": ("right-hand-side evaluations, fixed-step Heun", "1"),
        "heun_wall_time_s": ("wall time, fixed-step Heun", "s"),
        "heun_stable": ("1 if the fixed-step Heun run stayed stable", "1"),
        # T1 occurrence scan (fh_over_fv, force)
        "fh_over_fv": ("load ratio F_h/F_v", "1"),
        "occurred": ("1 if theta reached theta_end before t_end", "1"),
        "predicted": ("1 if F_h < F_v/sqrt3 (AB in tension, Eq. 27)", "1"),
        "f_ab_end": ("normal force of pair AB at the end", "F_v"),
        "f_v": ("vertical load F_v", "E R^2"),
        "f_h": ("horizontal load F_h", "E R^2"),
        "tau": ("Stokes time tau = eta R^2/F_v", "eta/E"),
    },
)
