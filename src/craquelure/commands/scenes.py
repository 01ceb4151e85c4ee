"""``craquelure scenes``: list the built-in scenes."""

from craquelure.scene import list_scenes

NAME = "scenes"
HELP = "list built-in scenes with a one-line description"


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    rows = list_scenes()
    width = max((len(name) for name, _ in rows), default=0)
    for name, desc in rows:
        print(f"{name:<{width}}  {desc}")
    return 0
