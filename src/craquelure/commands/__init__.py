"""CLI commands, one module each (see :mod:`craquelure.cli`)."""

import argparse

from craquelure.errors import CraquelureError
from craquelure.scene import overrides_from_file


class _OverridesFile(argparse.Action):
    """``--set-file FILE``: the overrides of a file, in order where it stands among ``--set``."""

    def __call__(self, parser, namespace, path, option_string=None):
        try:
            items = overrides_from_file(path)
        except (OSError, CraquelureError) as exc:
            parser.error(f"--set-file: {exc}")
        setattr(namespace, self.dest, [*(getattr(namespace, self.dest) or []), *items])


def add_scene_arguments(parser) -> None:
    parser.add_argument("scene", help="scene YAML file or built-in name such as drying/default")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY.PATH=VALUE", help="override a scene value (repeatable)")
    parser.add_argument("--set-file", dest="overrides", action=_OverridesFile, metavar="FILE",
                        help="override scene values with the `set` list (KEY.PATH=VALUE strings) "
                             "of a YAML file, in order among the --set arguments (repeatable)")
