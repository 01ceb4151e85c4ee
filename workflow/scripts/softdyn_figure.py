"""Figure of one Soft Dynamics dataset (t1 series: Fig. 4; phase: Fig. 3; pair: gap history)."""

from craquelure.io import open_dataset
from craquelure.softdyn import figures

sm = snakemake  # noqa: F821
ds = open_dataset(sm.input[0])
draw = {"fig4": figures.fig4, "fig3": figures.fig3, "pair": figures.two_sphere}[sm.params.kind]
draw(ds, sm.output[0], sm.config["profile"], sm.params.scene)
