"""``craquelure init SCENE --seed N --out FILE.nc``: build the initial state (positions,
mass-consistency masses, initial stress) and write it with provenance."""

from craquelure.commands import add_scene_arguments
from craquelure.io import write_dataset
from craquelure.models import stage
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene

NAME = "init"
HELP = "build the initial state of a scene and write it as netCDF"


def add_arguments(parser) -> None:
    add_scene_arguments(parser)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--out", required=True, help="output .nc file")
    parser.add_argument("--threads", type=int, default=None, help="numba threads")


def main(args) -> int:
    clock = WallClock()
    scene = load_scene(args.scene, args.overrides)
    ds = stage(scene.model, "build_initial_state")(scene, args.seed)
    ds.attrs.update(provenance_attrs(scene, args.seed, clock))
    write_dataset(ds, args.out)
    print(f"wrote {args.out}: {ds.sizes.get('particle', 0)} particles, "
          f"wall time {clock.elapsed:.1f} s")
    return 0
