"""Helpers of the Snakemake file ``workflow/rules/impact.smk`` (kept here so the rule file holds
rules only): the campaign's run paths from the ``impact`` config section, and the `--set`
arguments of one variant from its wildcards."""

from __future__ import annotations

import shlex


def seeds(section: dict) -> list[int]:
    return list(range(section["first_seed"], section["first_seed"] + section["n_seeds"]))


def run_path(scene: str, masses: str, precrack: str, kappa: float, seed: int) -> str:
    return f"results/impact/{scene}/{masses}_{precrack}/kappa{kappa}/seed{seed}.nc"


def campaign_runs(section: dict) -> list[str]:
    """The homogeneous disc (seed 0) for each kappa and pre-crack; the heterogeneous specimens
    (seeds) for each kappa of ``heterogeneous_kappas`` (default: every kappa), and with
    pre-cracks too if ``precrack_heterogeneous``."""
    scene = section["scene"]
    hetero_kappas = section.get("heterogeneous_kappas", section["kappas"])
    runs = []
    for kappa in section["kappas"]:
        for precrack in ["none", *section["precracks"]]:
            runs.append(run_path(scene, "homogeneous", precrack, kappa, 0))
            if kappa in hetero_kappas and (precrack == "none"
                                           or section.get("precrack_heterogeneous", False)):
                runs += [run_path(scene, section["distribution"], precrack, kappa, s)
                         for s in seeds(section)]
    return runs


def three_d(section: dict) -> dict | None:
    """The 3D campaign (config ``impact.three_d`` over the 2D section's keys: its own scene,
    kappas, seeds, layouts, threads, memory and run time), or None when ``dims`` lacks 3."""
    if 3 not in section.get("dims", [2]):
        return None
    return {**section, **section["three_d"]}


def campaign_runs_3d(section: dict) -> list[str]:
    """The 3D campaign's runs (:func:`campaign_runs` of :func:`three_d`); none without 3D."""
    cfg = three_d(section)
    return campaign_runs(cfg) if cfg is not None else []


def three_d_overrides(section: dict):
    """`--set` arguments of the 3D campaign's own scene overrides (``three_d.set``, e.g. a
    shorter ``outputs.t_end`` in a small profile) for runs of its scene; none otherwise."""
    cfg = three_d(section)

    def overrides(wildcards) -> str:
        if cfg is None or wildcards.scene != cfg["scene"]:
            return ""
        return " ".join(f"--set {shlex.quote(item)}" for item in cfg.get("set", []))
    return overrides


def run_resource(section: dict, key: str):
    """Per-run ``threads`` / ``mem_mb`` / ``runtime_run`` of rule impact_run: the 3D campaign's
    value for runs of its scene, the 2D section's otherwise (a function of the wildcards)."""
    cfg = three_d(section)

    def value(wildcards) -> int:
        if cfg is not None and wildcards.scene == cfg["scene"]:
            return cfg[key]
        return section[key]
    return value


def figure_runs(section: dict) -> dict:
    """Runs drawn in the report figures, by role."""
    scene, hetero = section["scene"], section["distribution"]
    shown = seeds(section)[:4]
    kappas = section["kappas"]
    one = 1.0 if 1.0 in kappas else kappas[0]
    return {
        "specimen": run_path(scene, hetero, "none", one, shown[0]),
        "homogeneous": [run_path(scene, "homogeneous", "none", k, 0) for k in kappas],
        "hetero_kappa1": [run_path(scene, hetero, "none", one, s) for s in shown],
        "hetero_low_high": [run_path(scene, hetero, "none", k, s)
                            for k in kappas if k != one for s in shown[:2]]
        or [run_path(scene, hetero, "none", one, shown[0])],
        "precracks": [run_path(scene, "homogeneous", p, one, 0) for p in section["precracks"]]
        or [run_path(scene, "homogeneous", "none", one, 0)],
        "contact": [run_path(scene, m, "none", k, s) for k in kappas
                    for m, s in (("homogeneous", 0), (hetero, shown[0]))],
    }


FIXED_KEYS = {"as_epsilon": "numerics.as_epsilon",
              "crack_band_width": "material.crack_band_width"}


def variant_overrides(section: dict):
    """`--set` arguments of one variant (masses, pre-crack, kappa) from its wildcards, and the
    values ``fixed_across_kappa`` holds fixed across kappa (eps_AS, l_c), if any."""
    fixed = " ".join(f"--set {FIXED_KEYS[k]}={v!r}" for k, v in
                     sorted((section.get("fixed_across_kappa") or {}).items()))

    def overrides(wildcards) -> str:
        return (f"--set particles.masses.distribution={wildcards.masses} "
                f"--set particles.precrack={wildcards.precrack} "
                f"--set numerics.kappa={wildcards.kappa}" + (f" {fixed}" if fixed else ""))
    return overrides


def regime_runs(section: dict) -> list[str]:
    """Runs of the regime map (config ``impact.regime``): f_t x contact_a x speed."""
    reg = section["regime"]
    return [f"results/impact/{section['scene']}/regime/ft{f_t / 1e6:g}_a{a}_v{v:g}.nc"
            for f_t in reg["f_t"] for a in reg["contact_a"] for v in reg["velocities"]]


def regime_overrides(section: dict):
    """`--set` arguments of one regime run from its wildcards (f_t in MPa, a, speed)."""
    def overrides(wildcards) -> str:
        return (f"--set material.f_t={wildcards.ft}e+6 "
                f"--set numerics.contact_a={wildcards.a} "
                f"--set particles.impact_velocity={wildcards.v} "
                f"--set outputs.t_end={section['regime']['t_end']!r} "
                f"--set particles.masses.distribution=homogeneous --set particles.precrack=none")
    return overrides
