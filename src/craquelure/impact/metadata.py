"""CF metadata of concrete impact (SI, 2D per unit thickness; a 3D dataset through
:func:`craquelure.cf.per_body`): title, references and the long name and units of each
variable, read by :func:`craquelure.cf.apply`."""

from craquelure.cf import ModelMetadata

# the final fields and their snapshots (snap_<name>)
FIELDS = {"x": ("position x", "m"), "y": ("position y", "m"), "damage": ("damage D", "1"),
          "softening": ("softening s = (eps_max - eps_0)/(eps_f - eps_0)", "1"),
          "plastic_strain": ("equivalent plastic strain", "1")}
# the energy series (series_<name>), per unit thickness in J m-1
ENERGIES = {"kinetic": "kinetic energy", "internal": "internal energy",
            "elastic": "elastic strain energy", "plastic": "plastic work",
            "damage": "energy dissipated by damage (released secant energy)",
            "unattributed": "internal energy not elastic, plastic nor damage",
            "viscous": "energy dissipated by artificial viscosity",
            "artificial_stress": "energy of the artificial stress",
            "penalty": "energy stored in the contact penalty",
            "kinematic_removed": "energy removed by the kinematic contact constraint"}

# Impact: the spec's SI units, 2D per unit out-of-plane thickness.
METADATA = ModelMetadata(
    title="Concrete impact: SPH concrete disc (2D slice or 3D) with random particle masses "
          "hitting a rigid base",
    references="M. Husek, F. Hokes, J. Kala, P. Kral, Inclusion of Randomness into SPH "
               "Simulations, WSEAS Transactions; J. Kala, M. Husek, Effect of the support "
               "domain size in SPH fracture simulations, Shock Vib. 2016; project spec "
               "../shared/spec/impact.md",
    variables={
        "time": ("simulated time", "s"),
        "snapshot_time": ("simulated time of the snapshot", "s"),
        "x0": ("initial position x", "m"),
        "y0": ("initial position y", "m"),
        "z0": ("initial position z along the disc axis (3D)", "m"),
        "z": ("final position z (3D)", "m"),
        "vz": ("final velocity z (3D)", "m s-1"),
        "mass": ("particle mass per unit thickness", "kg m-1"),
        "precrack": ("1 if the particle is on a pre-crack", "1"),
        **{name: (f"final {long}", unit) for name, (long, unit) in FIELDS.items()},
        "vx": ("final velocity x", "m s-1"),
        "vy": ("final velocity y", "m s-1"),
        "plastic_compaction": ("final plastic volumetric compaction on the cap", "1"),
        "h": ("final smoothing length", "m"),
        "rho": ("final density", "kg m-3"),
        "series_contact_force_penalty": ("base contact force per unit thickness (penalty "
                                         "force at the sample time)", "N m-1"),
        **{f"series_{name}": (f"{long} per unit thickness", "J m-1")
           for name, long in ENERGIES.items()},
        "series_balance_error": ("relative energy balance error (E(t) - E0)/E0", "1"),
        "series_momentum_y": ("total momentum y per unit thickness", "kg s-1"),
        "series_vcm_y": ("centre-of-mass velocity y", "m s-1"),
        "series_cracked_fraction": ("fraction of cracked particles", "1"),
        "series_impulse": ("impulse transmitted to the base per unit thickness", "N s m-1"),
        **{f"snap_{name}": v for name, v in FIELDS.items()},
    },
)
