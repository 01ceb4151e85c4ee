"""CF metadata of concrete impact (SI, 2D per unit thickness; a 3D dataset through
:func:`craquelure.cf.per_body`): title, references and the long name and units of each
variable, read by :func:`craquelure.cf.apply`."""

from craquelure.cf import ModelMetadata

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
        "x": ("final position x", "m"),
        "y": ("final position y", "m"),
        "vx": ("final velocity x", "m s-1"),
        "vy": ("final velocity y", "m s-1"),
        "damage": ("final damage D", "1"),
        "softening": ("final softening s = (eps_max - eps_0)/(eps_f - eps_0)", "1"),
        "plastic_strain": ("final equivalent plastic strain", "1"),
        "plastic_compaction": ("final plastic volumetric compaction on the cap", "1"),
        "h": ("final smoothing length", "m"),
        "rho": ("final density", "kg m-3"),
        "series_contact_force_penalty": ("base contact force per unit thickness (penalty "
                                         "force at the sample time)", "N m-1"),
        "series_kinetic": ("kinetic energy per unit thickness", "J m-1"),
        "series_internal": ("internal energy per unit thickness", "J m-1"),
        "series_elastic": ("elastic strain energy per unit thickness", "J m-1"),
        "series_plastic": ("plastic work per unit thickness", "J m-1"),
        "series_damage": ("energy dissipated by damage (released secant energy) per unit "
                          "thickness", "J m-1"),
        "series_unattributed": ("internal energy not elastic, plastic nor damage per unit "
                                "thickness", "J m-1"),
        "series_viscous": ("energy dissipated by artificial viscosity per unit thickness",
                           "J m-1"),
        "series_artificial_stress": ("energy of the artificial stress per unit thickness",
                                     "J m-1"),
        "series_penalty": ("energy stored in the contact penalty per unit thickness", "J m-1"),
        "series_kinematic_removed": ("energy removed by the kinematic contact constraint per "
                                     "unit thickness", "J m-1"),
        "series_balance_error": ("relative energy balance error (E(t) - E0)/E0", "1"),
        "series_momentum_y": ("total momentum y per unit thickness", "kg s-1"),
        "series_vcm_y": ("centre-of-mass velocity y", "m s-1"),
        "series_cracked_fraction": ("fraction of cracked particles", "1"),
        "series_impulse": ("impulse transmitted to the base per unit thickness", "N s m-1"),
        "snap_x": ("position x", "m"),
        "snap_y": ("position y", "m"),
        "snap_damage": ("damage D", "1"),
        "snap_softening": ("softening s = (eps_max - eps_0)/(eps_f - eps_0)", "1"),
        "snap_plastic_strain": ("equivalent plastic strain", "1"),
    },
)
