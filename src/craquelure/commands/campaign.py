"""``craquelure campaign FRAG1.nc FRAG2.nc ... --out CAMPAIGN.nc [--bins 30]``: aggregate the
per-seed fragment datasets of one drying scene over seeds (drying spec section 10)."""

from craquelure.errors import CraquelureError

NAME = "campaign"
HELP = "aggregate per-seed fragment datasets over seeds (pooled <S>_t, P(S;t), scaled P(X))"


def add_arguments(parser) -> None:
    parser.add_argument("fragments", nargs="+", help="fragment datasets, one per seed")
    parser.add_argument("--out", required=True, help="output campaign dataset (.nc)")
    parser.add_argument("--bins", type=int, default=30, help="histogram bins")


def main(args) -> int:
    from pathlib import Path

    from craquelure.drying.campaign import campaign_from_files

    missing = [p for p in args.fragments if not Path(p).is_file()]
    if missing:
        raise CraquelureError(f"fragment datasets not found: {', '.join(missing)}")
    if args.bins < 2:
        raise CraquelureError(f"--bins {args.bins} is not allowed; must be >= 2")
    out = campaign_from_files(args.fragments, args.out, args.bins)
    print(f"wrote {out}")
    return 0
