"""``craquelure campaign FRAG.nc ... --out CAMPAIGN.nc``: aggregate the per-seed fragment
datasets of one drying scene over seeds (drying spec section 10)."""

from craquelure.errors import CraquelureError

NAME = "campaign"
HELP = "aggregate per-seed fragment datasets over seeds (pooled <S>_t, P(S;t), scaled P(X))"


def add_arguments(parser) -> None:
    parser.add_argument("fragments", nargs="+", help="fragment datasets, one per seed")
    parser.add_argument("--out", required=True, help="output campaign dataset (.nc)")
    parser.add_argument("--bins", type=int, default=30, help="histogram bins")
    parser.add_argument("--window", default="paper",
                        help="statistics window: 'paper' (the paper's t = 180-300 rescaled by "
                             "t*) or 'all_broken' (from the first snapshot with every sample "
                             "broken to the end)")
    parser.add_argument("--labelling", default="periodic",
                        help="fragments counted: 'periodic' (labelled on the torus) or 'open' "
                             "(the image as a plain rectangle, its edges cut fragments)")


def main(args) -> int:
    from pathlib import Path

    from craquelure.models import model_module

    campaign = model_module("drying", "campaign")  # campaigns of drying fragment datasets
    windows = model_module("drying", "time_scales")
    missing = [p for p in args.fragments if not Path(p).is_file()]
    if missing:
        raise CraquelureError(f"fragment datasets not found: {', '.join(missing)}")
    if args.bins < 2:
        raise CraquelureError(f"--bins {args.bins} is not allowed; must be >= 2")
    for option, value, allowed in (("--window", args.window, windows.WINDOW_MODES),
                                   ("--labelling", args.labelling, campaign.LABELLINGS)):
        if value not in allowed:
            raise CraquelureError(f"{option} {value} is not allowed; allowed values: "
                                  f"{', '.join(allowed)}")
    out = campaign.campaign_from_files(args.fragments, args.out, args.bins, args.window,
                                       args.labelling)
    print(f"wrote {out}")
    return 0
