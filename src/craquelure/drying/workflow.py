"""DAG helpers of ``workflow/rules/drying.smk`` and ``drying_analysis.smk``: scene paths, seeds,
wildcard labels and the inputs of the thickness sweep and the drying-speed study, bound to the
config's ``drying`` section (no module state).

No physics here: a drying-speed run's drying rate, end and snapshot times come from the job of
rule ``drying_speed_scene`` (:func:`craquelure.drying.speed.speed_run_settings`); the scene
values read while the DAG is built are the scene's own layer thickness H, so that the
thickness sweep reuses the scene's runs at that H, and the onset study scene's L and h, which
turn a point's h/Delta into its particle count."""

from __future__ import annotations

import csv
import json
import re
import shlex
from pathlib import Path

from craquelure.scene import load_scene

SCENE_DIR = "config/scenes/drying"
# Criteria of the sensitivity runs (scene schema material.fracture_stress_measure), as the
# wildcard of results/drying/<scene>_C<measure>/.
CRITERION_MEASURES = ("trace", "max_principal")
CRITERION_PATTERN = "|".join(CRITERION_MEASURES)


def published_seeds(name: str | None, root: str = "results/published") -> set[int]:
    """Seeds whose tables the archived ensemble ``root/name`` holds (none without a name)."""
    path = Path(root) / (name or "") / "tables" / "seeds.csv"
    if not name or not path.is_file():
        return set()
    with open(path, newline="") as fh:
        return {int(float(row["seed"])) for row in csv.DictReader(fh)}


def published_companions(name: str, root: str = "results/published") -> list[str]:
    """The ensembles the archived ensemble ``root/name`` shows beside it (``companions`` of its
    provenance) that are archived (their tables committed), in its order."""
    path = Path(root) / name / "provenance.json"
    named = json.loads(path.read_text()).get("companions", []) if path.is_file() else []
    return [c for c in named if c != name and (Path(root) / c / "tables/common.json").is_file()]


def rebuilt_with_companions(wildcards) -> list[str]:
    """Rebuilt folders (rule drying_published) of ensemble ``wildcards.name`` and companions."""
    names = [wildcards.name, *published_companions(wildcards.name)]
    return [f"results/drying_published/{name}" for name in names]


def fragment_files(folder: str, seeds) -> list[str]:
    """The fragment datasets of ``seeds`` in results/drying/<folder>/."""
    return [f"results/drying/{folder}/fragments/seed{seed}.nc" for seed in seeds]


def label(value: float) -> str:
    """A number as a wildcard value (scene wildcards have no dots): 0.25 -> 0p25."""
    return f"{value:g}".replace(".", "p")


def label_value(text: str) -> float:
    """The number a wildcard label spells: 0p25 -> 0.25."""
    return float(text.replace("p", "."))


class Jobs:
    """Config-bound helpers for the Snakemake rules (input functions take ``wildcards``)."""

    def __init__(self, section: dict) -> None:
        study = section["speed"]
        ends = study["t_end_over_t_star"]
        if isinstance(ends, list) and len(ends) != len(study["pis"]):
            raise ValueError(
                f"config drying.speed.t_end_over_t_star: one number or one value per entry of "
                f"drying.speed.pis ({len(study['pis'])}), got {ends}")
        self.section = section

    @staticmethod
    def scene_path(wildcards) -> str:
        return f"{SCENE_DIR}/{wildcards.scene}.yaml"

    def seeds(self) -> list[int]:
        """The campaign's seeds (``seeds``, else ``first_seed`` on), less those its archived
        ensemble (``published``) holds."""
        first = self.section["first_seed"]
        seeds = self.section.get("seeds") or range(first, first + self.section["n_seeds"])
        done = published_seeds(self.section.get("published"))
        return [s for s in seeds if s not in done]

    def campaign_fragments(self, wildcards) -> list[str]:
        """Fragment datasets of the campaign of ``wildcards.scene``: every seed, or the first
        ``criterion.n_seeds`` for a criterion-sensitivity folder <scene>_C<measure>."""
        seeds = self.seeds()
        if re.fullmatch(rf".+_C(?:{CRITERION_PATTERN})", wildcards.scene):
            seeds = seeds[: self.section["criterion"]["n_seeds"]]
        return fragment_files(wildcards.scene, seeds)

    def publish_benchmarks(self, wildcards) -> dict[str, list[str]]:
        """The benchmark files of the jobs behind the tables of ``wildcards.scene`` (rule
        drying_publish_tables): a criterion folder's initial states are its scene's."""
        base = re.sub(rf"_C(?:{CRITERION_PATTERN})$", "", wildcards.scene)
        return {kind: [f"benchmarks/results/{kind}/{folder}/seed{seed}.tsv"
                       for seed in self.seeds()]
                for kind, folder in (("mass_consistency", base),
                                     ("drying_run", wildcards.scene),
                                     ("drying_fragments", wildcards.scene))}

    def criterion_folders(self) -> list[str]:
        """results/drying/<folder> of the criterion sensitivity runs (none if n_seeds = 0)."""
        study = self.section["criterion"]
        return ([f"{self.section['scene']}_C{m}" for m in study["measures"]]
                if study["n_seeds"] > 0 else [])

    def transition_fragments(self, wildcards=None) -> dict[str, list[str]]:
        """Fragment datasets of the transition study, grouped by scene (inputs <scene>): the runs of
        each scene in ``transition.variant`` (its own, a criterion or a drying speed folder)."""
        study = self.section["transition"]
        if len(study["scenes"]) != len(study["n_seeds"]):
            raise ValueError(
                f"config drying.transition.n_seeds: one count per entry of scenes "
                f"({len(study['scenes'])}), got {study['n_seeds']}")
        first = self.section["first_seed"]
        return {scene: fragment_files(f"{scene}{study['variant']}", range(first, first + n))
                for scene, n in zip(study["scenes"], study["n_seeds"], strict=True) if n > 0}

    @staticmethod
    def criterion_scene(wildcards) -> str:
        """The scene name of a criterion-sensitivity summary: <scene>_C<measure>."""
        return f"{wildcards.scene}_C{wildcards.measure}"

    @staticmethod
    def thickness_value(wildcards) -> str:
        return wildcards.thickness.replace("p", ".")

    def thickness_fragments(self, wildcards) -> dict[str, list[str]]:
        """Fragment datasets of the sweep, grouped by H (inputs H<label>); the scene's own H
        reuses its runs."""
        sweep = self.section["thickness"]
        own = float(load_scene(self.scene_path(wildcards)).get("material.thickness"))
        return {f"H{label(v)}": fragment_files(wildcards.scene if abs(v - own) < 1e-12
                                               else f"{wildcards.scene}_H{label(v)}",
                                               self.seeds()[: sweep["n_seeds"]])
                for v in sweep["values"]}

    @staticmethod
    def speed_value(wildcards) -> float:
        """Pi = tau/t* of a drying-speed run, from its label."""
        return label_value(wildcards.pi)

    def speed_end_over_t_star(self, wildcards) -> float:
        """End of the speed run at Pi in units of t*: one number for every speed, or one per
        entry of ``pis`` (slow drying is expensive per t*, fast drying breaks late in t*)."""
        study = self.section["speed"]
        ends = study["t_end_over_t_star"]
        if not isinstance(ends, list):
            return float(ends)
        by_label = {label(p): float(e) for p, e in zip(study["pis"], ends, strict=True)}
        return by_label[label(self.speed_value(wildcards))]

    def speed_times_over_t_star(self, wildcards) -> list[float]:
        """Snapshot times of the speed run at Pi in units of t*, up to its end: adding later
        snapshots for the fast speeds leaves the slow speeds' runs as they are."""
        end = self.speed_end_over_t_star(wildcards)
        return [float(t) for t in self.section["speed"]["times_over_t_star"]
                if t <= end * (1 + 1e-9)]

    def speed_overrides(self) -> str:
        """`--set` arguments of the study's own overrides (``speed.set``), after the speed's."""
        items = self.section["speed"].get("set", [])
        return " ".join(f"--set {shlex.quote(item)}" for item in items)

    def speed_fragments(self, wildcards) -> dict[str, list[str]]:
        """Fragment datasets of the drying-speed study, grouped by Pi (inputs P<label>)."""
        study = self.section["speed"]
        return {f"P{label(pi)}": fragment_files(f"{wildcards.scene}_Pi{label(pi)}",
                                                self.seeds()[: study["n_seeds"]])
                for pi in study["pis"]}


KAPPA_SCENE = f"{SCENE_DIR}/onset_fixed_f.yaml"
KAPPA_PATTERN = r"gap(?P<gap>[0-9p]+)_hd(?P<hd>[0-9p]+)_(?P<method>truncated_cg|clamped_cg)"


def kappa_label(gap: float, h_over_spacing: float, method: str) -> str:
    return f"gap{label(gap)}_hd{label(h_over_spacing)}_{method}"


class KappaJobs:
    """Points of the onset study (config ``drying.kappa``, rules drying_kappa*): the minimum
    gaps at h/Delta = 4 (clamped CG below 0.8, the truncated CG of the spec at 0.8) and the
    h/Delta values at gap 0.8, each for every seed."""

    def __init__(self, section: dict) -> None:
        self.section = section["kappa"]

    def labels(self) -> list[str]:
        out = [kappa_label(g, 4.0, "truncated_cg" if g >= 0.8 else "clamped_cg")
               for g in self.section["gaps"]]
        out += [kappa_label(0.8, hd, "truncated_cg") for hd in self.section["h_over_spacing"]]
        return list(dict.fromkeys(out))

    def runs(self) -> list[str]:
        return [f"results/drying/kappa/{point}/seed{seed}.nc" for point in self.labels()
                for seed in self.section["seeds"]]

    @staticmethod
    def point_overrides(wildcards) -> str:
        """`--set` arguments of one point: gap, N from h/Delta at the scene's L and h, solve."""
        match = re.fullmatch(KAPPA_PATTERN, wildcards.point)
        if match is None:
            raise ValueError(f"onset study point {wildcards.point!r} does not match "
                             f"{KAPPA_PATTERN}")
        gap, hd, method = match.group("gap"), match.group("hd"), match.group("method")
        scene = load_scene(KAPPA_SCENE)
        length, h = scene.get("domain.box_length"), scene.get("numerics.h")
        n = int(round((label_value(hd) * length / h) ** 2))
        return (f"--set particles.rsa_min_separation={label_value(gap):g} "
                f"--set particles.n={n} --set numerics.mass_solve.method={method}")
