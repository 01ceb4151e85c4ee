"""``craquelure fragments RUN.nc --out FRAG.nc`` (:func:`craquelure.api.fragments`)."""

NAME = "fragments"
HELP = "label the fragments of a run dataset (drying: every snapshot; lattice: the last frame)"


def add_arguments(parser) -> None:
    parser.add_argument("run", help="run dataset written by `craquelure run` (drying or lattice)")
    parser.add_argument("--out", required=True, help="output fragment dataset (.nc)")
    parser.add_argument("--phi0", type=float, default=None,
                        help="paste threshold on the Shepard field (default: the scene's "
                             "outputs.binarisation_threshold, 0.8 in the paper)")
    parser.add_argument("--spacing", type=float, default=None,
                        help="mesh spacing in units of h (default: the scene's "
                             "outputs.binarisation_spacing, 0.01 in the paper)")
    parser.add_argument("--threads", type=int, default=None, help="numba threads")


def main(args) -> int:
    from craquelure.api import fragments

    fragments(args.run, args.out, args.phi0, args.spacing)
    print(f"wrote {args.out}")
    return 0
