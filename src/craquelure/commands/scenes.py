"""``craquelure scenes``: list the built-in scenes."""

from craquelure.api import scenes

NAME = "scenes"
HELP = "list built-in scenes with a one-line description"


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    rows = scenes()
    width = max(map(len, rows), default=0)
    for name, desc in rows.items():
        print(f"{name:<{width}}  {desc}")
    return 0
