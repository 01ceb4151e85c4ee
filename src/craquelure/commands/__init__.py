"""CLI commands, one module each (see :mod:`craquelure.cli`)."""


def add_scene_arguments(parser) -> None:
    parser.add_argument("scene", help="scene YAML file or built-in name such as drying/default")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY.PATH=VALUE", help="override a scene value (repeatable)")
