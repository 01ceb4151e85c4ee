"""``craquelure export RUN.nc [--to vtu|xyz] [--out BASE]`` (:func:`craquelure.api.export`)."""

NAME = "export"
HELP = "export a run dataset for ParaView (.pvd of VTU point clouds) and OVITO (extended XYZ)"


def add_arguments(parser) -> None:
    from craquelure.export_formats import FORMATS

    parser.add_argument("run", help="run dataset (.nc) of any model")
    parser.add_argument("--to", default="vtu", choices=FORMATS,
                        help="vtu: .pvd series + extended XYZ (default); xyz: extended XYZ only")
    parser.add_argument("--out", default=None, help="output base path (default: RUN without .nc)")


def main(args) -> int:
    from craquelure.api import export

    for path in export(args.run, args.to, args.out):
        print(f"wrote {path}")
    return 0
