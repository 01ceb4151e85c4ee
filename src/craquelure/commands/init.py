"""``craquelure init SCENE --seed N --out FILE.nc`` (:func:`craquelure.api.initial_state`)."""

from craquelure import api
from craquelure.commands import add_scene_arguments
from craquelure.io import write_dataset

NAME = "init"
HELP = "build the initial state of a scene and write it as netCDF"


def add_arguments(parser) -> None:
    add_scene_arguments(parser)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--out", required=True, help="output .nc file")
    parser.add_argument("--threads", type=int, default=None, help="numba threads")


def main(args) -> int:
    ds = api.initial_state(api.load_scene(args.scene, args.overrides), args.seed)
    write_dataset(ds, args.out)
    print(f"wrote {args.out}: {ds.sizes.get('particle', 0)} particles, "
          f"wall time {ds.attrs['wall_time_s']:.1f} s")
    return 0
