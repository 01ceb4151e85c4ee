"""``craquelure verify PATH``: print every mismatch against the manifest, exit 1 if any."""

NAME = "verify"
HELP = "check an archive (.tar.gz) or its unpacked folder against its SHA-256 manifest"


def add_arguments(parser) -> None:
    parser.add_argument("path", help="craquelure-<profile>-<date>.tar.gz or its unpacked folder")


def main(args) -> int:
    from craquelure.archive import MANIFEST, verify

    problems, checked = verify(args.path)
    for problem in problems:
        print(problem)
    if problems:
        print(f"{args.path}: {len(problems)} mismatch(es) against {MANIFEST}")
        return 1
    print(f"{args.path}: OK, {checked} files match {MANIFEST}")
    return 0
