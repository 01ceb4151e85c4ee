"""Helpers of the Snakemake file ``workflow/rules/impact.smk`` (kept here so the rule file holds
rules only): the campaign's run paths from the ``impact`` config section, and the `--set`
arguments of one variant from its wildcards."""

from __future__ import annotations


def seeds(section: dict) -> list[int]:
    return list(range(section["first_seed"], section["first_seed"] + section["n_seeds"]))


def run_path(scene: str, masses: str, precrack: str, kappa: float, seed: int) -> str:
    return f"results/impact/{scene}/{masses}_{precrack}/kappa{kappa}/seed{seed}.nc"


def campaign_runs(section: dict) -> list[str]:
    """The homogeneous disc (seed 0) for each kappa and pre-crack; the heterogeneous specimens
    (seeds) for each kappa, and with pre-cracks too if ``precrack_heterogeneous``."""
    scene = section["scene"]
    runs = []
    for kappa in section["kappas"]:
        for precrack in ["none", *section["precracks"]]:
            runs.append(run_path(scene, "homogeneous", precrack, kappa, 0))
            if precrack == "none" or section.get("precrack_heterogeneous", False):
                runs += [run_path(scene, section["distribution"], precrack, kappa, s)
                         for s in seeds(section)]
    return runs


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
