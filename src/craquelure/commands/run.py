"""``craquelure run SCENE --out RUN.nc [--init STATE.nc] [--seed N] [--resume]``: simulate a
scene and write the run dataset (checkpointing as it goes)."""

import sys
from pathlib import Path

from craquelure.commands import add_scene_arguments
from craquelure.models import checkpoints, stage
from craquelure.scene import load_scene

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


def main(args) -> int:
    if args.threads:
        import numba

        numba.set_num_threads(args.threads)
    scene = load_scene(args.scene, args.overrides)
    if args.resume and not checkpoints(scene.model):
        print(f"--resume: {scene.model} runs are short and write no checkpoints; starting "
              f"from the beginning", file=sys.stderr)
    out = stage(scene.model, "run")(scene, Path(args.out), seed=args.seed,
                                    init=Path(args.init) if args.init else None,
                                    resume=args.resume)
    print(f"wrote {out}")
    return 0
