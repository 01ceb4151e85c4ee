"""Snakemake script of rule drying_speed_scene: the settings of a scene's drying-speed runs at
one Pi (:func:`craquelure.drying.speed.speed_run_settings`: drying rate, end, snapshot times)
as YAML, whose ``set`` list the runs apply with ``craquelure run --set-file``.

Outside Snakemake: ``python workflow/scripts/drying_speed_scene.py SCENE.yaml PI END F1,F2,...
OUT.yaml`` (END and the F in units of t*).
"""

import sys

import yaml

from craquelure.drying.speed import speed_run_settings
from craquelure.io import write_text_atomic
from craquelure.scene import load_scene


def main(scene_path: str, pi: float, end_over_t_star: float, times_over_t_star: list[float],
         out: str) -> None:
    scene = load_scene(scene_path)
    settings = speed_run_settings(scene, pi, end_over_t_star, times_over_t_star)
    text = yaml.safe_dump({"scene": scene.name, **settings}, sort_keys=False, width=1000)
    write_text_atomic(out, f"# drying-speed run settings (rule drying_speed_scene): the run "
                           f"applies `set`; the other values at full precision\n{text}")
    print(f"wrote {out}: {' '.join(settings['set'])}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        params = snakemake.params  # noqa: F821
        main(snakemake.input.scene, params.pi, params.end_over_t_star,  # noqa: F821
             list(params.times_over_t_star), snakemake.output[0])  # noqa: F821
elif __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]),
         [float(v) for v in sys.argv[4].split(",")], sys.argv[5])
