"""``craquelure run SCENE --out RUN.nc`` (:func:`craquelure.api.run_to_file`). Exit status: 0
done; 2 a clear error; 3 stopped by SIGTERM or SIGINT after writing its checkpoint (run again
with ``--resume``, which also starts from the beginning when there is no checkpoint)."""

from craquelure import api
from craquelure.commands import add_scene_arguments

NAME = "run"
HELP = "simulate a scene and write the run dataset"


def add_arguments(parser) -> None:
    add_scene_arguments(parser)
    parser.add_argument("--out", required=True, help="output .nc file")
    parser.add_argument("--init", default=None, help="initial state from `craquelure init`")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--resume", action="store_true",
                        help="continue from the last checkpoint next to --out")
    parser.add_argument("--threads", type=int, default=None, help="numba threads")
    parser.add_argument("--checkpoint-every", type=int, default=None, metavar="K",
                        help="checkpoint every K steps (lattice: frames; softdyn: study points; "
                             "default: the scene's numerics.checkpoint_every, else off)")
    parser.add_argument("--checkpoint-minutes", type=float, default=None, metavar="M",
                        help="and every M minutes of wall time (default 10; 0: off)")


def main(args) -> int:
    out = api.run_to_file(api.load_scene(args.scene, args.overrides), args.out, seed=args.seed,
                          init=args.init, resume=args.resume,
                          checkpoint_every=args.checkpoint_every,
                          checkpoint_minutes=args.checkpoint_minutes)
    print(f"wrote {out}")
    return 0
