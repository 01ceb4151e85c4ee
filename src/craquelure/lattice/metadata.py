"""CF metadata of the beam lattice (natural units of the lattice): title, references and the long
name and units of each variable, read by :func:`craquelure.cf.apply`."""

from craquelure.cf import ModelMetadata

_LENGTH_LATTICE = "L"
_TIME_LATTICE = "L sqrt(rho/E_b)"
_ENERGY_LATTICE = "E_b L^2"

METADATA = ModelMetadata(
    title="Beam-lattice fracture and flow (NUMFRAC style): discs bonded by breakable beams",
    references="J. A. Astrom et al., A particle based simulation model for glacier dynamics, "
               "The Cryosphere 7, 1591-1602 (2013); NUMFRAC PRACE white paper; project spec "
               "../shared/spec/lattice.md",
    reduced_unit_system="natural units of the lattice (lattice spec section 1): length L "
                        "(lattice spacing) = 1, disc density rho = 1, beam modulus E_b (k_n) = "
                        f"1; time {_TIME_LATTICE}, energy {_ENERGY_LATTICE} per unit "
                        "thickness, force E_b L",
    variables={
        "time": ("time of the energy sample", _TIME_LATTICE),
        "frame_time": ("time of the frame", _TIME_LATTICE),
        "kinetic": ("translational kinetic energy", _ENERGY_LATTICE),
        "rotational": ("rotational kinetic energy", _ENERGY_LATTICE),
        "elastic": ("elastic energy of the intact beams", _ENERGY_LATTICE),
        "contact": ("elastic energy of the contacts", _ENERGY_LATTICE),
        "external": ("potential energy of the external fields (gravity, buoyancy, bed)",
                     _ENERGY_LATTICE),
        "work": ("work done on the lattice by supports and drives", _ENERGY_LATTICE),
        "damping": ("energy dissipated by damping and friction", _ENERGY_LATTICE),
        "fracture": ("elastic energy released by broken beams", _ENERGY_LATTICE),
        "melting": ("energy removed with melted beams", _ENERGY_LATTICE),
        "total": ("energy balance: kinetic + potential - work + losses", _ENERGY_LATTICE),
        "broken": ("beams broken so far", "1"),
        "melted": ("beams melted so far", "1"),
        "load_ux": ("mean displacement x of the loaded particles", _LENGTH_LATTICE),
        "load_uy": ("mean displacement y of the loaded particles", _LENGTH_LATTICE),
        "drive_fx": ("force x exerted by the drive", "E_b L"),
        "drive_fy": ("force y exerted by the drive", "E_b L"),
        "x": ("position x", _LENGTH_LATTICE),
        "y": ("position y", _LENGTH_LATTICE),
        "theta": ("rotation of the particle", "rad"),
        "mass": ("particle mass", "rho L^2"),
        "body": ("label of the body the particle belongs to", "1"),
        "row": ("row of the particle in the lattice", "1"),
        "col": ("column of the particle in the lattice", "1"),
        "bond_i": ("index of the first particle of the beam", "1"),
        "bond_j": ("index of the second particle of the beam", "1"),
        "bond_state": ("beam state: 1 intact, 0 broken (other values: see the engine)", "1"),
        "bond_break_time": ("time the beam broke (NaN: never)", _TIME_LATTICE),
        "bond_unbreakable": ("1 if the beam can never break", "1"),
    },
)
